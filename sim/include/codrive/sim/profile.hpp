// SPDX-License-Identifier: Apache-2.0
// What a simulated drive model is: identity, modes, homing methods, option codes, fault codes.
#pragma once

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

/// Vendor behaviour switches and defaults. Everything a manual says differently lives here.
struct SimProfile {
    std::string name; ///< "akd2g", "ds-bvs", "fio"
    std::string vendor_name;
    std::string product_name;
    std::uint32_t device_type = 0x00020192;
    std::uint32_t vendor_id = 0;
    std::uint32_t product_code_1_axis = 0;
    std::uint32_t product_code_2_axes = 0;
    std::uint32_t revision = 0;
    std::string device_name; ///< 1008h
    std::string hw_version;  ///< 1009h
    std::string sw_version;  ///< 100Ah
    unsigned default_axes = 1;
    unsigned max_axes = 1;
    std::uint16_t axis_offset = 0x800; ///< index offset of axis 2 (AKD2G: 6040h → 6840h)
    bool can = true;                   ///< has a CAN interface (FIO is EtherCAT only)

    // Modes.
    std::uint32_t supported_modes = 0;       ///< 6502h
    std::vector<std::int8_t> accepted_modes; ///< values 6060h accepts
    std::int8_t default_mode = 0;
    std::vector<HomingMethod> homing_methods;
    std::int8_t default_homing_method = 0;
    bool homing_moves_by_offset = false;      ///< DS-BVS: move by 607Ch, then position := 0
    bool has_supported_homing_object = false; ///< 60E3h

    // Option codes.
    std::vector<std::int16_t> quick_stop_options;
    std::int16_t quick_stop_default = 2;
    bool has_option_objects = false; ///< 605Bh..605Eh exist
    std::int16_t shutdown_default = 0;
    std::int16_t disable_operation_default = 1;
    std::int16_t halt_default = 1;
    std::int16_t fault_reaction_default = 2;
    bool has_abort_connection = false; ///< 6007h (DS-BVS, FIO)
    std::int16_t abort_connection_default = 0;
    bool quick_stop_ignored_in_pt = false; ///< AKD2G: PT quick stop disables at once

    // Units and defaults (all in the device's own units).
    double counts_per_rev = 65536; ///< position units per motor revolution
    bool velocity_in_rpm = false;  ///< velocity rpm / acceleration rpm/s (else units/s, units/s²)
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

    // Statusword.
    bool sto_bit8 = false; ///< statusword bit 8 = STO active (AKD2G)

    // Faults.
    FaultCode sto_fault;
    FaultCode sto_warning; ///< emcy 0 = no warning code (STO while disabled is silent)
    FaultCode over_current;
    FaultCode following_error;
    FaultCode heartbeat_loss;
    bool heartbeat_loss_is_fault = true; ///< AKD2G F7002; DS-BVS reacts per 1029h/6007h instead
    bool error_register_generic_only = false; ///< AKD2G: only 1001h bit 0 is used
    bool has_error_history_1003 = true;
    bool has_error_history_4080 = false; ///< DS-BVS

    // Communication (CAN).
    bool pdo_cob_id_read_only = false; ///< DS-BVS
    bool tpdo_no_rtr_bit = false;      ///< DS-BVS: TPDO COB-IDs carry bit 30
    std::uint8_t rpdo_default_type = 0xFF;
    std::uint8_t tpdo_default_type = 0xFF;
    bool default_can_maps = false; ///< AKD2G sim choice: RPDO1/2, TPDO1/2 pre-mapped
    std::uint8_t max_mapped_entries = 8;
    bool node_guarding = false;    ///< 100Ch/100Dh
    bool has_sync_objects = false; ///< 1005h/1006h
    bool has_error_behaviour_1029 = false;
    std::uint16_t max_homing_switch_speed = 0;

    [[nodiscard]] const HomingMethod* find_homing(std::int8_t method) const;
    [[nodiscard]] bool accepts_mode(std::int8_t mode) const;
    [[nodiscard]] const FaultCode& code_for(FaultKind k) const;
    /// Position units per velocity unit and second (rpm → counts/s).
    [[nodiscard]] double velocity_scale() const {
        return velocity_in_rpm ? counts_per_rev / 60.0 : 1.0;
    }
};

/// The built-in profiles: "akd2g", "ds-bvs", "fio". Null if unknown.
[[nodiscard]] const SimProfile* find_profile(std::string_view name);
[[nodiscard]] std::vector<const SimProfile*> all_profiles();

} // namespace codrive::sim
