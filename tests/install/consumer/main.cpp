// SPDX-License-Identifier: Apache-2.0
// Downstream smoke test: uses core types and the virtual bus from an installed codrive.
#include <codrive/core/cob_id.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/core/virtual_bus.hpp>

#include <cstdio>

int main() {
    codrive::FakeClock clock;
    codrive::VirtualNetwork net(clock);
    auto& a = net.endpoint("a");
    auto& b = net.endpoint("b");
    int got = 0;
    b.set_frame_handler([&](const codrive::Frame& f, codrive::TimePoint) {
        got += codrive::classify_cob_id(f.id).type == codrive::CobType::Tpdo1 ? 1 : 0;
    });
    if (!a.send(codrive::Frame::make(codrive::cob::tpdo(1, 5), {1, 2}))) {
        return 1;
    }
    net.deliver();
    std::printf("consumer: received %d TPDO1 frame(s); abort 0x06020000 = %s\n", got,
                std::string(codrive::sdo_abort_describe(0x06020000)).c_str());
    return got == 1 ? 0 : 1;
}
