// SPDX-License-Identifier: Apache-2.0
// `codrive sdo serve`: event loop + SocketCAN + SdoServer, stopped by SIGINT/SIGTERM.
#include "sdo_serve.hpp"

#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/core/eds.hpp>
#include <codrive/sdo/server.hpp>

#include <csignal>
#include <fmt/format.h>
#include <sys/signalfd.h>
#include <unistd.h>

namespace codrive::cli {

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

    // Signals arrive through a signalfd so the loop stops cleanly between frames.
    sigset_t mask;
    sigemptyset(&mask);
    sigaddset(&mask, SIGINT);
    sigaddset(&mask, SIGTERM);
    if (sigprocmask(SIG_BLOCK, &mask, nullptr) != 0) {
        fmt::print(stderr, "codrive: cannot block signals\n");
        return kExitFailure;
    }
    const int sfd = signalfd(-1, &mask, SFD_NONBLOCK | SFD_CLOEXEC);
    if (sfd < 0) {
        fmt::print(stderr, "codrive: cannot create signalfd\n");
        return kExitFailure;
    }

    SocketCanOptions so;
    so.filters = {CanFilter{cob::sdo_rx(node), 0x7FF, false, false}};
    so.error_frames = false;
    auto s = open_bus(iface, so);
    if (!s) {
        ::close(sfd);
        return kExitNoBus;
    }
    sdo::ServerConfig config;
    config.node = node;
    sdo::SdoServer server(od, *s->bus, config);
    s->bus->set_frame_handler(
        [&server](const Frame& f, TimePoint t) { (void)server.on_frame(f, t); });
    s->loop->add_timed(&server);
    EventLoop& loop = *s->loop;
    (void)loop.add_fd(sfd, 0x001 /* EPOLLIN */, [&loop, sfd](std::uint32_t) {
        signalfd_siginfo info{};
        while (::read(sfd, &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
        }
        loop.stop();
    });
    fmt::print("codrive sdo serve: node {} on {} ready ({} objects)\n", node, iface, od.size());
    std::fflush(stdout);
    const auto r = loop.run();
    loop.remove_fd(sfd);
    loop.remove_timed(&server);
    ::close(sfd);
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
