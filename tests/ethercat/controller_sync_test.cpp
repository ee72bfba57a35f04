// SPDX-License-Identifier: Apache-2.0
// The Controller synchronises every slave of its bus file's EtherCAT segment the way `codrive
// drive --ethercat` does: 1C32h/1C33h read back from codrive-ecat-sim on veth, DC SYNC0 from
// `dc: true`, and a cycle below the slave's minimum (1C32h:05) refused before OP.
#include "veth_segment.hpp"

#include <codrive/controller/controller.hpp>

#include <fmt/format.h>

namespace codrive::testing {
namespace {

using namespace std::chrono_literals;

class ControllerSync : public EcatVethTest {
protected:
    /// Writes the bus file: `segment_keys` go under `ethercat:`, `slaves` is the list body.
    void write_bus_file(const std::string& segment_keys, const std::string& slaves) {
        path_ = write_temp_file("sync", fmt::format("ethercat:\n"
                                                    "  interface: {}\n"
                                                    "{}"
                                                    "  slaves:\n"
                                                    "{}",
                                                    veth_->master_if(), segment_keys, slaves));
    }
    /// The controller from the bus file, started (bring-up to OP); events go to `events_`.
    tl::expected<void, controller::ControllerError> start_controller() {
        auto c = controller::Controller::from_file(path_, {});
        if (!c) {
            return tl::unexpected(c.error());
        }
        controller_ = std::move(*c);
        controller_->set_event_callback([this](const std::string& t) { events_ += t + "\n"; });
        return controller_->start();
    }
    /// After the controller stepped the slaves back to PRE-OP: the slave's object, read with a
    /// master of our own.
    template <typename T>
    std::optional<T> read_back(std::size_t slave, std::uint16_t index, std::uint8_t sub) {
        if (!link_) {
            auto l = ethercat::RawSocketLink::open(veth_->master_if());
            if (!l) {
                return std::nullopt;
            }
            link_ = std::move(*l);
            ethercat::MasterConfig cfg;
            cfg.frame_timeout = 50ms;
            master_ = std::make_unique<ethercat::Master>(*link_, RealClock::instance(), cfg);
            if (!master_->scan() || !master_->set_state_all(ethercat::AlState::PreOp)) {
                return std::nullopt;
            }
        }
        auto v = master_->sdo_read<T>(slave, index, sub);
        return v ? std::optional<T>(*v) : std::nullopt;
    }
    /// The fixture's master: stale sync values on the slave first, so the read-back proves
    /// the controller's writes; then out of the controller's way.
    void preset_stale_sync_values() {
        ASSERT_TRUE(master_->scan()) << master_->last_error();
        ASSERT_TRUE(master_->set_state_all(ethercat::AlState::PreOp)) << master_->last_error();
        ASSERT_TRUE(master_->sdo_write<std::uint16_t>(0, 0x1C32, 1, 1));
        ASSERT_TRUE(master_->sdo_write<std::uint16_t>(0, 0x1C33, 1, 1));
        ASSERT_TRUE(master_->sdo_write<std::uint32_t>(0, 0x1C32, 2, 123'000));
        master_.reset();
        link_.reset();
    }
    [[nodiscard]] bool has(const std::string& text) const {
        return events_.find(text) != std::string::npos;
    }

    std::string path_;
    std::string events_;
    std::unique_ptr<controller::Controller> controller_;
};

// FIO manual §7.13.22/§7.13.23: the master sets sync type and cycle time; without `dc` the
// controller asks for free run (ETG.1020 §21.1.3.1: 0) at its cycle.
TEST_F(ControllerSync, FreeRunAndTheCycleAreWrittenToTheFioBeforeOp) {
    start({"--slave", "fio"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    preset_stale_sync_values();
    if (HasFatalFailure()) {
        return;
    }
    write_bus_file(
        "  cycle_us: 2000\n",
        "    - {position: 0, name: table, profile: fio, axes: [{axis: 1, mode: csp}]}\n");
    auto started = start_controller();
    ASSERT_TRUE(started) << started.error().detail << events_;
    controller_->run_for(200ms);
    EXPECT_TRUE(has("slave 0 (FIO Drive Control): sync mode 0 (free run), cycle 2000 µs\n"))
        << events_;
    // The FIO's 1C32h lists no minimum cycle time (sub 5 undocumented): said, not fatal.
    EXPECT_TRUE(has("slave 0 (FIO Drive Control) \"table\": has no 0x1C32:05 (it states no "
                    "minimum cycle time)"))
        << events_;
    EXPECT_TRUE(has("slave 0 (FIO Drive Control): OP")) << events_;
    controller_->shutdown();
    controller_.reset();
    EXPECT_EQ(read_back<std::uint16_t>(0, 0x1C32, 1), std::uint16_t{0});
    EXPECT_EQ(read_back<std::uint16_t>(0, 0x1C33, 1), std::uint16_t{0});
    EXPECT_EQ(read_back<std::uint32_t>(0, 0x1C32, 2), 2'000'000U);
}

// `dc: true` in the bus file: the master's DC set-up, SYNC0 at the cycle with the shift, and
// sync mode 2 (DC SYNC0) on the slave.
TEST_F(ControllerSync, DcFromTheBusFileRunsTheFioOnSync0) {
    start({"--slave", "fio"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    preset_stale_sync_values();
    if (HasFatalFailure()) {
        return;
    }
    write_bus_file(
        "  cycle_us: 1000\n  dc: true\n  sync0_shift_us: 100\n",
        "    - {position: 0, name: table, profile: fio, axes: [{axis: 1, mode: csp}]}\n");
    auto started = start_controller();
    ASSERT_TRUE(started) << started.error().detail << events_;
    controller_->run_for(200ms);
    EXPECT_TRUE(has("slave 0 (FIO Drive Control): sync mode 2 (DC SYNC0), cycle 1000 µs, SYNC0 "
                    "shift 100 µs"))
        << events_;
    EXPECT_TRUE(has("slave 0 (FIO Drive Control): OP")) << events_;
    EXPECT_FALSE(has("cyclic exchange failed")) << events_;
    controller_->shutdown();
    controller_.reset();
    EXPECT_EQ(read_back<std::uint16_t>(0, 0x1C32, 1), std::uint16_t{2});
    EXPECT_EQ(read_back<std::uint16_t>(0, 0x1C33, 1), std::uint16_t{2});
    EXPECT_EQ(read_back<std::uint32_t>(0, 0x1C32, 2), 1'000'000U);
}

// `sync: sm` in the bus file: sync mode 1 (synchronous with the SM2 event, ETG.1020
// §21.1.3.1) written to the FIO, which states no 1C32h:04 to check it against (manual §7.13.22).
TEST_F(ControllerSync, SmSynchronousFromTheBusFileIsWrittenToTheFio) {
    start({"--slave", "fio"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    master_.reset(); // out of the controller's way; read_back() opens a fresh one
    link_.reset();
    write_bus_file(
        "  cycle_us: 1000\n  sync: sm\n",
        "    - {position: 0, name: table, profile: fio, axes: [{axis: 1, mode: csp}]}\n");
    auto started = start_controller();
    ASSERT_TRUE(started) << started.error().detail << events_;
    controller_->run_for(200ms);
    EXPECT_TRUE(has("slave 0 (FIO Drive Control): sync mode 1 (SM synchronous), cycle 1000 µs\n"))
        << events_;
    EXPECT_TRUE(has("has no 0x1C32:04 (sync modes supported); sync mode 1 (SM synchronous) not "
                    "checked"))
        << events_;
    EXPECT_TRUE(has("slave 0 (FIO Drive Control): OP")) << events_;
    EXPECT_FALSE(has("cyclic exchange failed")) << events_;
    controller_->shutdown();
    controller_.reset();
    EXPECT_EQ(read_back<std::uint16_t>(0, 0x1C32, 1), std::uint16_t{1});
    EXPECT_EQ(read_back<std::uint16_t>(0, 0x1C33, 1), std::uint16_t{1});
}

// AKD2G manual §5.2.50: 1C32h:05 = 250 µs. A 200 µs cycle is refused before SAFE-OP with the
// bus file's line, the slave's position, product and name, the cycle and the minimum.
TEST_F(ControllerSync, ACycleBelowTheSlavesMinimumIsRefusedBeforeOp) {
    start({"--slave", "fio", "--slave", "akd2g"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    master_.reset();
    link_.reset();
    write_bus_file("  cycle_us: 200\n",
                   "    - {position: 0, name: table, profile: fio}\n"
                   "    - {position: 1, name: spindle, profile: akd2g, axes: [{axis: 1}]}\n");
    auto started = start_controller();
    ASSERT_FALSE(started) << events_;
    EXPECT_EQ(started.error().code, controller::ControllerErrc::SegmentFailed);
    EXPECT_EQ(started.error().detail,
              fmt::format("{}:6: slave 1 (AKD2G) \"spindle\": cycle time 200 µs is shorter than "
                          "the slave's minimum cycle time 250 µs (0x1C32:05)",
                          path_))
        << events_;
    EXPECT_FALSE(has(": OP")) << events_;
}

} // namespace
} // namespace codrive::testing
