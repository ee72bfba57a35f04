// SPDX-License-Identifier: Apache-2.0
// Simulated EtherCAT drives: object dictionaries of FIO, AKD2G and DS-BVS (identity, PDO maps and
// 1C12h/1C13h defaults from the specs) with a small CiA 402 device model behind them.
#include <codrive/sim/ecat/drive_profiles.hpp>

#include "error_history.hpp"
#include "parameter_store.hpp"

#include <codrive/sim/drive_core.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>

#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/sii.hpp>

#include <cmath>
#include <cstdlib>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

namespace {

struct PdoDef {
    std::uint16_t index;
    std::vector<std::uint32_t> entries;
    bool fixed = false; ///< read-only mapping (DS-BVS 1604h.., AKD2G 17xxh/1Bxxh)
};

/// The EtherCAT side of a simulated drive: ESC buffers and PDO maps. The identity (1018h and
/// SII) is filled in by make_drive_slave() from the SimProfile, the one the CAN simulator uses.
struct DriveDef {
    std::string name;
    std::string_view profile; ///< SimProfile name
    std::uint32_t vendor = 0;
    std::uint32_t product = 0;
    std::uint32_t revision = 0;
    std::uint16_t sm2 = 0x1100;
    std::uint16_t sm3 = 0x1180;
    std::vector<PdoDef> rx;
    std::vector<PdoDef> tx;
    std::vector<std::uint16_t> rx_assign;
    std::vector<std::uint16_t> tx_assign;
    std::uint8_t assign_max = 4;
    /// 1C32h/1C33h: highest sub-index reported, entries present (1..n) and the default cycle
    /// time. Drives whose manual is silent keep sub 1..2 and 1 ms.
    std::uint8_t sm_out_highest = 2;
    std::uint8_t sm_in_highest = 2;
    std::uint8_t sm_entries = 2;
    std::uint32_t sm_cycle_time = 1'000'000;
    /// When set: 1C32h/1C33h sub-indices 1.. exactly as a manual lists them (the AKD2G's).
    struct SyncSub {
        std::uint8_t sub;
        const char* name;
        bool u16;
        bool writable;
        std::uint32_t value;
    };
    std::vector<SyncSub> sm_subs;
};

// FIO: kuhnke-fio.md §1.4 — Rx 1600h (6040, 607A, 3202, 6060 = 11 bytes), Tx 1A00h (6041, 6064,
// 6061 = 7 bytes); 1C12:01 = 1600h, 1C13:01 = 1A00h.
DriveDef fio_def() {
    DriveDef d;
    d.name = "FIO Drive Control";
    d.profile = "fio";
    // The default maps are the profile's (one table, §7.13.11-§7.13.18).
    for (const drives::DefaultPdoMap& m : drives::fio_profile().default_pdo_maps) {
        PdoDef def{m.index, std::vector<std::uint32_t>(m.entries.begin(), m.entries.end())};
        (m.index < 0x1A00 ? d.rx : d.tx).push_back(std::move(def));
    }
    d.rx_assign = {0x1600};
    d.tx_assign = {0x1A00};
    // Manual §7.13.22/§7.13.23: 1C32h sub 0 = 05h, 1C33h sub 0 = 03h; both describe sub 1
    // (sync type 0), 2 (cycle time 0) and 3 (shift time 0) only: 1C32h sub 4/5 are undocumented.
    d.sm_out_highest = 5;
    d.sm_in_highest = 3;
    d.sm_entries = 3;
    d.sm_cycle_time = 0;
    return d;
}

// AKD2G: akd2g.md §3.3 — 1600h = 6040h + 607Ah (6 bytes), 1A00h = 6041h + 6064h + 60F4h
// (10 bytes); fixed CSP maps 1700h/1B00h; ESC buffers ProOut 0x1100, ProIn 0x1140 (§3.4).
DriveDef akd2g_def() {
    DriveDef d;
    d.name = "AKD2G";
    d.profile = "akd2g";
    d.sm2 = 0x1100;
    d.sm3 = 0x1140;
    d.rx = {{0x1600, {0x60400010, 0x607A0020}},
            {0x1601, {}},
            {0x1602, {}},
            {0x1603, {}},
            {0x1700, {0x60400010, 0x607A0020}, true},
            {0x1701, {0x60400010, 0x60FF0020}, true}};
    d.tx = {{0x1A00, {0x60410010, 0x60640020, 0x60F40020}},
            {0x1A01, {}},
            {0x1A02, {}},
            {0x1A03, {}},
            {0x1B00, {0x60410010, 0x60640020, 0x60F40020}, true},
            {0x1B01, {0x60410010, 0x60640020, 0x606C0020}, true}};
    d.rx_assign = {0x1600};
    d.tx_assign = {0x1A00};
    d.assign_max = 10;
    // Manual §5.2.50/§5.2.51: 1C32h/1C33h subs 1..0Ch, sync type and cycle time read-only (the
    // drive derives them from SYNC0 or 60C1h), shift time and get cycle time read/write;
    // minimum cycle time 250000 ns; sync modes supported: free run, synchronous, DC SYNC0,
    // shift with local timer = 0027h. Values the manual does not give (sync type, cycle, shift,
    // calc/copy and delay times, counters) start at 0 (docs/conformance.md).
    d.sm_out_highest = 0x0C;
    d.sm_in_highest = 0x0C;
    d.sm_subs = {{1, "Synchronization type", true, false, 0},
                 {2, "Cycle time", false, false, 0},
                 {3, "Shift time", false, true, 0},
                 {4, "Sync modes supported", true, false, 0x0027},
                 {5, "Minimum cycle time", false, false, 250'000},
                 {6, "Calc and copy time", false, false, 0},
                 {7, "Minimum delay time", false, false, 0},
                 {8, "Get cycle time", true, true, 0},
                 {9, "Delay time", false, false, 0},
                 {0x0A, "Sync0 Cycle Time", false, false, 0},
                 {0x0B, "SM-Event Missed", true, false, 0},
                 {0x0C, "Cycle time too small", true, false, 0}};
    return d;
}

// A CiA 402 drive codrive has never seen (issue 20): an unknown identity, the generic CiA 402
// objects, free maps 1600h/1A00h assigned by default with controlword/mode/target position and
// statusword/mode display/position (ETG.6010 §4 objects, no vendor manual behind it).
DriveDef generic_def(bool assigned) {
    DriveDef d;
    d.name = assigned ? "Generic 402 drive" : "Generic 402 drive (no PDOs)";
    d.profile = "generic";
    d.vendor = 0x00000F0E;
    d.product = assigned ? 0x00402001 : 0x00402002;
    d.revision = 1;
    d.rx = {{0x1600, {0x60400010, 0x60600008, 0x607A0020}}, {0x1601, {}}};
    d.tx = {{0x1A00, {0x60410010, 0x60610008, 0x60640020}}, {0x1A01, {}}};
    if (assigned) {
        d.rx_assign = {0x1600};
        d.tx_assign = {0x1A00};
    }
    d.assign_max = 2;
    return d;
}

// DS-BVS: ds-bvs.md §1.3/§6 — free maps 1600h..1603h/1A00h..1A03h empty, fixed 1604h..1609h /
// 1A04h..1A09h; defaults 1C12:01 = 1608h (17 bytes), 1C13:01 = 1A08h (17 bytes).
DriveDef dsbvs_def() {
    DriveDef d;
    d.name = "DS-BVS";
    d.profile = "ds-bvs";
    d.rx = {
        {0x1600, {}},
        {0x1601, {}},
        {0x1602, {}},
        {0x1603, {}},
        {0x1605, {0x60400010, 0x607A0020, 0x60B20010, 0x60FE0120}, true},
        {0x1606, {0x60400010, 0x60FF0020, 0x60FE0120}, true},
        {0x1607, {0x60400010, 0x60710010, 0x60FE0120}, true},
        {0x1608, {0x60400010, 0x607A0020, 0x60FF0020, 0x60710010, 0x60FE0120, 0x60600008}, true}};
    d.tx = {
        {0x1A00, {}},
        {0x1A01, {}},
        {0x1A02, {}},
        {0x1A03, {}},
        {0x1A04, {0x60410010, 0x60640020, 0x60FD0020}, true},
        {0x1A05, {0x60410010, 0x60640020, 0x606C0020, 0x60FD0020}, true},
        {0x1A06, {0x60410010, 0x60640020, 0x606C0020, 0x60770010, 0x60FD0020}, true},
        {0x1A08, {0x60410010, 0x60640020, 0x606C0020, 0x60770010, 0x60FD0020, 0x60610008}, true}};
    d.rx_assign = {0x1608};
    d.tx_assign = {0x1A08};
    d.assign_max = 1;
    return d;
}

Value u8(std::uint8_t v) {
    return Value(DataType::Unsigned8, {v});
}
Value u16(std::uint16_t v) {
    std::vector<std::uint8_t> b(2);
    put_le<std::uint16_t>(b.data(), v);
    return Value(DataType::Unsigned16, b);
}
Value u32(std::uint32_t v) {
    std::vector<std::uint8_t> b(4);
    put_le<std::uint32_t>(b.data(), v);
    return Value(DataType::Unsigned32, b);
}
Value typed(DataType t, std::int64_t v) {
    std::vector<std::uint8_t> b(data_type_size(t));
    put_le_n(b.data(), static_cast<std::uint64_t>(v), b.size());
    return Value(t, b);
}

/// CiA 402 device model: the power state machine (IEC 61800-7-201 §6.2) driven by 6040h, and a
/// position/velocity model for CSP (8), CSV (9), PP (1) and PV (3).
class Cia402Device final : public EcatApplication {
public:
    /// With a SimProfile the transport-independent DriveCore (sim/drive_core.hpp) serves the
    /// CiA 402 objects and behaviour; without one a minimal built-in state machine does.
    Cia402Device(const DriveDef& def, std::uint32_t serial, const SimProfile* profile) {
        if (profile != nullptr) {
            core_ = std::make_unique<DriveCore>(od_, *profile, 0);
            core_->set_event_handler([this, profile](const AxisEvent& e) {
                if (e.kind == AxisEvent::Kind::FaultRaised) {
                    push_error_history(od_, 0x1003, profile->error_history_entry(e.code));
                    emcy::EmcyMessage m;
                    m.error_code = e.code.emcy;
                    m.error_register = e.code.error_register;
                    emergencies_.push_back(m);
                } else if (e.kind == AxisEvent::Kind::FaultsCleared) {
                    emergencies_.push_back(emcy::EmcyMessage{});
                }
            });
            core_->power_on();
        }
        // 1000h as the master-side profile expects it (FIO: servo + stepper 0x00060192), so
        // drives::match_identity() finds the same profile over CoE as the drive would give.
        if (profile != nullptr && profile->drive != nullptr &&
            profile->drive->identity.device_type != 0) {
            device_type_ = profile->drive->identity.device_type;
        }
        build(def, serial, profile);
        if (profile != nullptr && profile->has_error_history_1003) {
            od_.insert(error_history_object(0x1003, "Pre-defined error field", "Number of errors",
                                            "Standard error field", DataType::Unsigned32,
                                            profile->drive->error_history_depth));
        }
        if (profile != nullptr && profile->drive != nullptr) {
            install_store(*profile->drive);
        }
    }
    [[nodiscard]] bool uses_drive_core() const { return core_ != nullptr; }

    bool take_restart() override {
        if (!restart_due_) {
            return false;
        }
        // Power cycle: the saved values come back and the drive starts over.
        restart_due_ = false;
        restart_at_.reset();
        store_->load(false);
        if (core_) {
            core_->power_on();
        }
        return true;
    }

    ObjectDictionary& od() override { return od_; }

    void step(TimePoint now) override {
        if (restart_at_ && now >= *restart_at_) {
            restart_due_ = true;
        }
        if (last_ == TimePoint{}) {
            last_ = now;
            return;
        }
        double dt = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        if (dt <= 0 || dt > 1.0) {
            return;
        }
        if (core_) {
            // DriveCore runs in fixed 1 ms steps, as in the CAN simulator (SimDeviceConfig::step).
            // Stepping it by the gaps between frames instead (tens of µs between the frames of
            // one cycle, then a whole period) made the reported 606Ch the speed over the last
            // tiny step — about 82 % of the true speed — so PV never reached its window.
            constexpr double kStep = 0.001;
            pending_ += dt;
            while (pending_ >= kStep) {
                core_->step(kStep);
                pending_ -= kStep;
            }
            return;
        }
        const auto mode = od_.get<std::int8_t>(0x6060, 0).value_or(0);
        od_.set<std::int8_t>(0x6061, 0, mode);
        auto pos = static_cast<double>(od_.get<std::int32_t>(0x6064, 0).value_or(0));
        double vel = 0;
        if (state_ == State::OperationEnabled) {
            const auto target = static_cast<double>(od_.get<std::int32_t>(0x607A, 0).value_or(0));
            if (mode == 8) {
                vel = (target - pos) / dt;
                pos = target;
            } else if (mode == 9 || mode == 3) {
                vel = static_cast<double>(od_.get<std::int32_t>(0x60FF, 0).value_or(0));
                pos += vel * dt;
            } else if (mode == 1) {
                const double vmax = 100000.0;
                const double step = std::min(std::abs(target - pos), vmax * dt);
                vel = target > pos ? vmax : -vmax;
                pos += target > pos ? step : -step;
            }
        }
        od_.set<std::int32_t>(0x6064, 0, static_cast<std::int32_t>(std::lround(pos)));
        od_.set<std::int32_t>(0x606C, 0, static_cast<std::int32_t>(std::lround(vel)));
        update_statusword();
    }

    void on_state_change(AlState from, AlState to) override {
        esm_ = to;
        if (has_slave_status_) {
            // FIO 2110h (§7.13.51): the ECAT bus status follows the ESM; bit 4 = active error.
            const auto error = od_.get<std::uint8_t>(0x1001, 0).value_or(0) != 0;
            od_.set<std::uint16_t>(0x2110, 0,
                                   static_cast<std::uint16_t>((static_cast<unsigned>(to) & 0x0FU) |
                                                              (error ? 0x10U : 0U)));
        }
        // Leaving OP (a master's request or the SM watchdog: the master is gone) means the
        // outputs are no longer valid (ETG.1000.6 §6.4.2): the drive applies its abort
        // connection option 6007h (FIO §7.13.77: default -1, clear the PDOs and coast). A
        // profile without 6007h (AKD2G) disables the voltage.
        if (core_) {
            core_->set_fieldbus_synchronised(to == AlState::Op);
            if (from == AlState::Op) {
                core_->abort_connection(od_.get<std::int16_t>(0x6007, 0).value_or(2));
            }
            return;
        }
        if (from == AlState::Op && state_ == State::OperationEnabled) {
            state_ = State::SwitchOnDisabled;
            update_statusword();
        }
        (void)to;
    }

    void on_outputs(TimePoint /*now*/) override {}

    std::vector<emcy::EmcyMessage> take_emergencies() override {
        return std::exchange(emergencies_, {});
    }

    void raise_fault(std::uint16_t code) {
        if (core_) {
            core_->raise_fault(FaultCode{code, 0x01, "injected fault"});
            return;
        }
        state_ = State::Fault;
        od_.set<std::uint16_t>(0x603F, 0, code);
        od_.set<std::uint8_t>(0x1001, 0, 0x01);
        emcy::EmcyMessage m;
        m.error_code = code;
        m.error_register = 0x01;
        emergencies_.push_back(m);
        update_statusword();
    }

private:
    enum class State {
        SwitchOnDisabled,
        ReadyToSwitchOn,
        SwitchedOn,
        OperationEnabled,
        QuickStop,
        Fault
    };

    void on_controlword(std::uint16_t cw) {
        const bool reset_edge = (cw & 0x80) != 0 && (last_cw_ & 0x80) == 0;
        last_cw_ = cw;
        if (state_ == State::Fault) {
            if (reset_edge) {
                state_ = State::SwitchOnDisabled;
                od_.set<std::uint16_t>(0x603F, 0, 0);
                od_.set<std::uint8_t>(0x1001, 0, 0);
                emergencies_.push_back(emcy::EmcyMessage{}); // 0000h: error reset
            }
        } else if ((cw & 0x02) == 0) {
            state_ = State::SwitchOnDisabled; // disable voltage
        } else if ((cw & 0x06) == 0x02) {
            state_ = state_ == State::OperationEnabled ? State::QuickStop : State::SwitchOnDisabled;
        } else if ((cw & 0x0F) == 0x06) {
            if (state_ != State::QuickStop) {
                state_ = State::ReadyToSwitchOn;
            }
        } else if ((cw & 0x0F) == 0x07) {
            if (state_ == State::ReadyToSwitchOn || state_ == State::OperationEnabled) {
                state_ = State::SwitchedOn;
            }
        } else if ((cw & 0x0F) == 0x0F) {
            if (state_ == State::SwitchedOn || state_ == State::ReadyToSwitchOn ||
                state_ == State::QuickStop) {
                state_ = State::OperationEnabled;
                // CSP must not jump: the target starts at the actual position.
                od_.set<std::int32_t>(0x607A, 0, od_.get<std::int32_t>(0x6064, 0).value_or(0));
            }
        }
        update_statusword();
    }

    void update_statusword() {
        std::uint16_t sw = 0;
        switch (state_) {
        case State::SwitchOnDisabled:
            sw = 0x0040;
            break;
        case State::ReadyToSwitchOn:
            sw = 0x0021;
            break;
        case State::SwitchedOn:
            sw = 0x0033;
            break;
        case State::OperationEnabled:
            sw = 0x0037;
            break;
        case State::QuickStop:
            sw = 0x0017;
            break;
        case State::Fault:
            sw = 0x0008;
            break;
        }
        sw |= 0x0200; // remote
        const auto target = od_.get<std::int32_t>(0x607A, 0).value_or(0);
        if (state_ == State::OperationEnabled &&
            target == od_.get<std::int32_t>(0x6064, 0).value_or(0)) {
            sw |= 0x0400; // target reached
        }
        // Profile position (IEC 61800-7-201 §6.3.4): set-point acknowledge (bit 12) answers
        // new set-point (controlword bit 4) while the master holds it.
        if (state_ == State::OperationEnabled && od_.get<std::int8_t>(0x6060, 0).value_or(0) == 1 &&
            (od_.get<std::uint16_t>(0x6040, 0).value_or(0) & 0x0010U) != 0) {
            sw |= 0x1000;
        }
        od_.set<std::uint16_t>(0x6041, 0, sw);
    }

    void build(const DriveDef& def, std::uint32_t serial, const SimProfile* profile) {
        od_.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro, u32(device_type_));
        od_.add_var(0x1001, "Error register", DataType::Unsigned8, Access::Ro, u8(0), true);
        od_.add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
                    Value::from_string(def.name));
        od_.add_var(0x1009, "Manufacturer hardware version", DataType::VisibleString, Access::Const,
                    Value::from_string("sim-1"));
        od_.add_var(0x100A, "Manufacturer software version", DataType::VisibleString, Access::Const,
                    Value::from_string("codrive-ecat-sim 0.1"));
        od_.add_sub(0x1018,
                    SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Ro, u8(4)),
                    "Identity object");
        od_.add_sub(0x1018, SubObject::make(1, "Vendor-ID", DataType::Unsigned32, Access::Ro,
                                            u32(def.vendor)));
        od_.add_sub(0x1018, SubObject::make(2, "Product code", DataType::Unsigned32, Access::Ro,
                                            u32(def.product)));
        od_.add_sub(0x1018, SubObject::make(3, "Revision number", DataType::Unsigned32, Access::Ro,
                                            u32(def.revision)));
        od_.add_sub(0x1018, SubObject::make(4, "Serial number", DataType::Unsigned32, Access::Ro,
                                            u32(serial)));
        const auto add_pdo = [&](const PdoDef& p, bool rx) {
            const std::string name = rx ? "RxPDO mapping" : "TxPDO mapping";
            const Access a = p.fixed ? Access::Ro : Access::Rw;
            od_.add_sub(p.index,
                        SubObject::make(0, "Number of entries", DataType::Unsigned8, a,
                                        u8(static_cast<std::uint8_t>(p.entries.size()))),
                        name);
            const std::size_t slots = p.fixed ? p.entries.size() : 8;
            for (std::size_t i = 0; i < slots; ++i) {
                od_.add_sub(p.index, SubObject::make(static_cast<std::uint8_t>(i + 1),
                                                     "Mapping entry " + std::to_string(i + 1),
                                                     DataType::Unsigned32, a,
                                                     u32(i < p.entries.size() ? p.entries[i] : 0)));
            }
            od_.find(p.index)->code = ObjectCode::Record;
        };
        for (const auto& p : def.rx) {
            add_pdo(p, true);
        }
        for (const auto& p : def.tx) {
            add_pdo(p, false);
        }
        const auto add_assign = [&](std::uint16_t index, const std::vector<std::uint16_t>& pdos,
                                    const char* name) {
            od_.add_sub(index,
                        SubObject::make(0, "Number of assigned PDOs", DataType::Unsigned8,
                                        Access::Rw, u8(static_cast<std::uint8_t>(pdos.size()))),
                        name);
            for (std::uint8_t i = 0; i < def.assign_max; ++i) {
                od_.add_sub(index,
                            SubObject::make(static_cast<std::uint8_t>(i + 1),
                                            "PDO " + std::to_string(i + 1), DataType::Unsigned16,
                                            Access::Rw, u16(i < pdos.size() ? pdos[i] : 0)));
            }
            od_.find(index)->code = ObjectCode::Array;
        };
        add_assign(0x1C12, def.rx_assign, "Sync manager 2 PDO assignment");
        add_assign(0x1C13, def.tx_assign, "Sync manager 3 PDO assignment");
        od_.add_sub(
            0x1C00,
            SubObject::make(0, "Number of sync managers", DataType::Unsigned8, Access::Ro, u8(4)),
            "Sync manager communication type");
        for (std::uint8_t i = 0; i < 4; ++i) {
            od_.add_sub(0x1C00, SubObject::make(static_cast<std::uint8_t>(i + 1),
                                                "Communication type SM" + std::to_string(i),
                                                DataType::Unsigned8, Access::Ro,
                                                u8(static_cast<std::uint8_t>(i + 1))));
        }
        od_.find(0x1C00)->code = ObjectCode::Array;
        for (std::uint16_t idx : {std::uint16_t{0x1C32}, std::uint16_t{0x1C33}}) {
            const bool out = idx == 0x1C32;
            od_.add_sub(idx,
                        SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8,
                                        Access::Ro,
                                        u8(out ? def.sm_out_highest : def.sm_in_highest)),
                        out ? "Output sync manager parameter" : "Input sync manager parameter");
            if (!def.sm_subs.empty()) {
                for (const auto& ss : def.sm_subs) {
                    od_.add_sub(
                        idx, SubObject::make(ss.sub, ss.name,
                                             ss.u16 ? DataType::Unsigned16 : DataType::Unsigned32,
                                             ss.writable ? Access::Rw : Access::Ro,
                                             ss.u16 ? u16(static_cast<std::uint16_t>(ss.value))
                                                    : u32(ss.value)));
                }
                continue;
            }
            od_.add_sub(idx, SubObject::make(1, "Synchronization type", DataType::Unsigned16,
                                             Access::Rw, u16(0)));
            od_.add_sub(idx, SubObject::make(2, "Cycle time", DataType::Unsigned32, Access::Rw,
                                             u32(def.sm_cycle_time)));
            if (def.sm_entries >= 3) {
                od_.add_sub(idx, SubObject::make(3, "Shift time", DataType::Unsigned32, Access::Rw,
                                                 u32(0)));
            }
        }
        // CiA 402 objects (mappable ones flagged): DriveCore installs its own; the rest fill in.
        // Objects the drive profile says the drive lacks (AKD2G 603Fh, §5.6) stay absent.
        const auto add_var = [this, profile](std::uint16_t index, const char* n, DataType t,
                                             Access a, Value v, bool map) {
            if (od_.find(index) == nullptr &&
                (profile == nullptr || profile->drive->has_object(index))) {
                od_.add_var(index, n, t, a, std::move(v), map);
            }
        };
        add_var(0x603F, "Error code", DataType::Unsigned16, Access::Ro, u16(0), true);
        add_var(0x6040, "Controlword", DataType::Unsigned16, Access::Rww, u16(0), true);
        add_var(0x6041, "Statusword", DataType::Unsigned16, Access::Rwr, u16(0x0240), true);
        add_var(0x6060, "Modes of operation", DataType::Integer8, Access::Rww,
                typed(DataType::Integer8, 8), true);
        add_var(0x6061, "Modes of operation display", DataType::Integer8, Access::Rwr,
                typed(DataType::Integer8, 8), true);
        add_var(0x6064, "Position actual value", DataType::Integer32, Access::Rwr,
                typed(DataType::Integer32, 0), true);
        add_var(0x606C, "Velocity actual value", DataType::Integer32, Access::Rwr,
                typed(DataType::Integer32, 0), true);
        add_var(0x6071, "Target torque", DataType::Integer16, Access::Rww,
                typed(DataType::Integer16, 0), true);
        add_var(0x6077, "Torque actual value", DataType::Integer16, Access::Rwr,
                typed(DataType::Integer16, 0), true);
        add_var(0x607A, "Target position", DataType::Integer32, Access::Rww,
                typed(DataType::Integer32, 0), true);
        add_var(0x60B2, "Torque offset", DataType::Integer16, Access::Rww,
                typed(DataType::Integer16, 0), true);
        add_var(0x60F4, "Following error actual value", DataType::Integer32, Access::Rwr,
                typed(DataType::Integer32, 0), true);
        add_var(0x60FD, "Digital inputs", DataType::Unsigned32, Access::Rwr, u32(0), true);
        od_.add_sub(0x60FE,
                    SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Ro, u8(1)),
                    "Digital outputs");
        od_.add_sub(0x60FE, SubObject::make(1, "Physical outputs", DataType::Unsigned32,
                                            Access::Rww, u32(0), true));
        add_var(0x60FF, "Target velocity", DataType::Integer32, Access::Rww,
                typed(DataType::Integer32, 0), true);
        add_var(0x6502, "Supported drive modes", DataType::Unsigned32, Access::Ro, u32(0x000003A5),
                false);
        if (def.profile == "fio") {
            // §7.13.52: 3202h default 00000000h (the profile holds it; DriveCore installs it).
            add_var(0x3202, "Motor drive submode select", DataType::Unsigned32, Access::Rww, u32(0),
                    true);
            // §7.13.51: 2110h bits 3..0 the EtherCAT state (1 INIT, 2 PREOP, 3 BOOT, 4 SAFEOP,
            // 8 OP), bit 4 ERR; default 0000h before the ESM runs. on_state_change() keeps it.
            od_.add_var(0x2110, "EtherCAT slave status", DataType::Unsigned16, Access::Ro,
                        u16(0x0000));
            has_slave_status_ = true;
        }
        if (def.profile == "akd2g" && od_.find(0x2F00) == nullptr) {
            od_.add_sub(
                0x2F00,
                SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Ro, u8(5)),
                "Firmware");
            od_.add_sub(0x2F00,
                        SubObject::make(1, "Major", DataType::Unsigned32, Access::Ro, u32(2)));
            od_.add_sub(0x2F00,
                        SubObject::make(2, "Minor", DataType::Unsigned32, Access::Ro, u32(3)));
            od_.add_sub(0x2F00,
                        SubObject::make(3, "Revision", DataType::Unsigned32, Access::Ro, u32(1)));
            od_.add_sub(0x2F00,
                        SubObject::make(4, "Branch", DataType::Unsigned32, Access::Ro, u32(0)));
            od_.add_sub(0x2F00, SubObject::make(
                                    5, "Version", DataType::VisibleString, Access::Ro,
                                    Value::from_string(
                                        "02-03-01-001 (simulated AKD2G firmware, EtherCAT CoE)")));
        }
        od_.add_var(kScratchStringIndex, "Simulator scratch string", DataType::VisibleString,
                    Access::Rw, Value::from_string("codrive"));
        if (core_) {
            add_control_object();
            // DriveCore owns 6040h/6041h (its controlword hook runs the CiA 402 state machine);
            // installing the built-in hooks here would replace it and run a second, diverging
            // state machine on the same objects.
            return;
        }
        od_.on_write(0x6040,
                     [this](std::uint16_t, std::uint8_t,
                            std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                         if (d.size() >= 2) {
                             pending_cw_ = get_le<std::uint16_t>(d.data());
                             has_cw_ = true;
                         }
                         return {};
                     });
        od_.on_read(0x6041, [this](std::uint16_t, std::uint8_t, SubObject&) { apply_cw(); });
        update_statusword();
    }

    /// The simulation control object of the CAN simulator (kControlObject, sim_device.hpp), so
    /// tests inject faults the same way over CoE as over CANopen SDO.
    void add_control_object() {
        od_.add_sub(kControlObject,
                    SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Ro,
                                    u8(kControlFollowingError)),
                    "Simulation control");
        od_.add_sub(kControlObject, SubObject::make(kControlSto, "STO input active",
                                                    DataType::Unsigned8, Access::Rw, u8(0)));
        od_.add_sub(kControlObject, SubObject::make(kControlOverCurrent, "Inject over-current",
                                                    DataType::Unsigned8, Access::Rw, u8(0)));
        od_.add_sub(kControlObject,
                    SubObject::make(kControlFollowingError, "Inject following error",
                                    DataType::Unsigned8, Access::Rw, u8(0)));
        od_.find(kControlObject)->code = ObjectCode::Record;
        od_.on_write(kControlObject,
                     [this](std::uint16_t, std::uint8_t sub,
                            std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                         const bool on = !d.empty() && d[0] != 0;
                         if (sub == kControlSto) {
                             core_->set_sto(on);
                         } else if (sub == kControlOverCurrent && on) {
                             core_->inject(FaultKind::OverCurrent);
                         } else if (sub == kControlFollowingError && on) {
                             core_->inject(FaultKind::FollowingError);
                         }
                         return {};
                     });
    }

    /// 1010h/1011h over CoE, from the same store as the CAN simulator.
    void install_store(const drives::Profile& p) {
        store_ = std::make_unique<ParameterStore>(od_, p);
        store_->add_objects();
        store_->snapshot_factory();
        store_->install_hooks(
            [this, &p]() -> tl::expected<void, SdoAbort> {
                // DS-BVS §6.2.7: pre-operational (ESM PREOP) and power disabled.
                if (!p.quirks.restore_needs_preop_power_disabled || !core_) {
                    return {};
                }
                const auto st = core_->state();
                const bool power_disabled = st == drives::cia402::State::NotReadyToSwitchOn ||
                                            st == drives::cia402::State::SwitchOnDisabled ||
                                            st == drives::cia402::State::ReadyToSwitchOn;
                if (esm_ != AlState::PreOp || !power_disabled) {
                    return tl::unexpected(SdoAbort::DataTransferState);
                }
                return {};
            },
            [this, &p] {
                if (p.persistence.restore_restarts) {
                    // FIO §7.12.4.16: restarts after clearing; the answer goes out first.
                    restart_at_ = last_ + milliseconds(100);
                }
            });
    }

    // The write hook runs before the value is stored; apply the controlword on the next access.
    void apply_cw() {
        if (has_cw_) {
            has_cw_ = false;
            on_controlword(pending_cw_);
        }
    }

public:
    void on_frame_done() { apply_cw(); }

private:
    ObjectDictionary od_;
    std::unique_ptr<DriveCore> core_;
    State state_ = State::SwitchOnDisabled;
    std::uint16_t last_cw_ = 0;
    std::uint16_t pending_cw_ = 0;
    bool has_cw_ = false;
    TimePoint last_{};
    double pending_ = 0;                     ///< seconds not yet stepped (DriveCore)
    std::uint32_t device_type_ = 0x00020192; ///< CiA 402 drive
    bool has_slave_status_ = false;          ///< FIO 2110h
    std::vector<emcy::EmcyMessage> emergencies_;
    std::unique_ptr<ParameterStore> store_;
    AlState esm_ = AlState::Init;
    std::optional<TimePoint> restart_at_; ///< FIO: restart after 1011h
    bool restart_due_ = false;
};

/// Wraps the device so the controlword is applied after every frame and every step.
class DriveApp final : public EcatApplication {
public:
    explicit DriveApp(std::unique_ptr<Cia402Device> dev) : dev_(std::move(dev)) {}
    ObjectDictionary& od() override { return dev_->od(); }
    void step(TimePoint now) override {
        dev_->on_frame_done();
        dev_->step(now);
    }
    void on_state_change(AlState from, AlState to) override { dev_->on_state_change(from, to); }
    void on_outputs(TimePoint /*now*/) override { dev_->on_frame_done(); }
    std::vector<emcy::EmcyMessage> take_emergencies() override {
        dev_->on_frame_done();
        return dev_->take_emergencies();
    }
    void inject_fault(std::uint16_t error_code) override { dev_->raise_fault(error_code); }
    bool take_restart() override { return dev_->take_restart(); }

private:
    std::unique_ptr<Cia402Device> dev_;
};

} // namespace

std::vector<std::string_view> ecat_profile_names() {
    return {"fio", "akd2g", "ds-bvs", "generic", "generic-nopdo"};
}

std::unique_ptr<EscSlave> make_drive_slave(std::string_view profile, std::uint32_t serial) {
    DriveDef def;
    if (profile == "fio") {
        def = fio_def();
    } else if (profile == "akd2g") {
        def = akd2g_def();
    } else if (profile == "ds-bvs" || profile == "dsbvs") {
        def = dsbvs_def();
    } else if (profile == "generic" || profile == "generic-nopdo") {
        def = generic_def(profile == "generic");
    } else {
        return nullptr;
    }
    // One identity per drive (issue 15): the SimProfile's, as on the CAN simulator.
    // The generic slave has no SimProfile: its own identity and the built-in state machine.
    const SimProfile* identity = find_profile(def.profile);
    if (identity != nullptr) {
        def.vendor = identity->identity_vendor_id();
        def.product = identity->identity_product_code(1);
        def.revision = identity->revision;
    }
    SiiInfo sii;
    sii.vendor_id = def.vendor;
    sii.product_code = def.product;
    sii.revision = def.revision;
    sii.serial = serial;
    sii.name = def.name;
    sii.rx_mailbox_offset = 0x1000;
    sii.rx_mailbox_size = 128;
    sii.tx_mailbox_offset = 0x1080;
    sii.tx_mailbox_size = 128;
    // The AKD2G takes its *.akd parameter file and its firmware over FoE (manual §2.3.3.4).
    sii.mailbox_protocols =
        profile == "akd2g" ? mbx_proto::kCoe | mbx_proto::kFoe : mbx_proto::kCoe;
    sii.fmmu_usage = {1, 2, 3};
    sii.sync_managers = {
        {0x1000, 128, 0x26, 0x01, SmType::MailboxOut},
        {0x1080, 128, 0x22, 0x01, SmType::MailboxIn},
        {def.sm2, 0, 0x64, 0x01, SmType::Outputs},
        {def.sm3, 0, 0x20, 0x01, SmType::Inputs},
    };
    const SimProfile* sp = nullptr;
    if (std::getenv("CODRIVE_ECAT_SIM_BUILTIN_402") == nullptr) {
        sp = identity;
    }
    auto app = std::make_unique<DriveApp>(std::make_unique<Cia402Device>(def, serial, sp));
    return std::make_unique<EscSlave>(std::move(sii), std::move(app), true);
}

} // namespace codrive::sim::ecat
