// SPDX-License-Identifier: Apache-2.0
// One CiA 402 axis on the master side: statusword decoding, controlword commands, asynchronous
// operations (enable, quick stop, fault reset, mode change, PP/PV/PT/HM moves) with timeouts and
// readable errors, and cyclic set-points (CSP/CSV/CST/IP). Sans-I/O: driven by on_cycle() with
// the process image, or by on_tick() polling the statusword over SDO.
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/time.hpp>
#include <codrive/drives/cia402.hpp>
#include <codrive/drives/error.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace codrive::drives {

struct AxisConfig {
    unsigned axis = 1;                       ///< 1-based axis number within the device
    const Profile* profile = nullptr;        ///< nullptr = generic CiA 402
    Duration timeout = seconds(2);           ///< default time limit of an operation
    Duration poll_period = milliseconds(20); ///< SDO polling when 6041h is not cyclic
    std::string name;                        ///< "" = "<transport name> axis <n>" / "axis <n>"
};

/// Options of a profile-position move (controlword bits 5, 6, 9 and the profile objects).
struct MoveOptions {
    bool relative = false;                     ///< bit 6
    bool immediate = false;                    ///< bit 5: change set immediately
    bool change_on_setpoint = false;           ///< bit 9: blend into the next set-point
    std::optional<std::uint32_t> velocity;     ///< 6081h
    std::optional<std::uint32_t> acceleration; ///< 6083h
    std::optional<std::uint32_t> deceleration; ///< 6084h
};

/// Homing parameters (6098h, 6099h:1/:2, 609Ah, 607Ch).
struct HomingParams {
    std::int8_t method = 35;
    std::uint32_t speed_switch = 0;
    std::uint32_t speed_zero = 0;
    std::uint32_t acceleration = 0;
    std::int32_t offset = 0;
};

/// A fault the drive attributes to one axis.
struct AxisFault {
    std::uint16_t code = 0; ///< EMCY error code (or the raw list entry if the profile lacks it)
    std::string text;       ///< the drive's fault text, "F2002 Output over current"
};

class Axis final : public ITimed {
public:
    using Done = std::function<void(DriveVoid)>;
    using StateHandler = std::function<void(cia402::State from, cia402::State to)>;
    using FaultHandler = std::function<void(const AxisFault&)>;

    Axis(DriveTransport& transport, AxisConfig config);
    ~Axis() override;
    Axis(const Axis&) = delete;
    Axis& operator=(const Axis&) = delete;

    /// Re-resolves the process-image handles (after the PDO mapping changed).
    void bind();
    /// One cycle with process data: reads the inputs, advances the operation, writes the
    /// outputs. Call after the inputs of the cycle arrived and before the next SYNC.
    void on_cycle(TimePoint now);
    /// Without cyclic statusword: polls 6041h (and 6061h) over the transport; also enforces
    /// timeouts.
    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    // ---- state ------------------------------------------------------------------------------
    [[nodiscard]] cia402::State state() const { return state_; }
    [[nodiscard]] std::uint16_t statusword() const { return statusword_; }
    [[nodiscard]] bool has_statusword() const { return has_status_; }
    /// The controlword the axis currently commands.
    [[nodiscard]] std::uint16_t controlword() const;
    [[nodiscard]] std::optional<std::int8_t> mode_display() const { return mode_display_; }
    [[nodiscard]] bool busy() const { return op_.has_value(); }
    [[nodiscard]] const std::string& name() const { return name_; }
    [[nodiscard]] unsigned number() const { return axis_; }
    [[nodiscard]] const Profile& profile() const { return *profile_; }
    /// Index of a CiA 402 object for this axis (6040h → 6840h on AKD2G axis 2).
    [[nodiscard]] std::uint16_t index(std::uint16_t base) const {
        return profile_->axis_index(base, axis_);
    }
    void on_state_change(StateHandler h) { state_handler_ = std::move(h); }
    /// Tells the axis the device's last error code (EMCY or 603Fh), used in messages. On a drive
    /// with per-axis fault lists (AKD2G: the EMCY names no axis, 5004h/5104h do, §5.3.84) a
    /// fault code is checked against this axis's list first: the axis keeps it only if the
    /// drive lists a fault for this axis (0000h and warnings are taken as they come).
    void note_error_code(std::uint16_t code);
    [[nodiscard]] std::uint16_t last_error_code() const { return last_error_code_; }
    /// Called when the drive's fault list attributes a new fault to this axis (after an EMCY or
    /// on entering FAULT), with the drive's fault text.
    void on_fault(FaultHandler h) { fault_handler_ = std::move(h); }
    /// Reads this axis's active faults from the drive's per-axis list (AKD2G 5004h / 5104h
    /// AXIS#.FAULT1..10, up to the first empty entry). Errors: NotSupported (the drive has no
    /// such list), Transport.
    void read_faults(std::function<void(DriveResult<std::vector<AxisFault>>)> done);

    // ---- power state operations (each ends in success or a readable error) --------------------
    /// To OPERATION ENABLED from any state: fault reset if needed, then transitions 2, 3, 4
    /// (or 16 from QUICK STOP ACTIVE).
    void enable(Done done, Duration timeout = Duration::zero());
    /// To READY TO SWITCH ON (shutdown: transitions 2, 6, 8).
    void shutdown(Done done, Duration timeout = Duration::zero());
    /// To SWITCHED ON (switch on 3 / disable operation 5).
    void switch_on(Done done, Duration timeout = Duration::zero());
    /// To SWITCH ON DISABLED (disable voltage: transitions 7, 9, 10, 12).
    void disable(Done done, Duration timeout = Duration::zero());
    /// Quick stop (transitions 11, 7, 10). Completes when the drive has stopped, not when the
    /// ramp starts: in SWITCH ON DISABLED (605Ah 0..4: the drive leaves QUICK STOP ACTIVE by
    /// itself after its ramp) or in QUICK STOP ACTIVE with statusword bit 10 set (605Ah 5..8:
    /// "set when the quick stop is completed and the drive is halted" — DS-BVS §6.2.81, AKD2G
    /// §5.4.2 6041h bit 10, CiA 402). A timeout while the drive still decelerates leaves the quick
    /// stop commanded.
    void quick_stop(Done done, Duration timeout = Duration::zero());
    /// Fault reset (transition 15, rising edge of bit 7): ends in SWITCH ON DISABLED.
    void fault_reset(Done done, Duration timeout = Duration::zero());
    /// Halt (controlword bit 8).
    void set_halt(bool on) { halt_ = on; }
    [[nodiscard]] bool halted() const { return halt_; }
    /// Cancels the running operation (its callback gets DriveErrc::Cancelled).
    void cancel();

    // ---- modes ----------------------------------------------------------------------------------
    /// Reads 6502h to learn the supported modes.
    void discover(Done done);
    [[nodiscard]] std::uint32_t supported_modes() const { return supported_modes_; }
    [[nodiscard]] bool supports_mode(std::int8_t mode) const;
    /// Writes 6060h and waits until 6061h confirms it. Errors: NotSupported, Timeout, Transport.
    void set_mode(std::int8_t mode, Done done, Duration timeout = Duration::zero());
    void set_mode(cia402::Mode mode, Done done, Duration timeout = Duration::zero()) {
        set_mode(static_cast<std::int8_t>(mode), std::move(done), timeout);
    }

    /// Profile position: writes the profile and 607Ah, then the set-point handshake (bit 4 →
    /// ack bit 12 → bit 4 cleared) and waits for target reached (bit 10). Errors: WrongState,
    /// WrongMode, FollowingError (bit 13), Fault, Timeout.
    void move_to(std::int32_t target, MoveOptions options, Done done,
                 Duration timeout = Duration::zero());
    /// Profile velocity: writes 60FFh, done when target reached (bit 10).
    void run_velocity(std::int32_t velocity, Done done, Duration timeout = Duration::zero());
    /// Profile torque: writes 6071h, done when target reached (bit 10).
    void run_torque(std::int16_t torque, Done done, Duration timeout = Duration::zero());
    /// Homing: writes the parameters, starts with bit 4, done on attained (bit 12) + reached
    /// (bit 10); HomingError on bit 13.
    void home(const HomingParams& params, Done done, Duration timeout = Duration::zero());

    /// Cyclic set-points (CSP, CSV, CST, IP): stored and sent with the next cycle.
    void set_target_position(std::int32_t target);
    void set_target_velocity(std::int32_t target);
    void set_target_torque(std::int16_t target);
    /// Interpolated position: 60C1h:1 and "enable ip mode" (bit 4).
    void set_ip_target(std::int32_t target);
    void set_ip_enabled(bool on) { ip_enabled_ = on; }
    /// CSx: statusword bit 12 "drive follows the command value".
    [[nodiscard]] bool following_setpoints() const;
    [[nodiscard]] std::optional<std::int32_t> target_position() const { return target_position_; }

    // ---- actual values (cyclic if mapped) -------------------------------------------------------
    [[nodiscard]] std::optional<std::int32_t> position_actual() const;
    [[nodiscard]] std::optional<std::int32_t> velocity_actual() const;
    [[nodiscard]] std::optional<std::int16_t> torque_actual() const;
    /// The drive's following error actual value (60F4h: position demand − actual), if mapped.
    [[nodiscard]] std::optional<std::int32_t> following_error_actual() const;

    /// The likely cause of being stuck in the current state (for messages), e.g.
    /// "STO active (statusword bit 8)".
    [[nodiscard]] std::string diagnose() const;

private:
    enum class OpKind : std::uint8_t {
        Enable,
        Shutdown,
        SwitchOn,
        Disable,
        QuickStop,
        FaultReset,
        ModeChange,
        Move,
        Velocity,
        Torque,
        Homing
    };
    struct Operation {
        OpKind kind = OpKind::Enable;
        std::string what;
        Done done;
        TimePoint deadline = kNever;
        bool deadline_armed = false;
        Duration timeout{0};
        int step = 0;
        int pending_writes = 0;
        bool write_failed = false;
        std::uint64_t armed_sample = 0;
        std::int8_t mode = 0;
        std::int32_t target = 0;
        MoveOptions move;
        HomingParams homing;
        bool fault_reset_phase = false;
    };

    void start(Operation op);
    void finish(DriveVoid result);
    void fail(DriveErrc code, const std::string& message) { finish(drive_fail(code, message)); }
    void advance(TimePoint now);
    void advance_power(TimePoint now);
    void advance_mode_change();
    void advance_motion();
    bool check_motion_preconditions(cia402::Mode mode);
    void update_status(std::uint16_t sw);
    /// The command that keeps the drive in `s` (EnableOperation for OPERATION ENABLED, ...).
    static cia402::Command hold_command(cia402::State s);
    void write_outputs();
    void poll(TimePoint now);
    void write_object(std::uint16_t index, std::uint8_t sub, Bytes data);
    template <typename T>
    void write_value(std::uint16_t base, std::uint8_t sub, T value) {
        Bytes b(sizeof(T));
        put_le<T>(b.data(), value);
        write_object(index(base), sub, std::move(b));
    }
    void command_for_enable();
    [[nodiscard]] bool cyclic_status() const;
    [[nodiscard]] std::string state_text() const;
    [[nodiscard]] std::string fault_description() const;
    /// Reads the axis's fault list and takes its fault (the one equal to `hint`, else the
    /// first) as this axis's error code; an empty list puts `before` back if `hint` is current.
    void attribute_fault(std::uint16_t hint, std::uint16_t before);

    DriveTransport& transport_;
    const Profile* profile_;
    unsigned axis_;
    std::string name_;
    Duration timeout_;
    Duration poll_period_;

    // process-image handles
    CyclicHandle in_statusword_, in_mode_display_, in_position_, in_velocity_, in_torque_,
        in_following_error_;
    CyclicHandle out_controlword_, out_mode_, out_target_position_, out_target_velocity_,
        out_target_torque_, out_ip_data_;

    // status
    cia402::State state_ = cia402::State::Unknown;
    std::uint16_t statusword_ = 0;
    bool has_status_ = false;
    std::uint64_t status_samples_ = 0;
    std::optional<std::uint64_t> status_received_; ///< input_count() of the last sample
    std::optional<std::int8_t> mode_display_;
    std::optional<std::int32_t> polled_position_;
    std::uint16_t last_error_code_ = 0;
    std::uint32_t supported_modes_ = 0;
    bool modes_discovered_ = false;
    StateHandler state_handler_;
    FaultHandler fault_handler_;
    std::uint16_t reported_fault_ = 0; ///< the last fault given to fault_handler_

    // command
    cia402::Command command_ = cia402::Command::DisableVoltage;
    std::uint16_t mode_bits_ = 0; ///< bits 4, 5, 6, 9
    bool halt_ = false;
    bool fault_reset_bit_ = false;
    bool ip_enabled_ = false;
    std::optional<std::uint16_t> cw_sent_;
    bool cw_write_in_flight_ = false;
    std::optional<std::int8_t> mode_command_;
    bool mode_written_ = false;
    std::optional<std::int32_t> target_position_;
    std::optional<std::int32_t> target_velocity_;
    std::optional<std::int16_t> target_torque_;
    std::optional<std::int32_t> ip_target_;

    // polling
    TimePoint next_poll_ = TimePoint{};
    bool poll_in_flight_ = false;
    TimePoint now_ = TimePoint{};

    std::optional<Operation> op_;
    std::shared_ptr<bool> alive_;
};

} // namespace codrive::drives
