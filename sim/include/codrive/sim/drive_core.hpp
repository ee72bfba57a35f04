// SPDX-License-Identifier: Apache-2.0
// The simulated CiA 402 axis: device state machine, modes of operation, faults, motor model.
// Transport-independent: it lives on an ObjectDictionary; CANopen and EtherCAT devices share it.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/drives/cia402.hpp>
#include <codrive/sim/homing.hpp>
#include <codrive/sim/motor_model.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/touch_probe.hpp>
#include <codrive/sim/trajectory.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace codrive::sim {

/// What an axis reports to its device (which turns it into EMCY, 1001h, 1003h).
struct AxisEvent {
    enum class Kind : std::uint8_t {
        FaultRaised,    ///< `code` is now active (603Fh set, state → FAULT REACTION ACTIVE)
        WarningRaised,  ///< `code` is active as a warning (statusword bit 7)
        WarningCleared, ///< `code` is no longer active
        FaultsCleared,  ///< fault reset succeeded: no fault left on this axis
    };
    Kind kind = Kind::FaultRaised;
    unsigned axis = 0;
    FaultCode code;
};

/// One axis of a simulated drive. Installs its CiA 402 objects (profile types, access, ranges
/// and defaults; axis n at index + n × axis offset) into the dictionary at construction and
/// serves them: controlword writes run the state machine at once (CiA 402 §6.3 transitions
/// 0–16), step() runs the active mode, the motor and the monitoring with a fixed dt.
class DriveCore {
public:
    using EventHandler = std::function<void(const AxisEvent&)>;

    DriveCore(ObjectDictionary& od, const SimProfile& profile, unsigned axis,
              std::optional<MachineConfig> machine = std::nullopt);
    DriveCore(const DriveCore&) = delete;
    DriveCore& operator=(const DriveCore&) = delete;

    void set_event_handler(EventHandler handler) { handler_ = std::move(handler); }

    /// Transitions 0 and 1: NOT READY TO SWITCH ON → SWITCH ON DISABLED, set-points cleared,
    /// faults forgotten (a power cycle or NMT reset node). The mechanics keep their position.
    void power_on();
    /// Advances the axis by dt seconds.
    void step(double dt);

    /// Fault injection: Sto sets the STO input (release with set_sto(false)); OverCurrent and
    /// FollowingError raise the profile's fault; HeartbeatLoss raises it if the profile treats
    /// it as an axis fault (AKD2G F7002), otherwise applies 6007h (DS-BVS).
    void inject(FaultKind kind);
    void set_sto(bool active);
    [[nodiscard]] bool sto() const { return sto_; }
    /// The fieldbus delivers synchronous process data (EtherCAT OP): FIO CSP statusword bit 8.
    void set_fieldbus_synchronised(bool on) { fieldbus_synchronised_ = on; }
    /// Raises a fault (transition 13). A `persistent` fault stays until clear_condition().
    void raise_fault(const FaultCode& code, bool persistent = false);
    /// The abort connection option code reaction (6007h): 2 disable voltage, 3 quick stop.
    void abort_connection(std::int16_t option);
    /// A local device control command (as if the controlword said it).
    void command(drives::cia402::Command c);

    [[nodiscard]] drives::cia402::State state() const { return state_; }
    [[nodiscard]] std::uint16_t statusword() const { return statusword_; }
    [[nodiscard]] std::int8_t mode_display() const { return mode_; }
    [[nodiscard]] const std::vector<FaultCode>& faults() const { return faults_; }
    [[nodiscard]] const std::vector<FaultCode>& warnings() const { return warnings_; }
    [[nodiscard]] MotorModel& motor() { return motor_; }
    [[nodiscard]] const MotorModel& motor() const { return motor_; }
    [[nodiscard]] const Trajectory& trajectory() const { return traj_; }
    [[nodiscard]] unsigned axis() const { return axis_; }
    /// The index of a CiA 402 object for this axis (6040h → 6840h on AKD2G axis 2).
    [[nodiscard]] std::uint16_t index(std::uint16_t base) const;
    /// The index of a manufacturer axis object (AKD2G 50xxh → 51xxh).
    [[nodiscard]] std::uint16_t mfr_index(std::uint16_t base) const;
    [[nodiscard]] const SimProfile& profile() const { return profile_; }
    /// Power stage on (torque can be produced).
    [[nodiscard]] bool enabled() const;
    /// The actual position (6064h).
    [[nodiscard]] std::int32_t position_actual() const {
        return od_.get<std::int32_t>(index(drives::cia402::obj::kPositionActual), 0).value_or(0);
    }
    /// The axis's touch probes (60B8h..60BDh), or nullptr if the drive has none (AKD2G §4.1.5).
    [[nodiscard]] TouchProbe* touch_probe() { return probe_.get(); }
    /// Homing attained since power-on (DS-BVS statusword bit 15).
    [[nodiscard]] bool homed() const { return homed_; }

private:
    struct PendingStop {
        bool active = false;
        double decel = 0;
        drives::cia402::State then = drives::cia402::State::SwitchOnDisabled;
    };

    void install_objects();
    void on_controlword(std::uint16_t cw);
    void evaluate(std::uint16_t cw);
    void set_state(drives::cia402::State s);
    void begin_stop(double decel, drives::cia402::State then);
    void disable_now(drives::cia402::State then);
    void quick_stop();
    void start_fault_reaction();
    void try_fault_reset();
    /// Writes the active faults to AKD2G 5004h/5104h AXIS#.FAULT1..10.
    void publish_faults();
    static constexpr std::uint8_t kAxisFaultSlots = 10;
    void enter_mode(std::int8_t mode);
    void run_mode(double dt);
    void run_pp(double dt);
    void run_pv(double dt);
    void run_pt(double dt);
    void run_hm(double dt);
    void run_csp(double dt);
    void monitor_following_error(double dt);
    void update_outputs();
    void emit(AxisEvent::Kind kind, const FaultCode& code);

    template <typename T>
    [[nodiscard]] T get(std::uint16_t base, std::uint8_t sub = 0, T fallback = T{}) const {
        return od_.get<T>(index(base), sub).value_or(fallback);
    }
    [[nodiscard]] double velocity_param(std::uint16_t base, std::uint8_t sub = 0) const;
    [[nodiscard]] double accel_param(std::uint16_t base, std::uint8_t sub = 0) const;
    [[nodiscard]] double quick_stop_decel() const;
    [[nodiscard]] double halt_decel() const;

    ObjectDictionary& od_;
    const SimProfile& profile_;
    unsigned axis_;
    MotorModel motor_;
    Trajectory traj_;
    Homing homing_;
    EventHandler handler_;

    drives::cia402::State state_ = drives::cia402::State::NotReadyToSwitchOn;
    std::uint16_t statusword_ = 0;
    std::uint16_t last_cw_ = 0;
    bool new_setpoint_edge_ = false; ///< bit 4 rose since the last step
    bool new_setpoint_fall_ = false; ///< bit 4 fell since the last step
    std::int8_t mode_ = 0;
    PendingStop stop_;
    bool sto_ = false;
    bool homed_ = false;
    std::vector<FaultCode> faults_;
    std::vector<FaultCode> warnings_;
    std::vector<FaultKind> persistent_;
    bool fieldbus_synchronised_ = false;
    std::unique_ptr<TouchProbe> probe_;

    // Profile position.
    bool pp_moving_ = false;
    double pp_target_ = 0;
    std::optional<double> pp_buffer_;
    double pp_buffer_vmax_ = 0;
    bool setpoint_ack_ = false;
    double in_window_time_ = 0;
    // Velocity.
    double velocity_window_time_ = 0;
    // Torque.
    double torque_demand_ = 0;
    // Cyclic.
    double csp_last_target_ = 0;
    double csp_since_change_ = 0;
    double csp_from_ = 0;         ///< where the current interpolation segment started
    double csp_period_ = 0.001;   ///< measured set-point period (s)
    double csp_segment_time_ = 1; ///< time into the current segment (s)
    // Monitoring.
    double following_error_ = 0;
    double ferr_time_ = 0;
    bool ferr_bit_ = false;
};

} // namespace codrive::sim
