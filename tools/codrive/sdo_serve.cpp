// SPDX-License-Identifier: Apache-2.0
// `codrive sdo serve`: event loop + SocketCAN + SdoServer, stopped by SIGINT/SIGTERM.
#include "sdo_serve.hpp"

#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/core/eds.hpp>
#include <codrive/sdo/server.hpp>

#include <atomic>
#include <csignal>
#include <fmt/format.h>

namespace codrive::cli {
namespace {

std::atomic<EventLoop*> g_serve_loop{nullptr};
static_assert(std::atomic<EventLoop*>::is_always_lock_free, "used from a signal handler");

} // namespace

ObjectDictionary make_sdo_serve_dictionary(NodeId node) {
    ObjectDictionary od;
    od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
               Value(DataType::Unsigned32, {0x92, 0x01, 0x02, 0x00}));
    od.add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
               Value::from_string("codrive sdo serve"));
    const auto u32 = [](std::uint32_t v) {
        Value value = Value::zero(DataType::Unsigned32);
        put_le<std::uint32_t>(value.mutable_bytes().data(), v);
        return value;
    };
    SubObject sub;
    sub.subindex = 0;
    sub.name = "Highest sub-index supported";
    sub.type = DataType::Unsigned8;
    sub.access = Access::Const;
    sub.value = Value(DataType::Unsigned8, {4});
    od.add_sub(0x1018, sub, "Identity object");
    const std::array<std::pair<const char*, std::uint32_t>, 4> identity{{
        {"Vendor-ID", 0x00000000},
        {"Product code", 0x00C0D21E},
        {"Revision number", 0x00010000},
        {"Serial number", node},
    }};
    for (std::uint8_t i = 0; i < identity.size(); ++i) {
        sub.subindex = static_cast<std::uint8_t>(i + 1);
        sub.name = identity[i].first;
        sub.type = DataType::Unsigned32;
        sub.access = Access::Ro;
        sub.value = u32(identity[i].second);
        od.add_sub(0x1018, sub);
    }
    od.add_var(0x2000, "Writable UNSIGNED32", DataType::Unsigned32, Access::Rw, u32(0));
    od.add_var(0x2001, "Writable DOMAIN", DataType::Domain, Access::Rw,
               Value(DataType::Domain, {}));
    return od;
}

int run_sdo_serve(const std::string& iface, NodeId node, const std::string& eds_path) {
    ObjectDictionary od;
    if (eds_path.empty()) {
        od = make_sdo_serve_dictionary(node);
    } else {
        auto desc = load_eds(eds_path, node);
        if (!desc) {
            fmt::print(stderr, "codrive: cannot read {}: {}\n", eds_path, desc.error().message());
            return kExitUsage;
        }
        for (const auto& f : desc->findings) {
            if (f.severity == EdsSeverity::Error) {
                fmt::print(stderr, "{}\n", format_finding(f));
            }
        }
        od = std::move(desc->od);
    }

    SocketCanOptions so;
    so.filters = {CanFilter{cob::sdo_rx(node), 0x7FF, false, false}};
    so.error_frames = false;
    auto s = open_bus(iface, so);
    if (!s) {
        return kExitNoBus;
    }
    sdo::ServerConfig config;
    config.node = node;
    sdo::SdoServer server(od, *s->bus, config);
    s->bus->set_frame_handler(
        [&server](const Frame& f, TimePoint t) { (void)server.on_frame(f, t); });
    s->loop->add_timed(&server);
    EventLoop& loop = *s->loop;
    // SIGINT/SIGTERM stop the loop from a plain handler (EventLoop::stop() is an atomic store and
    // an eventfd write, both async-signal-safe). A signalfd would be a second watched descriptor
    // and keep the loop off its one-socket direct-read path (docs/sdo.md, "Speed"); without
    // SA_RESTART the signal also ends a blocking read at once.
    g_serve_loop = &loop;
    struct sigaction sa {};
    sa.sa_handler = [](int) {
        if (EventLoop* l = g_serve_loop.load()) {
            l->stop();
        }
    };
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    fmt::print("codrive sdo serve: node {} on {} ready ({} objects)\n", node, iface, od.size());
    std::fflush(stdout);
    const auto r = loop.run();
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    g_serve_loop = nullptr;
    loop.remove_timed(&server);
    const auto& st = server.stats();
    fmt::print("codrive sdo serve: stopped after {} requests, {} transfers, {} aborts sent\n",
               st.requests, st.completed, st.aborts_sent);
    if (!r) {
        fmt::print(stderr, "codrive: event loop failed: {}\n", r.error().message());
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace codrive::cli
