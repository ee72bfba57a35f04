// SPDX-License-Identifier: Apache-2.0
// A bus file naming devices/akd2g.eds (the docs/bus-file.md example, as printed) boots the
// simulated AKD2G and moves both axes like a node with the profile's built-in dictionary.
#include <codrive/controller/controller.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace codrive;
using namespace codrive::controller;
using namespace std::chrono_literals;

namespace {

// The `eds:` example of docs/bus-file.md, exactly as printed there.
std::string docs_example() {
    std::ifstream in(std::string(CODRIVE_SOURCE_DIR) + "/docs/bus-file.md");
    std::stringstream doc;
    doc << in.rdbuf();
    const std::string text = doc.str();
    const auto at = text.find("eds: devices/akd2g.eds");
    if (at == std::string::npos) {
        return {};
    }
    const auto begin = text.rfind("```yaml\n", at);
    const auto end = text.find("```", at);
    return text.substr(begin + 8, end - begin - 8);
}

// A directory holding `bus.yml` and a `devices` link to the repository's devices/, so the
// relative `eds:` path of the example resolves as it does in the repository root.
struct BusDir {
    std::filesystem::path dir;
    explicit BusDir(const std::string& yaml) {
        dir = std::filesystem::temp_directory_path() /
              ("codrive-devices-" + std::to_string(::getpid()));
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
        std::filesystem::create_directory_symlink(std::string(CODRIVE_SOURCE_DIR) + "/devices",
                                                  dir / "devices");
        std::ofstream(dir / "bus.yml") << yaml;
    }
    ~BusDir() { std::filesystem::remove_all(dir); }
    [[nodiscard]] std::string bus_file() const { return (dir / "bus.yml").string(); }
};

} // namespace

TEST(DeviceFilesBusFile, NodeNamingTheAkd2gEdsBootsAndRunsLikeTheProfile) {
    const std::string yaml = docs_example();
    ASSERT_FALSE(yaml.empty()) << "docs/bus-file.md lost its `eds: devices/akd2g.eds` example";
    BusDir files(yaml);
    EXPECT_TRUE(check_bus_file(files.bus_file()).empty());

    VirtualNetwork net{RealClock::instance()};
    VirtualBus& ctl_bus = net.endpoint("controller");
    VirtualBus& sim_bus = net.endpoint("akd2g");
    sim::SimDeviceConfig sc;
    sc.node = 1;
    sc.profile = sim::find_profile("akd2g");
    sc.axes = 2;
    ASSERT_NE(sc.profile, nullptr);
    sim::SimDevice drive(sim_bus, sc);
    sim_bus.set_frame_handler([&drive](const Frame& f, TimePoint t) { drive.on_frame(f, t); });

    ControllerOptions o;
    o.buses = {&ctl_bus};
    auto created = Controller::from_file(files.bus_file(), o);
    ASSERT_TRUE(created) << created.error().detail;
    std::unique_ptr<Controller> ctl = std::move(*created);
    std::string events;
    ctl->set_event_callback([&events](const std::string& t) { events += t + "\n"; });
    ctl->loop().add_timed(&net);
    ctl->loop().add_timed(&drive);
    drive.start(SteadyClock::now());
    ctl->run_for(20ms);
    auto started = ctl->start();
    ASSERT_TRUE(started) << started.error().detail << "\n" << events;
    ASSERT_EQ(ctl->boot_reports().size(), 1U);
    EXPECT_TRUE(ctl->boot_reports()[0].ok) << ctl->boot_reports()[0].to_string();
    // The write whose type came from the EDS reached the drive (6083h UNSIGNED32).
    EXPECT_EQ(drive.od().get<std::uint32_t>(0x6083, 0), 5000U);

    auto* a1 = ctl->axis(1, 1);
    auto* a2 = ctl->axis(1, 2);
    ASSERT_TRUE(a1 && a2);
    ASSERT_TRUE(ctl->run_until([&] { return a1->has_statusword() && a2->has_statusword(); }, 2s))
        << events;
    int enabled = 0;
    for (auto* a : {a1, a2}) {
        a->enable([&enabled](drives::DriveVoid r) { enabled += r ? 1 : 0; });
    }
    ASSERT_TRUE(ctl->run_until([&] { return enabled == 2; }, 3s)) << events;
    const std::int32_t start1 = a1->position_actual().value_or(0);
    const std::int32_t start2 = a2->position_actual().value_or(0);
    std::int32_t step = 0;
    ctl->set_cycle_callback([&](const CycleInfo&) {
        step = std::min(step + 1, 100);
        a1->set_target_position(start1 + step * 100);
        a2->set_target_position(start2 - step * 100);
    });
    ctl->run_until([&] { return step >= 100; }, 5s);
    ctl->run_for(100ms);
    ctl->set_cycle_callback(nullptr);
    EXPECT_NEAR(a1->position_actual().value_or(0), start1 + 10000, 500) << events;
    EXPECT_NEAR(a2->position_actual().value_or(0), start2 - 10000, 500) << events;
    ctl->shutdown();
    ctl->loop().remove_timed(&net);
    ctl->loop().remove_timed(&drive);
}

TEST(DeviceFilesBusFile, MissingEdsIsRefusedNamingTheFile) {
    std::string yaml = docs_example();
    ASSERT_FALSE(yaml.empty());
    yaml.replace(yaml.find("devices/akd2g.eds"), 17, "devices/akd3g.eds");
    BusDir files(yaml);
    const auto findings = check_bus_file(files.bus_file());
    ASSERT_FALSE(findings.empty());
    std::string all;
    for (const auto& f : findings) {
        all += f + "\n";
    }
    const std::string want = files.bus_file() + ":3: node 1: cannot read EDS " +
                             (files.dir / "devices/akd3g.eds").string() +
                             ": No such file or directory";
    EXPECT_NE(all.find(want), std::string::npos) << all;
    EXPECT_FALSE(Controller::from_file(files.bus_file(), {}));
}
