// SPDX-License-Identifier: Apache-2.0
// The built-in simulated drive models (AKD2G, DS-BVS, FIO), from the specs in shared/specs.
#include <codrive/sim/profile.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::sim {

std::string_view to_string(FaultKind k) {
    switch (k) {
    case FaultKind::Sto:
        return "sto";
    case FaultKind::OverCurrent:
        return "overcurrent";
    case FaultKind::FollowingError:
        return "following-error";
    case FaultKind::HeartbeatLoss:
        return "heartbeat-loss";
    case FaultKind::NodeReset:
        return "node-reset";
    }
    return "?";
}

bool parse_fault_kind(std::string_view text, FaultKind& out) {
    if (text == "sto") {
        out = FaultKind::Sto;
    } else if (text == "overcurrent" || text == "over-current" || text == "oc") {
        out = FaultKind::OverCurrent;
    } else if (text == "following-error" || text == "ferr" || text == "following") {
        out = FaultKind::FollowingError;
    } else if (text == "heartbeat" || text == "heartbeat-loss" || text == "hb-loss" ||
               text == "hb") {
        out = FaultKind::HeartbeatLoss;
    } else if (text == "reset" || text == "node-reset") {
        out = FaultKind::NodeReset;
    } else {
        return false;
    }
    return true;
}

const HomingMethod* SimProfile::find_homing(std::int8_t method) const {
    const auto& listed = drive->homing_methods;
    if (std::find(listed.begin(), listed.end(), method) == listed.end()) {
        return nullptr;
    }
    auto it = std::find_if(homing_behaviour.begin(), homing_behaviour.end(),
                           [method](const HomingMethod& m) { return m.method == method; });
    return it == homing_behaviour.end() ? nullptr : &*it;
}

std::int64_t SimProfile::object_default(std::uint16_t index, std::uint8_t sub,
                                        std::int64_t fallback) const {
    for (const auto& o : drives::device_objects(*drive, 1)) {
        if (o.index == index && o.subindex == sub) {
            return o.default_value;
        }
    }
    return fallback;
}

bool SimProfile::simulates_mode(std::int8_t mode) {
    switch (mode) {
    case 0:
    case 1:
    case 3:
    case 4:
    case 6:
    case 8:
    case 9:
    case 10:
    case -8:
    case -9:
    case -10:
        return true;
    default:
        return false;
    }
}

std::uint32_t SimProfile::identity_product_code(unsigned axes) const {
    const drives::Identity& id = drive->identity;
    if (id.product_code == 0) {
        return product_code;
    }
    if (id.axes_mask == 0) {
        return id.product_code;
    }
    const unsigned n = std::clamp(axes, 1U, static_cast<unsigned>(drive->max_axes));
    return (id.product_code & ~id.axes_mask) | ((n << id.axes_shift) & id.axes_mask);
}

FaultCode SimProfile::fault(std::uint16_t code) const {
    FaultCode f;
    f.emcy = code;
    f.text = drive->fault_text(code);
    if (f.text.empty()) {
        f.text = fmt::format("error code 0x{:04X}", code);
    }
    const drives::FaultRow* row = drive->fault(code);
    // 1001h bit 0 (generic) is set with every error (CiA 301 §7.5.2.2); AKD2G uses no other.
    // Codes the profile's table does not give a register for get the bit of their CiA 301
    // error class: current, voltage, temperature, communication, manufacturer.
    std::uint8_t bits = row != nullptr ? row->error_register : 0;
    if (bits == 0) {
        switch (code >> 12) {
        case 0x2:
            bits = 0x02;
            break;
        case 0x3:
            bits = 0x04;
            break;
        case 0x4:
            bits = 0x08;
            break;
        case 0xF:
            bits = 0x80;
            break;
        default:
            bits = (code >> 8) == 0x81 ? 0x10 : 0x00;
            break;
        }
    }
    f.error_register =
        static_cast<std::uint8_t>(0x01 | (error_register_generic_only ? 0x00 : bits));
    return f;
}

std::uint32_t SimProfile::error_history_entry(const FaultCode& code, std::uint8_t reg) const {
    if (drive->error_numbers.empty()) {
        return code.emcy | (static_cast<std::uint32_t>(reg) << 16);
    }
    // The error number comes from the drive profile's table (FIO manual §7.13.3, 1003h), the
    // one the master decodes with: the first number the profile pairs with this error code.
    std::uint8_t number = 0;
    for (const drives::ErrorNumberRow& row : drive->error_numbers) {
        if (row.typical_code == code.emcy) {
            number = row.number;
            break;
        }
    }
    const auto error_class = static_cast<std::uint8_t>(code.error_register & 0xFEU);
    return (static_cast<std::uint32_t>(number) << 24) |
           (static_cast<std::uint32_t>(error_class) << 16) | code.emcy;
}

FaultCode SimProfile::code_for(FaultKind k) const {
    switch (k) {
    case FaultKind::Sto:
        return fault(sto_code);
    case FaultKind::OverCurrent:
        return fault(over_current_code);
    case FaultKind::FollowingError:
        return fault(following_error_code);
    case FaultKind::HeartbeatLoss:
    case FaultKind::NodeReset:
        break;
    }
    return fault(heartbeat_loss_code);
}

namespace {

HomingMethod hm(std::int8_t method, HomingRef ref, std::int8_t dir, bool index, std::int8_t edge,
                std::string text) {
    return HomingMethod{method, ref, dir, index, edge, std::move(text)};
}

// Kollmorgen AKD2G, CAN option "C" (akd2g.md; [M] manual, [STD] CiA fill-ins).
SimProfile make_akd2g() {
    SimProfile p;
    p.drive = &drives::akd2g_profile();
    p.vendor_name = "Kollmorgen";
    p.product_name = "AKD2G";
    p.revision = 0x03010000; // byte 3 = FW minor, byte 2 = map revision
    p.device_name = "AKD2G-SPE-6V03D-A1C1-0000";
    p.hw_version = "A";
    p.sw_version = "02-03-01-001 (codrive-sim)";
    p.default_axes = 2;
    p.power_on_mode = 8; // not stated in the manual; CSP is what a CAN master will use
    p.homing_behaviour = {
        hm(-4, HomingRef::HomeSwitch, 1, false, -1,
           "reference switch fast, home on switch slow, positive"),
        hm(-3, HomingRef::HomeSwitch, -1, false, 1,
           "reference switch fast, home on switch slow, negative"),
        hm(-2, HomingRef::HardStop, 1, false, 0, "mechanical stop, positive"),
        hm(-1, HomingRef::HardStop, -1, false, 0, "mechanical stop, negative"),
        hm(1, HomingRef::LimitSwitch, -1, true, 0, "negative limit switch with zeroing"),
        hm(2, HomingRef::LimitSwitch, 1, true, 0, "positive limit switch with zeroing"),
        hm(8, HomingRef::HomeSwitch, 1, true, -1, "reference switch with zeroing, positive"),
        hm(12, HomingRef::HomeSwitch, -1, true, 1, "reference switch with zeroing, negative"),
        hm(17, HomingRef::LimitSwitch, -1, false, 0, "negative limit switch"),
        hm(18, HomingRef::LimitSwitch, 1, false, 0, "positive limit switch (AMB-17)"),
        hm(24, HomingRef::HomeSwitch, 1, false, -1, "reference switch, positive"),
        hm(28, HomingRef::HomeSwitch, -1, false, 1, "reference switch, negative"),
        hm(33, HomingRef::IndexPulse, -1, true, 0, "index pulse, negative"),
        hm(34, HomingRef::IndexPulse, 1, true, 0, "index pulse, positive"),
        hm(35, HomingRef::CurrentPosition, 1, false, 0, "current position"),
    };
    p.default_homing_method = 35;
    p.quick_stop_ignored_in_pt = true;
    p.counts_per_rev = 65536; // 6092h feed 65536/1 (§5.11)
    p.velocity_in_rpm = false;
    p.profile_velocity = 655360;          // 10 rev/s (sim default; manual gives none)
    p.profile_acceleration = 6553600;     // 100 rev/s²
    p.quick_stop_deceleration = 13107200; // AXIS#.CS.DEC (5002h:2)
    p.following_error_window = 262144;    // 4 rev; 0 would switch monitoring off
    p.following_error_timeout = 10;
    p.position_window = 655; // AXIS#.SETTLE.P (5016h:1), ~0.01 rev
    p.position_window_time = 0;
    p.velocity_window = 6553;
    p.velocity_window_time = 10;
    p.homing_speed_switch = 327680; // 5 rev/s
    p.homing_speed_zero = 32768;
    p.homing_acceleration = 6553600;
    p.akd2g_objects = true;
    p.has_interpolation_period = true;
    p.sto_code = 0xFF0B;
    p.sto_warning_code = 0xFF0C;
    p.over_current_code = 0xFF07;
    p.following_error_code = 0x8611;
    p.heartbeat_loss_code = 0x8130;
    p.heartbeat_loss_is_fault = true;
    p.error_register_generic_only = true; // §5.2.2
    p.rpdo_default_type = 0xFF;           // AMB-9
    p.tpdo_default_type = 0xFF;
    p.default_can_maps = true; // AMB-10 suggestion
    p.node_guarding = true;
    p.has_sync_objects = true;
    return p;
}

// DINGS DS-BVS/BVM (ds-bvs.md).
SimProfile make_ds_bvs() {
    SimProfile p;
    p.drive = &drives::ds_bvs_profile();
    p.vendor_name = "DINGS Motion";
    p.product_name = "DS-BVS";
    // Manual §6.2.11 (0x1018) lists vendor ID and product code with no value ("Default Value
    // -"): these are the simulator's placeholders, the only ones, used on CAN and EtherCAT.
    p.vendor_id = 0x00444D53;    // "DMS"
    p.product_code = 0x42565331; // "BVS1"
    p.revision = 0x00010001;
    p.device_name = "DS-BVS";
    p.hw_version = "1.0";
    p.sw_version = "1.1 (codrive-sim)";
    p.default_axes = 1;
    p.homing_behaviour = {
        hm(37, HomingRef::CurrentPosition, 1, false, 0, "actual position"),
        hm(27, HomingRef::HomeSwitch, -1, false, 1, "home switch, negative speed"),
        hm(23, HomingRef::HomeSwitch, 1, false, -1, "home switch, positive speed"),
        hm(18, HomingRef::LimitSwitch, 1, false, 0, "positive limit switch"),
        hm(17, HomingRef::LimitSwitch, -1, false, 0, "negative limit switch"),
        hm(-3, HomingRef::HardStop, 1, false, 0, "current threshold, positive"),
        hm(-4, HomingRef::HardStop, -1, false, 0, "current threshold, negative"),
    };
    p.default_homing_method = 17;
    p.homing_moves_by_offset = true;
    p.has_supported_homing_object = true;
    p.counts_per_rev = 500; // 608Fh:01 default, treated as counts (spec §7)
    // At 500 increments per revolution the default machine (limit switches at ±10 rev) would
    // leave ±5,000 increments of travel and a mechanical stop at 5,250: a 20,000-increment PP
    // move ran into it and "stopped short". The simulated DS-BVS machine is longer.
    p.machine.neg_limit_rev = -100;
    p.machine.pos_limit_rev = 100;
    p.machine.neg_stop_rev = -105;
    p.machine.pos_stop_rev = 105;
    p.velocity_in_rpm = true;
    p.profile_velocity = 1000;
    p.profile_acceleration = 1000;
    p.quick_stop_deceleration = 1000;
    p.max_profile_velocity = 1000;
    p.following_error_window = 100000;
    p.following_error_timeout = 0;
    p.position_window = 5;
    p.position_window_time = 10;
    p.velocity_window = 30;
    p.velocity_window_time = 30;
    p.homing_speed_switch = 100;
    p.homing_speed_zero = 10;
    p.homing_acceleration = 10000;
    p.ds_bvs_objects = true;
    // The manual documents no STO; its emergency input (60FDh bit 3) stands in: generic error.
    p.sto_code = 0x1000;
    p.sto_warning_code = 0;
    p.over_current_code = 0x2310;
    p.following_error_code = 0x8611;
    p.heartbeat_loss_code = 0x8130;
    p.heartbeat_loss_is_fault = false; // reaction per 1029h:01 and 6007h
    p.tpdo_no_rtr_bit = true;
    p.rpdo_default_type = 0xFF;
    p.tpdo_default_type = 0;
    return p;
}

// Kuhnke FIO Drive Control (kuhnke-fio.md), EtherCAT only.
SimProfile make_fio() {
    SimProfile p;
    p.drive = &drives::fio_profile();
    p.vendor_name = "Kendrion Kuhnke";
    p.product_name = "FIO Drive Control";
    p.revision = 0;
    p.device_name = "FIO Drive Control";
    p.hw_version = "1";
    p.sw_version = "V2039 (codrive-sim)";
    p.homing_behaviour = {
        hm(1, HomingRef::LimitSwitch, -1, true, 0, "negative limit switch and index"),
        hm(2, HomingRef::LimitSwitch, 1, true, 0, "positive limit switch and index"),
    };
    // Home switch methods (kuhnke-fio.md §5.5 with CiA 402 positions): 3/4 and 19/20 switch on
    // the positive side, 5/6 and 21/22 on the negative side, 7-14 and 23-30 narrow switch with
    // reversal at a limit switch. The simulated switch is the region [2, 3] rev.
    const auto add = [&p](int m, std::int8_t dir, bool index, std::int8_t edge, const char* text) {
        p.homing_behaviour.push_back(
            hm(static_cast<std::int8_t>(m), HomingRef::HomeSwitch, dir, index, edge, text));
    };
    for (int m : {3, 4}) {
        add(m, 1, true, -1, "home switch (positive side) and index");
    }
    for (int m : {5, 6}) {
        add(m, -1, true, 1, "home switch (negative side) and index");
    }
    for (int m : {7, 8}) {
        add(m, 1, true, -1, "home switch, reversal at LS+, index");
    }
    for (int m : {9, 10}) {
        add(m, 1, true, 1, "home switch, reversal at LS+, index");
    }
    for (int m : {11, 12}) {
        add(m, -1, true, 1, "home switch, reversal at LS-, index");
    }
    for (int m : {13, 14}) {
        add(m, -1, true, -1, "home switch, reversal at LS-, index");
    }
    p.homing_behaviour.push_back(
        hm(17, HomingRef::LimitSwitch, -1, false, 0, "negative limit switch"));
    p.homing_behaviour.push_back(
        hm(18, HomingRef::LimitSwitch, 1, false, 0, "positive limit switch"));
    for (int m : {19, 20}) {
        add(m, 1, false, -1, "home switch (positive side)");
    }
    for (int m : {21, 22}) {
        add(m, -1, false, 1, "home switch (negative side)");
    }
    for (int m : {23, 24}) {
        add(m, 1, false, -1, "home switch, reversal at LS+");
    }
    for (int m : {25, 26}) {
        add(m, 1, false, 1, "home switch, reversal at LS+");
    }
    for (int m : {27, 28}) {
        add(m, -1, false, 1, "home switch, reversal at LS-");
    }
    for (int m : {29, 30}) {
        add(m, -1, false, -1, "home switch, reversal at LS-");
    }
    p.homing_behaviour.push_back(
        hm(33, HomingRef::IndexPulse, -1, true, 0, "next index pulse, negative"));
    p.homing_behaviour.push_back(
        hm(34, HomingRef::IndexPulse, 1, true, 0, "next index pulse, positive"));
    p.homing_behaviour.push_back(
        hm(35, HomingRef::CurrentPosition, 1, false, 0, "current position"));
    // Homing on block: the mechanical block replaces the limit switch. -1/-2 and -17/-18 home
    // on the block itself; -7..-14 and -23..-30 search the home switch and reverse at the block
    // (the simulated stops lie just beyond the limit switches, so they behave as 7..14, 23..30).
    p.homing_behaviour.push_back(hm(-1, HomingRef::HardStop, -1, false, 0, "block, negative"));
    p.homing_behaviour.push_back(hm(-2, HomingRef::HardStop, 1, false, 0, "block, positive"));
    p.homing_behaviour.push_back(
        hm(-17, HomingRef::HardStop, -1, false, 0, "block, negative, no index"));
    p.homing_behaviour.push_back(
        hm(-18, HomingRef::HardStop, 1, false, 0, "block, positive, no index"));
    const std::size_t switch_methods = p.homing_behaviour.size();
    for (std::size_t i = 0; i < switch_methods; ++i) {
        const HomingMethod m = p.homing_behaviour[i];
        if (m.ref == HomingRef::HomeSwitch &&
            ((m.method >= 7 && m.method <= 14) || (m.method >= 23 && m.method <= 30))) {
            HomingMethod b = m;
            b.method = static_cast<std::int8_t>(-m.method);
            b.text = m.text + " (block instead of limit switch)";
            p.homing_behaviour.push_back(b);
        }
    }
    p.default_homing_method = 35;
    p.counts_per_rev = 3600; // 60A8h default: 0.1 degree
    p.velocity_in_rpm = true;
    p.profile_velocity = 500;
    p.profile_acceleration = 500;
    p.quick_stop_deceleration = 5000;
    p.max_profile_velocity = 30000;
    p.following_error_window = 256;
    p.following_error_timeout = 100;
    p.position_window = 10;
    p.position_window_time = 100;
    p.velocity_window = 0;
    p.velocity_window_time = 0;
    p.homing_speed_switch = 50;
    p.homing_speed_zero = 10;
    p.homing_acceleration = 500;
    p.ds_bvs_objects = true; // 6062h, 6067h/6068h, 6080h, 6085h, 6086h, 608Fh exist too
    p.has_interpolation_period = true;
    p.sto_code = 0x1000;
    p.over_current_code = 0x2300;
    p.following_error_code = 0x8611;
    p.heartbeat_loss_code = 0x8000;
    p.heartbeat_loss_is_fault = false;
    return p;
}

// A CiA 402 drive with no vendor behind it (the EtherCAT simulator's "generic" slave, issue 20):
// the master's generic profile, homing on the current position, counts and counts/s.
SimProfile make_generic() {
    SimProfile p;
    p.drive = &drives::generic_profile();
    p.vendor_name = "codrive simulator";
    p.product_name = "Generic 402 drive";
    p.device_name = "Generic 402 drive";
    p.hw_version = "1";
    p.sw_version = "codrive-sim";
    p.homing_behaviour = {hm(35, HomingRef::CurrentPosition, 1, false, 0, "current position"),
                          hm(37, HomingRef::CurrentPosition, 1, false, 0, "current position")};
    p.default_homing_method = 35;
    // Simulator choices (no manual): 4096 counts per revolution, velocities in counts/s, a
    // profile of 100 rev/s² that a PP move of a few revolutions ends within a second.
    p.counts_per_rev = 4096;
    p.profile_velocity = 40960;
    p.profile_acceleration = 409600;
    p.quick_stop_deceleration = 819200;
    p.max_profile_velocity = 409600;
    p.ds_bvs_objects = true; // the CiA 402 position window, encoder and limit objects too
    p.position_window = 10;
    p.position_window_time = 10;
    p.following_error_window = 100000;
    return p;
}

} // namespace

const SimProfile* find_profile(std::string_view name) {
    static const SimProfile akd2g = make_akd2g();
    static const SimProfile ds_bvs = make_ds_bvs();
    static const SimProfile fio = make_fio();
    static const SimProfile generic = make_generic();
    if (name == "generic") {
        return &generic;
    }
    if (name == "akd2g" || name == "AKD2G") {
        return &akd2g;
    }
    if (name == "ds-bvs" || name == "dsbvs" || name == "DS-BVS") {
        return &ds_bvs;
    }
    if (name == "fio" || name == "kuhnke-fio") {
        return &fio;
    }
    return nullptr;
}

std::vector<const SimProfile*> all_profiles() {
    return {find_profile("akd2g"), find_profile("ds-bvs"), find_profile("fio")};
}

} // namespace codrive::sim
