// SPDX-License-Identifier: Apache-2.0
// A scripted in-test CiA 402 device (object dictionary from a profile + a small state machine and
// mode model) behind a DriveTransport with deferred object access and a process image.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/time.hpp>
#include <codrive/drives/cia402.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>

#include <deque>
#include <fmt/format.h>
#include <map>
#include <set>
#include <utility>

namespace codrive::drives::testing {

using cia402::Command;
using cia402::State;

/// One axis of the fake device.
struct FakeAxisModel {
    State state = State::NotReadyToSwitchOn;
    bool sto = false;
    bool voltage = true;
    bool remote = true;
    bool fault_cause = false; ///< fault reset fails while true
    bool stuck = false;       ///< ignore every command
    bool reject_modes = false;
    std::uint16_t prev_cw = 0;
    std::int64_t position = 0;
    std::int32_t pp_target = 0;
    bool pp_moving = false;
    bool pp_ack = false;
    std::int32_t step_size = 100; ///< PP: units per cycle
    int homing_cycles = -1;
    bool homing_fail = false;
    bool homing_done = false;
    bool following_error = false;
    std::int32_t velocity = 0;
    std::uint16_t mode_bits = 0;
    /// Quick stop: cycles the drive needs to decelerate to standstill on its ramp.
    int stop_ramp_cycles = 3;
    int stop_ramp_left = 0; ///< cycles still to go on the ramp (0: halted)
    int ramps_cut = 0;      ///< disable voltage received while still on the ramp (coasting)
};

class FakeDevice {
public:
    FakeDevice(const Profile& p, unsigned axes) : profile_(p), axes_(axes) {
        build_device_dictionary(od_, p, axes);
        models_.resize(axes);
    }

    ObjectDictionary& od() { return od_; }
    FakeAxisModel& model(unsigned axis) { return models_.at(axis - 1); }
    std::uint16_t idx(std::uint16_t base, unsigned axis) const {
        return profile_.axis_index(base, axis);
    }
    std::uint16_t statusword(unsigned axis) const {
        return od_.get<std::uint16_t>(idx(0x6041, axis), 0).value_or(0);
    }
    void trigger_fault(unsigned axis, std::uint16_t code) {
        model(axis).state = State::FaultReactionActive;
        model(axis).fault_cause = true;
        if (od_.find(idx(0x603F, axis), 0) != nullptr) {
            od_.set<std::uint16_t>(idx(0x603F, axis), 0, code);
        }
        if (profile_.axis_fault_list != 0) { // AKD2G §5.3.84: the axis's own fault list
            od_.set<std::uint16_t>(idx(profile_.axis_fault_list, axis), 1, code);
        }
    }
    std::vector<std::uint16_t> controlword_log(unsigned axis) const { return cw_log_.at(axis - 1); }

    /// One device cycle: apply the controlword and the mode, update the statusword.
    void step() {
        cw_log_.resize(axes_);
        for (unsigned a = 1; a <= axes_; ++a) {
            step_axis(a);
        }
    }

private:
    void step_axis(unsigned a) {
        FakeAxisModel& m = model(a);
        const auto cwv = od_.get<std::uint16_t>(idx(0x6040, a), 0).value_or(0);
        auto& log = cw_log_.at(a - 1);
        if (log.empty() || log.back() != cwv) {
            log.push_back(cwv);
        }
        const auto cmd = cia402::decode_command(cwv);
        const bool reset_edge = (cwv & 0x80) != 0 && (m.prev_cw & 0x80) == 0;
        const std::int16_t qs = od_.get<std::int16_t>(idx(0x605A, a), 0).value_or(2);
        if (!m.stuck) {
            switch (m.state) {
            case State::NotReadyToSwitchOn:
                m.state = State::SwitchOnDisabled;
                break;
            case State::SwitchOnDisabled:
                if (cmd == Command::Shutdown) {
                    m.state = State::ReadyToSwitchOn;
                }
                break;
            case State::ReadyToSwitchOn:
                if (cmd == Command::SwitchOn || cmd == Command::EnableOperation) {
                    if (m.voltage && !m.sto) {
                        m.state = State::SwitchedOn;
                    }
                } else if (cmd == Command::DisableVoltage || cmd == Command::QuickStop) {
                    m.state = State::SwitchOnDisabled;
                }
                break;
            case State::SwitchedOn:
                if (cmd == Command::EnableOperation && !m.sto) {
                    m.state = State::OperationEnabled;
                } else if (cmd == Command::Shutdown) {
                    m.state = State::ReadyToSwitchOn;
                } else if (cmd == Command::DisableVoltage || cmd == Command::QuickStop) {
                    m.state = State::SwitchOnDisabled;
                }
                break;
            case State::OperationEnabled:
                if (cmd == Command::SwitchOn) {
                    m.state = State::SwitchedOn;
                } else if (cmd == Command::Shutdown) {
                    m.state = State::ReadyToSwitchOn;
                } else if (cmd == Command::DisableVoltage) {
                    m.state = State::SwitchOnDisabled;
                } else if (cmd == Command::QuickStop) {
                    // 605Ah 0: disable drive function at once; otherwise the ramp starts.
                    m.state = qs == 0 ? State::SwitchOnDisabled : State::QuickStopActive;
                    m.stop_ramp_left = m.stop_ramp_cycles;
                }
                break;
            case State::QuickStopActive:
                if (cmd == Command::DisableVoltage) { // 12: the power stage goes off now
                    if (m.stop_ramp_left > 0) {
                        ++m.ramps_cut;
                    }
                    m.stop_ramp_left = 0;
                    m.state = State::SwitchOnDisabled;
                } else if (m.stop_ramp_left > 0) {
                    --m.stop_ramp_left; // decelerating
                } else if (qs >= 1 && qs <= 4) {
                    m.state = State::SwitchOnDisabled; // 12: quick stop completed
                } else if (cmd == Command::EnableOperation) {
                    m.state = State::OperationEnabled; // 16 (605Ah 5..8)
                }
                break;
            case State::FaultReactionActive:
                m.state = State::Fault;
                break;
            case State::Fault:
                if (reset_edge && !m.fault_cause) {
                    m.state = State::SwitchOnDisabled;
                    if (profile_.axis_fault_list != 0) {
                        od_.set<std::uint16_t>(idx(profile_.axis_fault_list, a), 1, 0);
                    }
                }
                break;
            case State::Unknown:
                break;
            }
        }
        m.prev_cw = cwv;
        // Mode: 6061h follows 6060h one cycle later (if the profile accepts it).
        const auto mode = od_.get<std::int8_t>(idx(0x6060, a), 0).value_or(0);
        const auto display = od_.get<std::int8_t>(idx(0x6061, a), 0).value_or(0);
        if (mode != display && !m.reject_modes && profile_.supports_mode(mode)) {
            od_.set<std::int8_t>(idx(0x6061, a), 0, mode);
        }
        m.mode_bits = 0;
        if (m.state == State::OperationEnabled) {
            run_mode(a, m, cwv, display);
        } else if (m.state == State::QuickStopActive) {
            if (m.stop_ramp_left == 0) {
                m.mode_bits |= cia402::sw::kTargetReached; // 605Ah 5..8: halted
            }
        } else {
            m.pp_ack = false;
            m.pp_moving = false;
        }
        std::uint16_t s = cia402::state_bits(m.state);
        if (m.voltage) {
            s |= cia402::sw::kVoltageEnabled;
        }
        if (m.sto && profile_.quirks.sto_in_statusword_bit8) {
            s |= cia402::sw::kManufacturer8;
        }
        if (m.remote) {
            s |= cia402::sw::kRemote;
        }
        s = static_cast<std::uint16_t>(s | m.mode_bits);
        od_.set<std::uint16_t>(idx(0x6041, a), 0, s);
        od_.set<std::int32_t>(idx(0x6064, a), 0, static_cast<std::int32_t>(m.position));
        if (od_.find(idx(0x606C, a), 0) != nullptr) {
            od_.set<std::int32_t>(idx(0x606C, a), 0, m.velocity);
        }
    }

    void run_mode(unsigned a, FakeAxisModel& m, std::uint16_t cwv, std::int8_t mode) {
        using namespace cia402;
        switch (static_cast<Mode>(mode)) {
        case Mode::ProfilePosition: {
            const bool bit4 = (cwv & cw::kOpMode4) != 0;
            if (bit4 && !m.pp_ack) {
                const auto t = od_.get<std::int32_t>(idx(0x607A, a), 0).value_or(0);
                m.pp_target =
                    (cwv & cw::kOpMode6) != 0 ? static_cast<std::int32_t>(m.position) + t : t;
                m.pp_moving = true;
                m.pp_ack = true;
            } else if (!bit4) {
                m.pp_ack = false;
            }
            if (m.pp_moving && (cwv & cw::kHalt) == 0) {
                const std::int64_t d = m.pp_target - m.position;
                const std::int64_t stepv = std::min<std::int64_t>(std::llabs(d), m.step_size);
                m.position += d > 0 ? stepv : -stepv;
                if (m.position == m.pp_target) {
                    m.pp_moving = false;
                }
            }
            if (m.pp_ack) {
                m.mode_bits |= sw::kOpMode12;
            }
            if (!m.pp_moving) {
                m.mode_bits |= sw::kTargetReached;
            }
            if (m.following_error) {
                m.mode_bits |= sw::kOpMode13;
            }
            break;
        }
        case Mode::ProfileVelocity:
            m.velocity = od_.get<std::int32_t>(idx(0x60FF, a), 0).value_or(0);
            m.mode_bits |= sw::kTargetReached;
            if (m.velocity == 0) {
                m.mode_bits |= sw::kOpMode12;
            }
            break;
        case Mode::ProfileTorque:
            m.mode_bits |= sw::kTargetReached;
            break;
        case Mode::Homing: {
            const bool bit4 = (cwv & cw::kOpMode4) != 0;
            if (bit4 && m.homing_cycles < 0 && !m.homing_done) {
                m.homing_cycles = 5;
            }
            if (m.homing_cycles > 0) {
                --m.homing_cycles;
            } else if (m.homing_cycles == 0) {
                m.homing_cycles = -1;
                m.homing_done = true;
                if (!m.homing_fail) {
                    m.position = od_.get<std::int32_t>(idx(0x607C, a), 0).value_or(0);
                }
            }
            if (m.homing_done) {
                m.mode_bits |= m.homing_fail
                                   ? static_cast<std::uint16_t>(sw::kOpMode13 | sw::kTargetReached)
                                   : static_cast<std::uint16_t>(sw::kOpMode12 | sw::kTargetReached);
            } else if (m.homing_cycles < 0) {
                m.mode_bits |= sw::kTargetReached; // not started
            }
            break;
        }
        case Mode::CyclicSyncPosition:
            m.position = od_.get<std::int32_t>(idx(0x607A, a), 0).value_or(0);
            m.mode_bits |= sw::kOpMode12;
            break;
        case Mode::CyclicSyncVelocity:
        case Mode::CyclicSyncTorque:
            m.mode_bits |= sw::kOpMode12;
            break;
        default:
            break;
        }
    }

    const Profile& profile_;
    unsigned axes_;
    ObjectDictionary od_;
    std::vector<FakeAxisModel> models_;
    std::vector<std::vector<std::uint16_t>> cw_log_;
};

/// A transport over a FakeDevice: object access completes on process() (like an SDO answer a
/// little later), outputs reach the device on apply_outputs() (like an RPDO at SYNC).
class FakeTransport final : public DriveTransport {
public:
    explicit FakeTransport(FakeDevice& dev, std::string name = "node 5")
        : dev_(dev), name_(std::move(name)) {}

    /// Maps an object into the process image.
    void map_output(std::uint16_t index, std::uint8_t sub) { outputs_.push_back({index, sub}); }
    void map_input(std::uint16_t index, std::uint8_t sub) { inputs_.push_back({index, sub}); }

    [[nodiscard]] std::string name() const override { return name_; }

    void read(std::uint16_t index, std::uint8_t sub, ReadDone done) override {
        ++reads_;
        queue_.emplace_back([this, index, sub, done = std::move(done)] {
            auto r = dev_.od().read(index, sub);
            if (!r) {
                done(drive_fail(DriveErrc::Transport,
                                fmt::format("{}: SDO upload {} aborted 0x{:08X}", name_,
                                            hex_index(index, sub),
                                            static_cast<std::uint32_t>(r.error()))));
                return;
            }
            done(Bytes(r->begin(), r->end()));
        });
    }

    void write(std::uint16_t index, std::uint8_t sub, Bytes data, WriteDone done) override {
        ++writes_;
        writes_log_.push_back({index, sub});
        queue_.emplace_back([this, index, sub, data = std::move(data), done = std::move(done)] {
            auto r = dev_.od().write(index, sub, data);
            if (!r) {
                done(drive_fail(DriveErrc::Transport,
                                fmt::format("{}: SDO download {} aborted 0x{:08X}", name_,
                                            hex_index(index, sub),
                                            static_cast<std::uint32_t>(r.error()))));
                return;
            }
            done({});
        });
    }

    [[nodiscard]] CyclicHandle output(std::uint16_t index, std::uint8_t sub) const override {
        for (std::size_t i = 0; i < outputs_.size(); ++i) {
            if (outputs_[i] == std::pair<std::uint16_t, std::uint8_t>{index, sub}) {
                return {static_cast<std::int32_t>(i)};
            }
        }
        return {};
    }
    [[nodiscard]] CyclicHandle input(std::uint16_t index, std::uint8_t sub) const override {
        for (std::size_t i = 0; i < inputs_.size(); ++i) {
            if (inputs_[i] == std::pair<std::uint16_t, std::uint8_t>{index, sub}) {
                return {static_cast<std::int32_t>(1000 + i)};
            }
        }
        return {};
    }
    void set_raw(CyclicHandle h, std::uint64_t raw) override {
        if (h.valid() && h.slot < 1000) {
            pending_[static_cast<std::size_t>(h.slot)] = raw;
        }
    }
    [[nodiscard]] std::optional<std::uint64_t> get_raw(CyclicHandle h) const override {
        if (!h.valid() || h.slot < 1000) {
            return std::nullopt;
        }
        if (auto it = stalled_.find(h.slot); it != stalled_.end()) {
            return it->second;
        }
        const auto& [index, sub] = inputs_.at(static_cast<std::size_t>(h.slot - 1000));
        const SubObject* s = dev_.od().find(index, sub);
        if (s == nullptr) {
            return std::nullopt;
        }
        std::uint64_t v = 0;
        for (std::size_t i = 0; i < s->value.size() && i < 8; ++i) {
            v |= static_cast<std::uint64_t>(s->value.bytes()[i]) << (8 * i);
        }
        return v;
    }

    /// Counts input receptions (one per cycle) for input_count(), as the CANopen transport does.
    void count_inputs(bool on) { counting_ = on; }
    /// A late TPDO: the inputs keep their current values and are not received again until
    /// stall_inputs(false).
    void stall_inputs(bool on) {
        stalled_.clear();
        if (on) {
            for (std::size_t i = 0; i < inputs_.size(); ++i) {
                const CyclicHandle h{static_cast<std::int32_t>(1000 + i)};
                if (auto v = get_raw(h)) {
                    stalled_[h.slot] = *v;
                }
            }
        }
    }
    [[nodiscard]] std::optional<std::uint64_t> input_count(CyclicHandle h) const override {
        if (!counting_ || !h.valid() || h.slot < 1000) {
            return std::nullopt;
        }
        return received_;
    }

    /// Completes all queued object accesses (callbacks may queue more: those run next time).
    void process() {
        if (stalled_.empty()) {
            ++received_;
        }
        auto q = std::move(queue_);
        queue_.clear();
        for (auto& fn : q) {
            fn();
        }
    }
    /// Copies the outputs into the device's dictionary.
    void apply_outputs() {
        for (auto& [slot, raw] : pending_) {
            const auto& [index, sub] = outputs_.at(slot);
            SubObject* s = dev_.od().find(index, sub);
            if (s == nullptr) {
                continue;
            }
            auto& b = s->value.mutable_bytes();
            for (std::size_t i = 0; i < b.size(); ++i) {
                b[i] = static_cast<std::uint8_t>(raw >> (8 * i));
            }
        }
        ++cycles_;
    }
    [[nodiscard]] std::uint64_t reads() const { return reads_; }
    [[nodiscard]] std::uint64_t writes() const { return writes_; }
    [[nodiscard]] const std::vector<std::pair<std::uint16_t, std::uint8_t>>& writes_log() const {
        return writes_log_;
    }

private:
    FakeDevice& dev_;
    std::string name_;
    std::vector<std::pair<std::uint16_t, std::uint8_t>> outputs_;
    std::vector<std::pair<std::uint16_t, std::uint8_t>> inputs_;
    std::map<std::size_t, std::uint64_t> pending_;
    std::deque<std::function<void()>> queue_;
    std::uint64_t reads_ = 0;
    std::uint64_t writes_ = 0;
    std::uint64_t cycles_ = 0;
    std::vector<std::pair<std::uint16_t, std::uint8_t>> writes_log_;
    bool counting_ = false;
    std::uint64_t received_ = 0;
    std::map<std::int32_t, std::uint64_t> stalled_;
};

} // namespace codrive::drives::testing
