// SPDX-License-Identifier: Apache-2.0
// `codrive bus`: interface info, raw frame send, and a flow-controlled stream/sink pair that
// proves frames cross the bus between processes with none lost and order kept.
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/core/can_interface.hpp>
#include <codrive/core/endian.hpp>
#include <codrive/core/value.hpp>

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <csignal>

namespace codrive::cli {
namespace {

struct StreamOptions {
    std::string iface;
    std::uint64_t count = 100000;
    std::string id_text = "0x123";
    unsigned window = 2048;
    bool no_flow_control = false;
    int idle_timeout_ms = 5000;
    int rcvbuf = 8 * 1024 * 1024;
};

std::optional<std::uint32_t> parse_id(const std::string& text) {
    auto v = parse_uint(text);
    if (!v || *v > 0x7FE) {
        fmt::print(stderr, "codrive: stream id must be an 11-bit id below 0x7FF, not '{}'\n", text);
        return std::nullopt;
    }
    return static_cast<std::uint32_t>(*v);
}

double per_second(std::uint64_t n, std::chrono::steady_clock::duration d) {
    const double s = std::chrono::duration<double>(d).count();
    return s > 0 ? static_cast<double>(n) / s : 0.0;
}

int run_stream(const StreamOptions& o) {
    const auto id = parse_id(o.id_text);
    if (!id) {
        return kExitUsage;
    }
    SocketCanOptions so;
    so.filters = {CanFilter{*id + 1, 0x7FF}};
    so.tx_queue_capacity = 65536;
    auto s = open_bus(o.iface, so);
    if (!s) {
        return kExitNoBus;
    }
    std::uint64_t acked = 0;
    s->bus->set_frame_handler([&](const Frame& f, TimePoint) {
        if (f.len >= 4) {
            acked = std::max<std::uint64_t>(acked, get_le<std::uint32_t>(f.data.data()));
        }
    });
    const auto start = std::chrono::steady_clock::now();
    std::uint64_t sent = 0;
    auto last_progress = start;
    // Frames go out in batches (one sendmmsg() per batch) and the clock is read once per batch:
    // a system call per frame would measure the kernel's entry cost, not the bus (in a UML guest
    // every call, clock reads included, traps to the host).
    std::array<Frame, 64> batch{};
    while (sent < o.count) {
        bool stop_sending = false;
        while (!stop_sending && sent < o.count && (o.no_flow_control || sent - acked < o.window)) {
            std::uint64_t room = std::min<std::uint64_t>(batch.size(), o.count - sent);
            if (!o.no_flow_control) {
                room = std::min<std::uint64_t>(room, o.window - (sent - acked));
            }
            for (std::size_t k = 0; k < room; ++k) {
                Frame& f = batch[k];
                f.id = *id;
                f.len = 8;
                const auto seq = static_cast<std::uint32_t>(sent + k);
                put_le<std::uint32_t>(f.data.data(), seq);
                put_le<std::uint32_t>(f.data.data() + 4, ~seq);
            }
            const std::size_t n = s->bus->send_many(std::span<const Frame>(batch.data(), room));
            sent += n;
            if (n > 0) {
                last_progress = std::chrono::steady_clock::now();
            }
            if (n < room) {
                // The kernel and the retry queue are full (let the loop drain them), or the
                // frame was refused: send() says why.
                if (auto r = s->bus->send(batch[n]); r) {
                    ++sent;
                } else if (r.error() == CoreErrc::TxQueueFull) {
                    stop_sending = true;
                } else {
                    fmt::print(stderr, "codrive: stream: send failed on {}: {}\n", o.iface,
                               r.error().message());
                    return kExitFailure;
                }
            }
        }
        (void)s->loop->poll_once(std::chrono::milliseconds(1));
        if (std::chrono::steady_clock::now() - last_progress >
            std::chrono::milliseconds(o.idle_timeout_ms)) {
            fmt::print(stderr,
                       "codrive: stream: no acknowledgement from the sink for {} ms after {} "
                       "frames (acked {}): is `codrive bus sink` running on {}?\n",
                       o.idle_timeout_ms, sent, acked, o.iface);
            return kExitFailure;
        }
    }
    if (!s->bus->drain(std::chrono::seconds(10))) {
        fmt::print(stderr, "codrive: stream: {} frames still queued after 10 s\n",
                   s->bus->tx_pending());
        return kExitFailure;
    }
    const auto elapsed = std::chrono::steady_clock::now() - start;
    const auto& st = s->bus->stats();
    fmt::print("stream: sent {} frames, {} waited in the retry queue, {:.0f} frames/s\n", sent,
               st.tx_queued, per_second(sent, elapsed));
    return kExitOk;
}

int run_sink(const StreamOptions& o) {
    const auto id = parse_id(o.id_text);
    if (!id) {
        return kExitUsage;
    }
    SocketCanOptions so;
    so.filters = {CanFilter{*id, 0x7FF}};
    so.rcvbuf_bytes = o.rcvbuf;
    auto s = open_bus(o.iface, so);
    if (!s) {
        return kExitNoBus;
    }
    std::uint64_t received = 0;
    std::uint64_t lost = 0;
    std::uint64_t out_of_order = 0;
    std::uint64_t corrupt = 0;
    std::uint32_t expected = 0;
    const unsigned ack_every = std::max(1U, o.window / 4);
    auto send_ack = [&] {
        Frame ack;
        ack.id = *id + 1;
        ack.len = 4;
        put_le<std::uint32_t>(ack.data.data(), static_cast<std::uint32_t>(received));
        (void)s->bus->send(ack);
    };
    // Times come from the frames' receive stamps (the kernel's, or the loop's clock read for the
    // batch): no clock read per frame.
    std::optional<TimePoint> first;
    TimePoint last_rx = SteadyClock::now();
    s->bus->set_frame_handler([&](const Frame& f, TimePoint t) {
        if (!first) {
            first = t;
        }
        last_rx = t;
        ++received;
        const auto seq = get_le<std::uint32_t>(f.data.data());
        if (f.len != 8 || get_le<std::uint32_t>(f.data.data() + 4) != ~seq) {
            ++corrupt;
        } else if (seq > expected) {
            lost += seq - expected;
            expected = seq + 1;
        } else if (seq < expected) {
            ++out_of_order;
        } else {
            expected = seq + 1;
        }
        if (received % ack_every == 0) {
            send_ack();
        }
    });
    fmt::print("sink: ready on {}\n", o.iface);
    std::fflush(stdout);
    // Before the first frame the sink waits 30 s for the sender to start; after it, the idle
    // timeout ends a stream whose tail was lost.
    const TimePoint started = SteadyClock::now();
    while (received < o.count && expected < o.count) {
        (void)s->loop->poll_once(std::chrono::milliseconds(50));
        const TimePoint now = SteadyClock::now();
        if (received == 0 ? now - started > std::chrono::seconds(30)
                          : now - last_rx > std::chrono::milliseconds(o.idle_timeout_ms)) {
            break;
        }
    }
    send_ack();
    const Duration elapsed = first ? SteadyClock::now() - *first : Duration{};
    const std::uint64_t missing = o.count > expected ? o.count - expected : 0;
    lost += missing;
    fmt::print("sink: received {} frames, lost {}, out of order {}, corrupt {}, kernel drops {}, "
               "{:.0f} frames/s\n",
               received, lost, out_of_order, corrupt, s->bus->stats().rx_dropped,
               per_second(received, elapsed));
    const bool ok = lost == 0 && out_of_order == 0 && corrupt == 0 && received == o.count;
    if (!ok) {
        fmt::print(stderr, "codrive: sink: expected {} frames in order on {}, got {} ({} lost)\n",
                   o.count, o.iface, received, lost);
    }
    return ok ? kExitOk : kExitFailure;
}

int run_send(const std::string& iface, const std::vector<std::string>& frames) {
    std::vector<Frame> parsed;
    for (const auto& text : frames) {
        Frame f;
        if (!parse_frame(text, f)) {
            fmt::print(stderr,
                       "codrive: '{}' is not a frame (expected e.g. 123#11223344, 123#R, "
                       "12345678#00)\n",
                       text);
            return kExitUsage;
        }
        parsed.push_back(f);
    }
    SocketCanOptions so;
    so.error_frames = false;
    auto s = open_bus(iface, so);
    if (!s) {
        return kExitNoBus;
    }
    for (const auto& f : parsed) {
        if (auto r = s->bus->send(f); !r) {
            fmt::print(stderr, "codrive: cannot send {} on {}: {}\n", to_string(f), iface,
                       r.error().message());
            return kExitFailure;
        }
    }
    return s->bus->drain(std::chrono::seconds(2)) ? kExitOk : kExitFailure;
}

int run_info(const std::string& iface) {
    CanInterface ci(iface);
    auto info = ci.info();
    if (!info) {
        fmt::print(stderr, "codrive: {}\n",
                   describe_interface_error(iface, "read state", info.error()));
        return kExitNoBus;
    }
    fmt::print("{}: {}", info->name, info->up ? "up" : "down");
    fmt::print(", bitrate {}", info->bitrate ? fmt::format("{} bit/s", *info->bitrate)
                                             : std::string("n/a (virtual)"));
    if (info->state) {
        fmt::print(", state {}", to_string(*info->state));
    }
    if (info->tx_errors) {
        fmt::print(", tx errors {}, rx errors {}", *info->tx_errors, info->rx_errors.value_or(0));
    }
    fmt::print("\n");
    return kExitOk;
}

void install_bus(CLI::App& app, int& exit_code) {
    auto* bus = app.add_subcommand("bus", "Raw CAN interface tools (info, send, stream/sink test)");
    bus->require_subcommand(1);

    auto opts = std::make_shared<StreamOptions>();
    auto frames = std::make_shared<std::vector<std::string>>();

    auto* info = bus->add_subcommand("info", "Show interface state, bitrate and error counters");
    info->add_option("-i,--iface", opts->iface, "CAN interface")->required();
    info->callback([opts, &exit_code] { exit_code = run_info(opts->iface); });

    auto* send = bus->add_subcommand("send", "Send frames given as candump text (123#11223344)");
    send->add_option("-i,--iface", opts->iface, "CAN interface")->required();
    send->add_option("frames", *frames, "Frames to send")->required();
    send->callback([opts, frames, &exit_code] { exit_code = run_send(opts->iface, *frames); });

    for (const bool is_sink : {false, true}) {
        auto* cmd = bus->add_subcommand(
            is_sink ? "sink" : "stream",
            is_sink ? "Receive a numbered stream and check none is lost or reordered"
                    : "Send a numbered stream of frames (flow-controlled by the sink's acks)");
        cmd->add_option("-i,--iface", opts->iface, "CAN interface")->required();
        cmd->add_option("-c,--count", opts->count, "Frames in the stream")->capture_default_str();
        cmd->add_option("--id", opts->id_text, "Data COB-ID (acks use id+1)")
            ->capture_default_str();
        cmd->add_option("--window", opts->window, "Frames in flight before waiting for an ack")
            ->capture_default_str();
        cmd->add_option("--idle-timeout", opts->idle_timeout_ms, "Give up after this many ms idle")
            ->capture_default_str();
        if (is_sink) {
            cmd->add_option("--rcvbuf", opts->rcvbuf, "Socket receive buffer bytes")
                ->capture_default_str();
            cmd->callback([opts, &exit_code] { exit_code = run_sink(*opts); });
        } else {
            cmd->add_flag("--no-flow-control", opts->no_flow_control,
                          "Send as fast as the kernel takes frames (tests the retry queue)");
            cmd->callback([opts, &exit_code] { exit_code = run_stream(*opts); });
        }
    }
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_bus;
CODRIVE_REGISTER_COMMAND(install_bus);
