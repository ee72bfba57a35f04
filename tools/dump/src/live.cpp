// SPDX-License-Identifier: Apache-2.0
// Live capture from SocketCAN interfaces.
#include <codrive/dump/live.hpp>

#include <codrive/core/event_loop.hpp>
#include <codrive/core/value.hpp>

#include <fmt/format.h>

#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>

namespace codrive::dump {

Result<LiveSpec> parse_live_spec(std::string_view text, std::string& error) {
    LiveSpec spec;
    const auto comma = text.find(',');
    spec.iface = std::string(text.substr(0, comma));
    if (spec.iface.empty()) {
        error = fmt::format("'{}': missing interface name", text);
        return fail(CoreErrc::InvalidArgument);
    }
    std::string_view rest = comma == std::string_view::npos ? "" : text.substr(comma + 1);
    while (!rest.empty()) {
        const auto c = rest.find(',');
        const auto item = rest.substr(0, c);
        rest = c == std::string_view::npos ? std::string_view{} : rest.substr(c + 1);
        const auto sep = item.find_first_of(":~");
        if (sep == std::string_view::npos) {
            error = fmt::format("'{}': a filter is ID:MASK or ID~MASK in hex", item);
            return fail(CoreErrc::InvalidArgument);
        }
        // candump writes hex without a prefix; accept "0x" too.
        const auto strip = [](std::string_view h) {
            return h.size() > 2 && h[0] == '0' && (h[1] == 'x' || h[1] == 'X') ? h.substr(2) : h;
        };
        const auto id_text = strip(item.substr(0, sep));
        const auto mask_text = strip(item.substr(sep + 1));
        const auto id = parse_uint("0x" + std::string(id_text));
        const auto mask = parse_uint("0x" + std::string(mask_text));
        if (!id || !mask || *id > Frame::kExtMask || *mask > Frame::kExtMask) {
            error = fmt::format("'{}': a filter is ID:MASK or ID~MASK in hex", item);
            return fail(CoreErrc::InvalidArgument);
        }
        CanFilter f;
        f.id = static_cast<std::uint32_t>(*id);
        f.mask = static_cast<std::uint32_t>(*mask);
        f.extended = id_text.size() > 3 || *id > Frame::kStdMask;
        f.invert = item[sep] == '~';
        spec.filters.push_back(f);
    }
    return spec;
}

std::vector<std::string> list_can_interfaces() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator("/sys/class/net", ec)) {
        std::ifstream type(e.path() / "type");
        int t = 0;
        if (type >> t && t == 280) { // ARPHRD_CAN
            names.push_back(e.path().filename().string());
        }
    }
    std::sort(names.begin(), names.end());
    return names;
}

VoidResult run_live(const std::vector<LiveSpec>& specs, Dumper& dumper, const LiveOptions& o,
                    std::string& error) {
    auto loop = EventLoop::create();
    if (!loop) {
        error = "cannot create the event loop: " + loop.error().message();
        return fail(loop.error());
    }
    // Monotonic kernel timestamps → wall clock.
    const auto offset = std::chrono::system_clock::now().time_since_epoch() -
                        std::chrono::duration_cast<std::chrono::system_clock::duration>(
                            SteadyClock::now().time_since_epoch());
    const auto offset_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(offset).count();
    std::deque<std::string> names;
    std::vector<std::unique_ptr<SocketCanBus>> buses;
    std::uint64_t frames = 0;
    bool done = false;
    for (const auto& s : specs) {
        SocketCanOptions so;
        so.filters = s.filters;
        so.error_frames = true;
        so.timestamps = true;
        so.rcvbuf_bytes = 4 * 1024 * 1024;
        auto bus = SocketCanBus::open(s.iface, so);
        if (!bus) {
            error = describe_can_open_error(s.iface, bus.error());
            return fail(bus.error());
        }
        names.push_back(s.iface);
        const std::string_view name = names.back();
        (*bus)->set_frame_handler([&, name](const Frame& f, TimePoint rx) {
            if (done) {
                return;
            }
            TraceRecord r;
            r.frame = f;
            r.iface = name;
            r.has_ts = true;
            r.ts_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(rx.time_since_epoch())
                          .count() +
                      offset_ns;
            dumper.on_record(r);
            if (o.count != 0 && ++frames >= o.count) {
                done = true;
            }
        });
        if (auto a = (*bus)->attach(**loop); !a) {
            error = fmt::format("{}: cannot watch the socket: {}", s.iface, a.error().message());
            return fail(a.error());
        }
        buses.push_back(std::move(*bus));
    }
    if (o.ready) {
        o.ready();
    }
    auto next_draw = SteadyClock::now() + o.refresh;
    while (!done && (o.stop == nullptr || !o.stop->load())) {
        (void)(*loop)->poll_once(std::chrono::milliseconds(100));
        dumper.flush();
        if (o.top && SteadyClock::now() >= next_draw) {
            next_draw += o.refresh;
            if (o.screen) {
                // Rates of the last second, on the receive timestamps' clock.
                const std::int64_t now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                SteadyClock::now().time_since_epoch())
                                                .count() +
                                            offset_ns;
                o.screen((o.clear_screen ? std::string("\033[H\033[2J") : std::string("\n")) +
                         dumper.stats().table(now_ns));
            }
        }
    }
    return {};
}

} // namespace codrive::dump
