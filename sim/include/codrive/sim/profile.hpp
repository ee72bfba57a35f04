// SPDX-License-Identifier: Apache-2.0
// A simulated drive model: the drives/ profile plus the simulator's own data (unit, motor,
// machine).
#pragma once

#include <codrive/drives/profile.hpp>
#include <codrive/sim/motor_model.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::sim {

/// Faults a simulated axis can suffer (injected or detected).
enum class FaultKind : std::uint8_t {
    Sto,            ///< safe torque off input active
    OverCurrent,    ///< output over-current
    FollowingError, ///< following error beyond 6065h
    HeartbeatLoss,  ///< consumer heartbeat (1016h) expired
    NodeReset,      ///< not a fault: the device resets (boot-up follows)
};
[[nodiscard]] std::string_view to_string(FaultKind k); ///< "sto", "overcurrent", ...
/// Parses "sto", "overcurrent"/"over-current", "following-error"/"ferr", "heartbeat"/"hb-loss",
/// "reset"/"node-reset". False if unknown.
[[nodiscard]] bool parse_fault_kind(std::string_view text, FaultKind& out);

/// One EMCY/603Fh code with its error-register bits and the manual's text.
struct FaultCode {
    std::uint16_t emcy = 0;
    std::uint8_t error_register = 0x01;
    std::string text;
};

/// What a homing method searches for (CiA 402 §6.7 and the vendor tables).
enum class HomingRef : std::uint8_t {
    CurrentPosition, ///< 35/37: no motion
    LimitSwitch,     ///< home on the edge where the limit switch releases
    HomeSwitch,      ///< home on an edge of the (narrow) home switch
    HardStop,        ///< push into a mechanical stop until blocked
    IndexPulse,      ///< next index pulse only
};

/// A homing method as the simulator executes it.
struct HomingMethod {
    std::int8_t method = 0;
    HomingRef ref = HomingRef::CurrentPosition;
    std::int8_t direction = 1; ///< initial search direction
    bool index = false;        ///< finish on the next index pulse after the edge
    /// HomeSwitch: which edge of the switch region is home: -1 lower (negative) edge, +1 upper.
    std::int8_t edge = -1;
    std::string text;
};

/// A simulated drive model: the drive profile (codrive::drives — identity, modes, homing
/// methods, option codes, PDO quirks, EMCY codes and texts, the same data the master uses) plus
/// what only a simulator needs: the values of one simulated unit the profile leaves open,
/// object defaults, the motor and machine, and how each homing method moves that machine.
struct SimProfile {
    const drives::Profile* drive = nullptr; ///< required

    // Identity values of the simulated unit where the profile has none or only a pattern.
    std::string vendor_name;
    std::string product_name;
    /// 1018h:1/:2 of the simulated unit, used only where the drive profile's identity has none
    /// (DS-BVS: the manual documents neither, §6.2.11). AKD2G and FIO take theirs from the
    /// profile, so CAN and EtherCAT simulators report the one identity the master matches.
    std::uint32_t vendor_id = 0;
    std::uint32_t product_code = 0;
    std::uint32_t revision = 0;
    std::string device_name; ///< 1008h
    std::string hw_version;  ///< 1009h
    std::string sw_version;  ///< 100Ah
    unsigned default_axes = 1;
    std::int8_t power_on_mode = 0; ///< 6060h at power-on when the profile documents none

    // Homing: how each of the profile's methods moves the simulated machine.
    std::vector<HomingMethod> homing_behaviour;
    std::int8_t default_homing_method = 0;
    bool homing_moves_by_offset = false;      ///< DS-BVS: move by 607Ch, then position := 0
    bool has_supported_homing_object = false; ///< 60E3h

    // Option-code behaviour the profile's data does not carry.
    bool has_abort_connection = false;     ///< 6007h (DS-BVS, FIO)
    bool quick_stop_ignored_in_pt = false; ///< AKD2G: PT quick stop disables at once

    // Units, motor and machine, object defaults (all in the device's own units).
    double counts_per_rev = 65536; ///< position units per motor revolution
    bool velocity_in_rpm = false;  ///< velocity rpm / acceleration rpm/s (else units/s, units/s²)
    MachineConfig machine;         ///< switches and stops (counts_per_rev is set from above)
    std::uint32_t profile_velocity = 0;
    std::uint32_t profile_acceleration = 0;
    std::uint32_t quick_stop_deceleration = 0;
    std::uint32_t max_profile_velocity = 0; ///< 607Fh (0: object absent)
    std::uint32_t following_error_window = 0;
    std::uint16_t following_error_timeout = 0;
    std::uint32_t position_window = 0; ///< 6067h (AKD2G: SETTLE.P 5016h:1)
    std::uint16_t position_window_time = 0;
    std::uint16_t velocity_window = 0;
    std::uint16_t velocity_window_time = 0;
    std::uint32_t homing_speed_switch = 0;
    std::uint32_t homing_speed_zero = 0;
    std::uint32_t homing_acceleration = 0;
    bool akd2g_objects = false;            ///< 5002h CS.DEC, 5007h STO, 5016h SETTLE, 60C2h
    bool ds_bvs_objects = false;           ///< 6062h, 6067h/6068h, 6080h, 6085h, 6086h, 608Fh
    bool has_interpolation_period = false; ///< 60C2h

    // Which of the profile's EMCY codes the simulator raises for each fault kind.
    std::uint16_t sto_code = 0;
    std::uint16_t sto_warning_code = 0; ///< 0 = no warning (STO while disabled is silent)
    std::uint16_t over_current_code = 0;
    std::uint16_t following_error_code = 0;
    std::uint16_t heartbeat_loss_code = 0;
    bool heartbeat_loss_is_fault = true; ///< AKD2G F7002; DS-BVS reacts per 1029h/6007h instead
    bool error_register_generic_only = false; ///< AKD2G: only 1001h bit 0 is used
    /// The 1003h entry this drive records for an error, on CAN and EtherCAT alike: with an
    /// error-number table (FIO §7.13.3) the number in bits 31..24, the error class in 23..16 and
    /// the code; otherwise the first four EMCY bytes, code and 1001h `reg` (AKD2G, AMB-7).
    [[nodiscard]] std::uint32_t error_history_entry(const FaultCode& code, std::uint8_t reg) const;

    // Communication (CAN) defaults of the simulated unit.
    bool tpdo_no_rtr_bit = false; ///< DS-BVS: TPDO COB-IDs carry bit 30
    std::uint8_t rpdo_default_type = 0xFF;
    std::uint8_t tpdo_default_type = 0xFF;
    bool default_can_maps = false; ///< AKD2G sim choice: the CSP layout pre-mapped per axis
    bool node_guarding = false;    ///< 100Ch/100Dh
    bool has_sync_objects = false; ///< 1005h/1006h

    // ---- from the drive profile -------------------------------------------------------------
    [[nodiscard]] std::string_view name() const { return drive->name; }
    [[nodiscard]] std::uint32_t device_type() const { return drive->identity.device_type; }
    [[nodiscard]] std::uint32_t identity_vendor_id() const {
        return drive->identity.vendor_id != 0 ? drive->identity.vendor_id : vendor_id;
    }
    /// 1018h:2 for a unit with `axes` axes: the profile's product code with the axis count in
    /// its axis bits (AKD2G §2.8), else the simulator's placeholder.
    [[nodiscard]] std::uint32_t identity_product_code(unsigned axes) const;
    [[nodiscard]] unsigned max_axes() const { return drive->max_axes; }
    [[nodiscard]] std::uint16_t axis_offset() const { return drive->axis_offset; }
    [[nodiscard]] bool can() const { return drive->quirks.canopen; }
    [[nodiscard]] std::uint32_t supported_modes() const { return drive->supported_modes; }
    [[nodiscard]] std::int8_t default_mode() const {
        return drive->default_mode != 0 ? drive->default_mode : power_on_mode;
    }
    /// True if 6060h takes `mode`: the drive supports it (profile) and the simulator runs it.
    /// Modes the drive has but the simulator cannot run (DS-BVS -12 CRM and -128 MSM, FIO and
    /// AKD2G -1/-2, FIO vl 2) are refused as a drive refuses an unsupported value (SDO abort
    /// 06090030h), never accepted and silently ignored (docs/conformance.md).
    [[nodiscard]] bool accepts_mode(std::int8_t mode) const {
        return drive->supports_mode(mode) && simulates_mode(mode);
    }
    /// Modes the simulated axis runs: 0 (none), PP, PV, PT, HM, CSP, CSV, CST and the DS-BVS
    /// regulation modes -8/-9/-10 (run as CSP, CSV, CST).
    [[nodiscard]] static bool simulates_mode(std::int8_t mode);
    [[nodiscard]] std::span<const std::int16_t> quick_stop_options() const {
        return drive->quick_stop_options;
    }
    [[nodiscard]] std::int16_t quick_stop_default() const {
        return drive->default_quick_stop_option;
    }
    [[nodiscard]] bool has_option_objects() const {
        return drive->quirks.has_shutdown_option_codes;
    }
    /// Default of a CiA 402 object as the profile documents it (axis 1 index), else `fallback`.
    [[nodiscard]] std::int64_t object_default(std::uint16_t index, std::uint8_t sub,
                                              std::int64_t fallback) const;
    /// The behaviour of a homing method the profile lists, or nullptr (not a method of this
    /// drive, or one the simulator cannot execute).
    [[nodiscard]] const HomingMethod* find_homing(std::int8_t method) const;
    /// The EMCY code for a fault kind with the profile's text and error-register bits.
    [[nodiscard]] FaultCode code_for(FaultKind k) const;
    /// A profile EMCY code with its text and error-register bits (1001h bit 0 always set).
    [[nodiscard]] FaultCode fault(std::uint16_t code) const;
    /// Position units per velocity unit and second (rpm → counts/s).
    [[nodiscard]] double velocity_scale() const {
        return velocity_in_rpm ? counts_per_rev / 60.0 : 1.0;
    }
};

/// The built-in profiles: "akd2g", "ds-bvs", "fio". Null if unknown.
[[nodiscard]] const SimProfile* find_profile(std::string_view name);
[[nodiscard]] std::vector<const SimProfile*> all_profiles();

} // namespace codrive::sim
