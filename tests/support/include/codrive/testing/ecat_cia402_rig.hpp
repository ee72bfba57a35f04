// SPDX-License-Identifier: Apache-2.0
// The master side of an EtherCAT segment for the CiA 402 scenario: a CoeTransport and a
// drives::DriveDevice per slave, emergencies decoded with the profiles' texts, and the process
// data loop as a cia402::CycleDriver — on a real clock (veth) or a FakeClock (in-process).
#pragma once

#include <codrive/drives/drive_device.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/ethercat/coe_transport.hpp>
#include <codrive/sim/sim_device.hpp>
#include <codrive/testing/cia402_scenario.hpp>

#include <codrive/core/time.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace codrive::testing {

/// RxPDO/TxPDO layout for the scenario: the default maps lack 60FFh and 606Ch (PV) and 60F4h
/// (CSP following error), and the AKD2G's lacks 6060h/6061h, so both get the same explicit map
/// (ETG.1000.6 §5.6.7.4).
inline const std::vector<ethercat::PdoMapping> kScenarioRx{
    {0x1600, {{0x6040, 0, 16}, {0x607A, 0, 32}, {0x60FF, 0, 32}, {0x6060, 0, 8}}}};
inline const std::vector<ethercat::PdoMapping> kScenarioTx{
    {0x1A00, {{0x6041, 0, 16}, {0x6064, 0, 32}, {0x606C, 0, 32}, {0x6061, 0, 8}, {0x60F4, 0, 32}}}};

/// The master side of the segment: a CoE transport and a DriveDevice per slave, and the
/// process data loop as a cia402::CycleDriver.
class EcatCia402Rig {
public:
    /// `wait_until` blocks (or, on a FakeClock, advances the clock) until a cycle is due.
    EcatCia402Rig(ethercat::Master& master, IClock& clock, Duration period,
                  std::function<void(TimePoint)> wait_until)
        : master_(master), clock_(clock), period_(period), wait_until_(std::move(wait_until)) {}

    ::testing::AssertionResult bring_up(const std::vector<std::string>& profiles) {
        if (!master_.scan()) {
            return ::testing::AssertionFailure() << master_.last_error();
        }
        if (!master_.set_state_all(ethercat::AlState::PreOp)) {
            return ::testing::AssertionFailure() << master_.last_error();
        }
        for (std::size_t i = 0; i < profiles.size(); ++i) {
            if (!master_.configure_pdos(i, kScenarioRx, kScenarioTx)) {
                return ::testing::AssertionFailure() << master_.last_error();
            }
        }
        if (!master_.set_state_all(ethercat::AlState::Op)) {
            return ::testing::AssertionFailure() << master_.last_error();
        }
        for (std::size_t i = 0; i < profiles.size(); ++i) {
            const drives::Profile* p = drives::find_profile(profiles[i]);
            if (p == nullptr) {
                return ::testing::AssertionFailure() << "no profile " << profiles[i];
            }
            transports_.push_back(std::make_unique<ethercat::CoeTransport>(master_, i));
            drives::AxisConfig base;
            base.timeout = seconds(5);
            devices_.push_back(
                std::make_unique<drives::DriveDevice>(*transports_.back(), *p, 1, base));
            providers_.push_back(drives::emcy_text_provider(*p));
        }
        master_.on_emergency([this](std::size_t slave, const emcy::EmcyMessage& m) {
            emcy::EmcyEvent e;
            e.message = m;
            e.time = clock_.now();
            e.reset = m.error_code == 0;
            e.text = master_.describe_emergency(slave, m, providers_.at(slave).get());
            std::printf("  emergency: %s\n", e.text.c_str());
            emergencies_.push_back(e.text);
            devices_.at(slave)->on_emcy(e);
        });
        driver_.period = period_;
        driver_.run_until = [this](const std::function<bool()>& pred, Duration timeout) {
            return run_until(pred, timeout);
        };
        driver_.set_cycle_hook = [this](std::function<void(bool)> hook) {
            hook_ = std::move(hook);
        };
        next_ = clock_.now();
        // First statusword and position by process data.
        const bool ready = run_until(
            [this] {
                for (auto& d : devices_) {
                    if (!d->axis(1).has_statusword() || !d->axis(1).position_actual()) {
                        return false;
                    }
                }
                return true;
            },
            seconds(2));
        if (!ready) {
            return ::testing::AssertionFailure() << "no statusword/position by process data";
        }
        return ::testing::AssertionSuccess();
    }

    bool run_until(const std::function<bool()>& pred, Duration timeout) {
        const TimePoint deadline = clock_.now() + timeout;
        while (!pred()) {
            if (clock_.now() >= deadline) {
                return false;
            }
            cycle();
        }
        return true;
    }

    /// One control cycle: acyclic work (queued CoE accesses, emergencies), the LRW, then the
    /// axes and the cyclic set-point hook.
    void cycle() {
        next_ += period_;
        const TimePoint now = clock_.now();
        // The host disturbed this cycle when it starts more than two periods after the last.
        bool on_time = true;
        if (last_cycle_ != TimePoint{}) {
            max_gap_ = std::max(max_gap_, now - last_cycle_);
            on_time = now - last_cycle_ <= 2 * period_;
        }
        last_cycle_ = now;
        if (next_ < now) {
            next_ = now; // late: no catching up with a burst of cycles
        } else {
            wait_until_(next_);
        }
        for (auto& t : transports_) {
            t->poll();
        }
        master_.poll_mailboxes();
        if (auto wkc = master_.exchange_process_data(); !wkc) {
            ++bad_cycles_;
            if (bad_cycles_ <= 10) {
                std::printf("  cycle %llu: %s\n", static_cast<unsigned long long>(cycles_),
                            master_.last_error().c_str());
            }
        }
        ++cycles_;
        const TimePoint t = clock_.now();
        for (auto& d : devices_) {
            d->on_cycle(t);
            if (d->next_deadline() <= t) {
                d->on_tick(t);
            }
        }
        if (hook_) {
            hook_(on_time);
        }
    }

    /// Writes an object over the slave's CoE transport while the cycle runs.
    template <typename T>
    bool write(std::size_t slave, std::uint16_t index, std::uint8_t sub, T value) {
        std::optional<drives::DriveVoid> done;
        transports_.at(slave)->write_as<T>(index, sub, value,
                                           [&](drives::DriveVoid r) { done = r; });
        run_until([&] { return done.has_value(); }, seconds(2));
        EXPECT_TRUE(done && *done) << (done && !*done ? done->error().message : "timed out");
        return done && *done;
    }

    /// Writes the simulator's fault-injection object (2FF0h, sim_device.hpp) over CoE.
    bool control(std::size_t slave, std::uint8_t sub, std::uint8_t value) {
        return write<std::uint8_t>(slave, sim::kControlObject, sub, value);
    }

    bool saw_emergency(const std::string& a, const std::string& b) const {
        for (const auto& e : emergencies_) {
            if (e.find(a) != std::string::npos && e.find(b) != std::string::npos) {
                return true;
            }
        }
        return false;
    }

    drives::Axis& axis(std::size_t slave) { return devices_.at(slave)->axis(1); }
    ethercat::CoeTransport& transport(std::size_t slave) { return *transports_.at(slave); }
    const cia402::CycleDriver& driver() const { return driver_; }
    [[nodiscard]] std::uint64_t cycles() const { return cycles_; }
    [[nodiscard]] std::uint64_t bad_cycles() const { return bad_cycles_; }
    /// The longest time between two cycles (scheduling stalls of a loaded machine).
    [[nodiscard]] Duration max_gap() const { return max_gap_; }

private:
    ethercat::Master& master_;
    IClock& clock_;
    Duration period_;
    std::function<void(TimePoint)> wait_until_;
    std::vector<std::unique_ptr<ethercat::CoeTransport>> transports_;
    std::vector<std::unique_ptr<drives::DriveDevice>> devices_;
    std::vector<std::shared_ptr<const emcy::IEmcyTextProvider>> providers_;
    std::vector<std::string> emergencies_;
    cia402::CycleDriver driver_;
    std::function<void(bool)> hook_;
    TimePoint next_{};
    TimePoint last_cycle_{};
    Duration max_gap_{};
    std::uint64_t cycles_ = 0;
    std::uint64_t bad_cycles_ = 0;
};

/// Following-error tolerance of the CSP path in drive increments: 1,000 of the AKD2G's 65,536
/// per revolution (≈ 5.5°, as on vcan) and 60 of the FIO's 3,600 (6°).
constexpr double kAkd2gPathTolerance = 1000;
constexpr double kFioPathTolerance = 60;
constexpr std::uint64_t kPathCycles = 1000;

inline void print_path(const char* who, const cia402::PathFigures& f, double tolerance) {
    std::printf("CSP %s: %llu cycles, max following error 60F4h %.0f increments (tolerance %.0f), "
                "%.0f including %llu disturbed cycles; end to end against the set-points %.0f\n",
                who, static_cast<unsigned long long>(f.cycles), f.max_error.at(0), tolerance,
                f.max_error_all.at(0), static_cast<unsigned long long>(f.disturbed),
                f.max_path_error.at(0));
}

/// The CiA 402 scenario on a FIO (slave 0) and an AKD2G (slave 1) after bring_up(): enable,
/// homing, PP with target reached, PV, CSP paths within a tolerance, quick stop, an injected
/// over-current with its emergency decoded, fault reset — the steps the vcan test runs.
inline void run_fio_akd2g_scenario(EcatCia402Rig& rig, unsigned max_latency = 4) {
    const cia402::CycleDriver& d = rig.driver();
    drives::Axis& fio = rig.axis(0);
    drives::Axis& akd = rig.axis(1);
    EXPECT_EQ(akd.name(), "slave 1 (AKD2G) axis 1");

    // Enable.
    for (drives::Axis* a : {&fio, &akd}) {
        ASSERT_TRUE(cia402::enable(d, *a));
    }

    // Homing: the FIO searches its home switch (method 19, switch at 2..3 rev = 7,200 of 3,600
    // increments per revolution; position := offset there), the AKD2G takes the current
    // position with an offset (35).
    drives::HomingParams hf;
    hf.method = 19;
    hf.speed_switch = 300; // rpm
    hf.speed_zero = 30;
    hf.acceleration = 10000;
    hf.offset = 0;
    ASSERT_TRUE(cia402::home(d, fio, hf, 0, 40));
    drives::HomingParams ha;
    ha.method = 35;
    ha.offset = -5000;
    ASSERT_TRUE(cia402::home(d, akd, ha, -5000, 700));

    // PP moves with target reached.
    ASSERT_TRUE(cia402::pp_move(d, fio, 7200, 5));
    ASSERT_TRUE(cia402::pp_move(d, akd, -5000 + 327680, 700));
    std::printf("PP: fio %d, akd2g %d\n", fio.position_actual().value_or(0),
                akd.position_actual().value_or(0));

    // PV, verified on the cyclic 606Ch. The FIO's velocity window 606Dh defaults to 0 (target
    // reached only at exactly the target speed): 10 rpm, as a commissioning step would set.
    ASSERT_TRUE(rig.write<std::uint16_t>(0, 0x606D, 0, 10));
    cia402::PvFigures pv;
    ASSERT_TRUE(cia402::pv_run_and_stop(d, fio, 120, 12, &pv));
    std::printf("PV fio: 606Ch %d rpm at 120 rpm, %d after the stop\n", pv.at_speed, pv.after_stop);
    ASSERT_TRUE(cia402::pv_run_and_stop(d, akd, 655360, 20000, &pv));
    std::printf("PV akd2g: 606Ch %d at 655360, %d after the stop\n", pv.at_speed, pv.after_stop);

    // CSP: 1,000 cycles each on a jerk-limited path, streamed one set-point per cycle.
    cia402::PathFigures path;
    ASSERT_TRUE(cia402::csp_path(d, {&akd}, {-100000.0}, kPathCycles, kAkd2gPathTolerance, &path,
                                 max_latency));
    print_path("akd2g", path, kAkd2gPathTolerance);
    ASSERT_TRUE(
        cia402::csp_path(d, {&fio}, {5400.0}, kPathCycles, kFioPathTolerance, &path, max_latency));
    print_path("fio", path, kFioPathTolerance);

    // Quick stop while moving, per each drive's 605Ah.
    std::int16_t option = -1;
    ASSERT_TRUE(cia402::quick_stop_while_moving(d, akd, rig.transport(1), -327680, 100, &option));
    std::printf("quick stop akd2g: 605Ah = %d\n", option);
    ASSERT_TRUE(cia402::quick_stop_while_moving(d, fio, rig.transport(0), -120, 5, &option));
    std::printf("quick stop fio: 605Ah = %d\n", option);

    // Injected over-current: CoE emergency decoded with the vendor text, fault reset, enable.
    const auto over_current = [&rig](std::size_t slave) {
        return [&rig, slave](bool on) {
            return rig.control(slave, sim::kControlOverCurrent, on ? 1 : 0);
        };
    };
    ASSERT_TRUE(
        cia402::fault_and_recover(d, akd, over_current(1), 0xFF07, "F2002 Output over current"));
    EXPECT_TRUE(rig.saw_emergency("slave 1 (AKD2G): EMCY 0xFF07", "F2002"));
    ASSERT_TRUE(cia402::fault_and_recover(d, fio, over_current(0), 0x2300, "too high"));
    EXPECT_TRUE(rig.saw_emergency("slave 0 (FIO Drive Control): EMCY 0x2300", "too high"));
    for (drives::Axis* a : {&fio, &akd}) {
        EXPECT_EQ(a->state(), drives::cia402::State::OperationEnabled) << a->name();
    }
    std::printf("%llu cycles of %lld µs, %llu with a lost frame or working counter error, "
                "longest gap between cycles %.1f ms\n",
                static_cast<unsigned long long>(rig.cycles()),
                static_cast<long long>(
                    std::chrono::duration_cast<std::chrono::microseconds>(d.period).count()),
                static_cast<unsigned long long>(rig.bad_cycles()), to_ms(rig.max_gap()));
}

} // namespace codrive::testing
