// SPDX-License-Identifier: Apache-2.0
// A bus file that points an EtherCAT slave at an ESI file (`esi:`), against codrive-ecat-sim on
// veth: the FIO reaches OP as with its profile alone, the ESI's default PDO assignment is used
// when the slave has no axes, and a slave the file does not describe is refused.
#include "veth_segment.hpp"

#include <codrive/controller/controller.hpp>

#include <fmt/format.h>

namespace codrive::testing {
namespace {

class ControllerWithEsi : public EcatVethTest {
protected:
    void SetUp() override {
        start({"--slave", "fio"});
        // The controller opens its own socket; the fixture's master stays out of the way.
        master_.reset();
        link_.reset();
    }
    /// A bus file; `slave` is the text after `- position: 0` (DEVICES: the devices/ folder).
    std::string bus_file(std::string slave) {
        for (auto at = slave.find("DEVICES"); at != std::string::npos; at = slave.find("DEVICES")) {
            slave.replace(at, 7, std::string(CODRIVE_SOURCE_DIR) + "/devices");
        }
        return write_temp_file("esi", fmt::format("ethercat:\n"
                                                  "  interface: {}\n"
                                                  "  cycle_us: 2000\n"
                                                  "  slaves:\n"
                                                  "    - position: 0\n"
                                                  "{}",
                                                  veth_->master_if(), slave));
    }
    /// Starts a controller on `path`; its events, or the start error after "start failed: ".
    std::string run(const std::string& path) {
        auto c = controller::Controller::from_file(path, {});
        if (!c) {
            return "from_file failed: " + c.error().detail;
        }
        std::string events;
        (*c)->set_event_callback([&events](const std::string& t) { events += t + "\n"; });
        auto started = (*c)->start();
        if (!started) {
            return "start failed: " + started.error().detail;
        }
        c->reset(); // shuts the segment down before the next run opens it
        return events;
    }
};

std::string op_line(const std::string& events) {
    const auto at = events.find(": OP, ");
    if (at == std::string::npos) {
        return "(no OP event in: " + events + ")";
    }
    const auto begin = events.rfind('\n', at);
    return events.substr(begin == std::string::npos ? 0 : begin + 1,
                         events.find('\n', at) - (begin == std::string::npos ? 0 : begin + 1));
}

TEST_F(ControllerWithEsi, FioWithTheVendorsEsiReachesOpExactlyAsWithTheProfile) {
    const std::string axes = "      axes:\n        - {axis: 1, mode: csp}\n";
    const std::string with_profile = run(bus_file("      profile: fio\n" + axes));
    const std::string with_esi =
        run(bus_file("      profile: fio\n      esi: DEVICES/fio.xml\n" + axes));
    EXPECT_NE(with_profile.find("OP, 1 axis(es)"), std::string::npos) << with_profile;
    EXPECT_EQ(op_line(with_esi), op_line(with_profile)) << with_esi;
}

TEST_F(ControllerWithEsi, WithoutAxesTheEsisDefaultPdoAssignmentIsWritten) {
    // devices/fio.xml: RxPDO 1600h (6040h, 607Ah, 3202h, 6060h: 88 bits) on SM2 and TxPDO
    // 1A00h (6041h, 6064h, 6061h: 56 bits) on SM3.
    const std::string events =
        run(bus_file("      profile: generic\n      esi: DEVICES/fio.xml\n"));
    EXPECT_NE(events.find("default PDO assignment of"), std::string::npos) << events;
    EXPECT_NE(events.find("(1 RxPDO, 1 TxPDO)"), std::string::npos) << events;
    EXPECT_NE(events.find("OP, 0 axis(es), 11 output / 7 input bytes"), std::string::npos)
        << events;
}

TEST_F(ControllerWithEsi, ASlaveTheEsiDoesNotDescribeIsRefusedNamingItAndTheFile) {
    // The FIO answers with Kuhnke's identity; devices/akd2g.xml describes Kollmorgen's AKD2G.
    const std::string out = run(bus_file("      profile: generic\n      esi: DEVICES/akd2g.xml\n"));
    EXPECT_EQ(out.rfind("start failed: ", 0), 0U) << out;
    EXPECT_NE(out.find("slave 0"), std::string::npos) << out;
    EXPECT_NE(out.find("the slave is vendor 0x0048554B product 0x0002BA67 revision 0x00000000"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("devices/akd2g.xml describes vendor 0x0000006A"), std::string::npos) << out;
}

} // namespace
} // namespace codrive::testing
