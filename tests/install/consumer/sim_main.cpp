// SPDX-License-Identifier: Apache-2.0
// Downstream smoke test of codrive::sim: a simulated AKD2G boots on a virtual bus and a listener
// sees its boot-up message (CiA 301 7.2.8.3.2.1: COB-ID 700h + node, one data byte 00h).
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>

#include <cstdio>

int main() {
    codrive::FakeClock clock;
    codrive::VirtualNetwork net(clock);
    auto& listener = net.endpoint("listener");
    int boot_ups = 0;
    listener.set_frame_handler([&](const codrive::Frame& f, codrive::TimePoint) {
        boot_ups += f.id == 0x703 && f.len == 1 && f.data[0] == 0 ? 1 : 0;
    });
    const codrive::sim::SimProfile* profile = codrive::sim::find_profile("akd2g");
    if (profile == nullptr) {
        std::puts("sim consumer: no akd2g profile");
        return 1;
    }
    codrive::sim::SimDevice dev(net.endpoint("node3"), {.node = 3, .profile = profile});
    dev.start(clock.now());
    net.deliver();
    std::printf("sim consumer: %d boot-up message(s) from the simulated AKD2G (node 3)\n",
                boot_ups);
    return boot_ups == 1 ? 0 : 1;
}
