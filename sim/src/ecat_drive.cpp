// SPDX-License-Identifier: Apache-2.0
// Simulated EtherCAT drives: object dictionaries of FIO, AKD2G and DS-BVS (identity, PDO maps,
// 1C12h/1C13h defaults, sync managers from the manuals) with one DriveCore per axis behind them.
#include <codrive/sim/ecat/drive_profiles.hpp>

#include "ecat_drive_defs.hpp"
#include "error_history.hpp"
#include "parameter_store.hpp"

#include <codrive/sim/active_errors.hpp>
#include <codrive/sim/drive_core.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>

#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/sii.hpp>
#include <codrive/pdo/device.hpp>

#include <algorithm>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

namespace {

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

/// One simulated EtherCAT drive: the object dictionary served over CoE and one DriveCore per
/// axis — the CiA 402 state machine, modes and motor model the CAN simulator runs too (axis n's
/// objects at index + (n − 1) × the profile's axis offset: AKD2G 6040h → 6840h). Fault events
/// become CoE emergencies, 1001h and 1003h entries, as on CAN.
class EcatDrive final : public EcatApplication {
public:
    EcatDrive(DriveDef def, std::uint32_t serial, const SimProfile& profile, unsigned axes)
        : def_(std::move(def)), profile_(profile) {
        for (unsigned a = 0; a < axes; ++a) {
            axes_.push_back(std::make_unique<DriveCore>(od_, profile, a));
            axes_.back()->set_event_handler([this](const AxisEvent& e) { on_axis_event(e); });
            axes_.back()->power_on();
        }
        // 1000h as the master-side profile expects it (FIO: servo + stepper 0x00060192), so
        // drives::match_identity() finds the same profile over CoE as the drive would give.
        if (profile.drive->identity.device_type != 0) {
            device_type_ = profile.drive->identity.device_type;
        }
        build(serial);
        add_error_objects(od_, profile);
        install_store(*profile.drive);
    }

    bool take_restart() override {
        if (!restart_due_) {
            return false;
        }
        // Power cycle: the saved values come back and the drive starts over.
        restart_due_ = false;
        restart_at_.reset();
        store_->load(false);
        for (auto& a : axes_) {
            a->power_on();
        }
        errors_.reset();
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
        const double dt = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        if (dt <= 0 || dt > 1.0) {
            return;
        }
        // DriveCore runs in fixed 1 ms steps, as in the CAN simulator (SimDeviceConfig::step).
        // Stepping it by the gaps between frames instead (tens of µs between the frames of one
        // cycle, then a whole period) made the reported 606Ch the speed over the last tiny
        // step — about 82 % of the true speed — so PV never reached its window.
        constexpr double kStep = 0.001;
        pending_ += dt;
        while (pending_ >= kStep) {
            for (auto& a : axes_) {
                a->step(kStep);
            }
            pending_ -= kStep;
        }
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
        // outputs are no longer valid (ETG.1000.6 §6.4.2): every axis applies its abort
        // connection option 6007h (FIO §7.13.77: default -1, clear the PDOs and coast). A
        // profile without 6007h (AKD2G) disables the voltage.
        for (auto& a : axes_) {
            a->set_fieldbus_synchronised(to == AlState::Op);
            if (from == AlState::Op) {
                a->abort_connection(od_.get<std::int16_t>(a->index(0x6007), 0).value_or(2));
            }
        }
    }

    void on_outputs(TimePoint /*now*/) override {}

    std::vector<emcy::EmcyMessage> take_emergencies() override {
        return std::exchange(emergencies_, {});
    }

    void inject_fault(std::uint16_t code) override {
        axes_.front()->raise_fault(FaultCode{code, 0x01, "injected fault"});
    }

    [[nodiscard]] std::uint16_t al_status_code(std::uint16_t code) const override {
        return def_.al_code != nullptr ? def_.al_code(code) : code;
    }

private:
    /// Faults and warnings as on CAN (one ActiveErrors for both simulators): 1001h, 1003h/4080h
    /// and an emergency per change, EMCY 0000h once nothing is active (CiA 301 §7.2.7.1).
    void on_axis_event(const AxisEvent& e) {
        if (const auto m = errors_.on_axis_event(e)) {
            emergencies_.push_back(*m);
        }
    }

    void add_pdo(const PdoDef& p, bool rx) {
        const std::string name = rx ? "RxPDO mapping" : "TxPDO mapping";
        const Access a = p.fixed ? Access::Ro : Access::Rw;
        auto count = SubObject::make(0, "Number of entries", DataType::Unsigned8, a,
                                     u8(static_cast<std::uint8_t>(p.entries.size())));
        const std::size_t slots = p.fixed ? p.entries.size() : def_.map_slots;
        if (!p.fixed) {
            count.low_limit = u8(0);
            count.high_limit = u8(def_.map_slots);
        }
        od_.add_sub(p.index, std::move(count), name);
        for (std::size_t i = 0; i < slots; ++i) {
            od_.add_sub(p.index, SubObject::make(static_cast<std::uint8_t>(i + 1),
                                                 "Mapping entry " + std::to_string(i + 1),
                                                 DataType::Unsigned32, a,
                                                 u32(i < p.entries.size() ? p.entries[i] : 0)));
        }
        od_.find(p.index)->code = ObjectCode::Record;
        if (!p.fixed && def_.map_rules) {
            check_mapping_writes(p.index, rx ? PdoDir::Rpdo : PdoDir::Tpdo);
        }
    }

    /// Flexible mapping (AKD2G §3.11): sub 0 = 0 first, then the entries, then sub 0 = n; an
    /// object that cannot be mapped in this direction aborts 0x06040041 ("If any objects are not
    /// PDO mappable, an error will be received"); padding is index 0000h sub 00h with a length
    /// of whole bytes (§3.11.1). The rules are the pdo module's (pdo::check_mapping_entry).
    void check_mapping_writes(std::uint16_t index, PdoDir dir) {
        od_.on_write(
            index,
            [this, index, dir](std::uint16_t, std::uint8_t sub,
                               std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                const pdo::PdoQuirks& q = *def_.map_rules;
                const auto ok = [&](std::uint32_t raw) {
                    return pdo::check_mapping_entry(od_, dir, q,
                                                    pdo::MappingEntry::from_raw(raw)) == SdoAbort{};
                };
                if (sub != 0) {
                    if (od_.get<std::uint8_t>(index, 0).value_or(0) != 0) {
                        return tl::unexpected(SdoAbort::DataTransferState);
                    }
                    const auto raw = static_cast<std::uint32_t>(
                        get_le_n(d.data(), std::min<std::size_t>(d.size(), 4)));
                    if (raw != 0 && !ok(raw)) {
                        return tl::unexpected(SdoAbort::NotMappable);
                    }
                    return {};
                }
                const unsigned n = d.empty() ? 0U : d[0];
                if (n > def_.map_slots) {
                    return tl::unexpected(SdoAbort::ValueTooHigh);
                }
                for (unsigned i = 1; i <= n; ++i) {
                    if (!ok(od_.get<std::uint32_t>(index, static_cast<std::uint8_t>(i))
                                .value_or(0))) {
                        return tl::unexpected(SdoAbort::NotMappable);
                    }
                }
                return {};
            });
    }

    void build(std::uint32_t serial) {
        od_.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro, u32(device_type_));
        od_.add_var(0x1001, "Error register", DataType::Unsigned8, Access::Ro, u8(0), true);
        od_.add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
                    Value::from_string(def_.name));
        od_.add_var(0x1009, "Manufacturer hardware version", DataType::VisibleString, Access::Const,
                    Value::from_string("sim-1"));
        od_.add_var(0x100A, "Manufacturer software version", DataType::VisibleString, Access::Const,
                    Value::from_string("codrive-ecat-sim 0.1"));
        od_.add_sub(0x1018,
                    SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Ro, u8(4)),
                    "Identity object");
        od_.add_sub(0x1018, SubObject::make(1, "Vendor-ID", DataType::Unsigned32, Access::Ro,
                                            u32(def_.vendor)));
        od_.add_sub(0x1018, SubObject::make(2, "Product code", DataType::Unsigned32, Access::Ro,
                                            u32(def_.product)));
        od_.add_sub(0x1018, SubObject::make(3, "Revision number", DataType::Unsigned32, Access::Ro,
                                            u32(def_.revision)));
        od_.add_sub(0x1018, SubObject::make(4, "Serial number", DataType::Unsigned32, Access::Ro,
                                            u32(serial)));
        add_objects_of_axes();
        if (def_.profile == "akd2g") {
            add_akd2g_objects();
        }
        // The maps after the objects: the mapping checks look the mapped objects up.
        for (const auto& p : def_.rx) {
            add_pdo(p, true);
        }
        for (const auto& p : def_.tx) {
            add_pdo(p, false);
        }
        add_sync_manager_objects();
        if (def_.profile == "fio") {
            // §7.13.52: 3202h default 00000000h (the profile holds it; DriveCore installs it).
            if (od_.find(0x3202) == nullptr) {
                od_.add_var(0x3202, "Motor drive submode select", DataType::Unsigned32, Access::Rww,
                            u32(0), true);
            }
            // §7.13.51: 2110h bits 3..0 the EtherCAT state (1 INIT, 2 PREOP, 3 BOOT, 4 SAFEOP,
            // 8 OP), bit 4 ERR; default 0000h before the ESM runs. on_state_change() keeps it.
            od_.add_var(0x2110, "EtherCAT slave status", DataType::Unsigned16, Access::Ro,
                        u16(0x0000));
            has_slave_status_ = true;
        }
        od_.add_var(kScratchStringIndex, "Simulator scratch string", DataType::VisibleString,
                    Access::Rw, Value::from_string("codrive"));
        for (unsigned a = 0; a < axes_.size(); ++a) {
            add_control_object(a);
        }
    }

    void add_sync_manager_objects() {
        const auto add_assign = [&](std::uint16_t index, const std::vector<std::uint16_t>& pdos,
                                    const char* name, std::uint16_t low, std::uint16_t high) {
            od_.add_sub(index,
                        SubObject::make(0, "Number of assigned PDOs", DataType::Unsigned8,
                                        Access::Rw, u8(static_cast<std::uint8_t>(pdos.size()))),
                        name);
            for (std::uint8_t i = 0; i < def_.assign_max; ++i) {
                auto entry = SubObject::make(static_cast<std::uint8_t>(i + 1),
                                             "PDO " + std::to_string(i + 1), DataType::Unsigned16,
                                             Access::Rw, u16(i < pdos.size() ? pdos[i] : 0));
                if (high != 0) {
                    entry.low_limit = u16(low);
                    entry.high_limit = u16(high);
                }
                od_.add_sub(index, std::move(entry));
            }
            od_.find(index)->code = ObjectCode::Array;
        };
        add_assign(0x1C12, def_.rx_assign, "Sync manager 2 PDO assignment", def_.rx_assign_low,
                   def_.rx_assign_high);
        add_assign(0x1C13, def_.tx_assign, "Sync manager 3 PDO assignment", def_.tx_assign_low,
                   def_.tx_assign_high);
        od_.add_sub(0x1C00,
                    SubObject::make(0, "Number of sync managers", DataType::Unsigned8, Access::Ro,
                                    u8(def_.sm_channels)),
                    "Sync manager communication type");
        for (std::uint8_t i = 0; i < def_.sm_channels; ++i) {
            od_.add_sub(0x1C00, SubObject::make(static_cast<std::uint8_t>(i + 1),
                                                "Communication type SM" + std::to_string(i),
                                                DataType::Unsigned8, Access::Ro,
                                                u8(static_cast<std::uint8_t>(i < 4 ? i + 1 : 0))));
        }
        od_.find(0x1C00)->code = ObjectCode::Array;
        for (std::uint16_t idx : {std::uint16_t{0x1C32}, std::uint16_t{0x1C33}}) {
            const bool out = idx == 0x1C32;
            od_.add_sub(idx,
                        SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8,
                                        Access::Ro,
                                        u8(out ? def_.sm_out_highest : def_.sm_in_highest)),
                        out ? "Output sync manager parameter" : "Input sync manager parameter");
            if (!def_.sm_subs.empty()) {
                for (const auto& ss : def_.sm_subs) {
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
                                             u32(def_.sm_cycle_time)));
            if (def_.sm_entries >= 3) {
                od_.add_sub(idx, SubObject::make(3, "Shift time", DataType::Unsigned32, Access::Rw,
                                                 u32(0)));
            }
        }
    }

    /// The CiA 402 objects DriveCore does not install, per axis (at the axis's index). Objects
    /// the drive profile says the drive lacks (AKD2G 603Fh, §5.6) stay absent.
    void add_objects_of_axes() {
        for (const auto& core : axes_) {
            const DriveCore& c = *core;
            const auto add_var = [this, &c](std::uint16_t base, const char* n, DataType t, Access a,
                                            Value v, bool map) {
                const std::uint16_t index = c.index(base);
                if (od_.find(index) == nullptr && profile_.drive->has_object(base)) {
                    od_.add_var(index, n, t, a, std::move(v), map);
                }
            };
            add_var(0x603F, "Error code", DataType::Unsigned16, Access::Ro, u16(0), true);
            add_var(0x6071, "Target torque", DataType::Integer16, Access::Rww,
                    typed(DataType::Integer16, 0), true);
            add_var(0x6077, "Torque actual value", DataType::Integer16, Access::Rwr,
                    typed(DataType::Integer16, 0), true);
            add_var(0x60B2, "Torque offset", DataType::Integer16, Access::Rww,
                    typed(DataType::Integer16, 0), true);
            add_var(0x60F4, "Following error actual value", DataType::Integer32, Access::Rwr,
                    typed(DataType::Integer32, 0), true);
            add_var(0x60FD, "Digital inputs", DataType::Unsigned32, Access::Rwr, u32(0), true);
            add_var(0x60FF, "Target velocity", DataType::Integer32, Access::Rww,
                    typed(DataType::Integer32, 0), true);
            add_var(0x6502, "Supported drive modes", DataType::Unsigned32, Access::Ro,
                    u32(0x000003A5), false);
            const std::uint16_t outputs = c.index(0x60FE);
            if (od_.find(outputs) == nullptr) {
                od_.add_sub(
                    outputs,
                    SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Ro, u8(1)),
                    "Digital outputs");
                od_.add_sub(outputs, SubObject::make(1, "Physical outputs", DataType::Unsigned32,
                                                     Access::Rww, u32(0), true));
            }
        }
    }

    void add_akd2g_objects() {
        // §5.3.25 3580h and §5.3.39 3601h: the objects of the drive's fixed maps 1A20h/1620h.
        if (od_.find(0x3580) == nullptr) {
            od_.add_var(0x3580, "Digital input states", DataType::Unsigned32, Access::Rwr, u32(0),
                        true);
        }
        if (od_.find(0x3601) == nullptr) {
            od_.add_sub(0x3601,
                        SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8,
                                        Access::Ro, u8(2)),
                        "Digital output control");
            od_.add_sub(0x3601, SubObject::make(1, "Physical outputs", DataType::Unsigned32,
                                                Access::Rww, u32(0), true));
            od_.add_sub(0x3601, SubObject::make(2, "Output mask", DataType::Unsigned32, Access::Rw,
                                                u32(0)));
            od_.find(0x3601)->code = ObjectCode::Record;
        }
        if (od_.find(0x2F00) == nullptr) {
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
    }

    /// The simulation control object of the CAN simulator (kControlObject + axis, see
    /// sim_device.hpp), so tests inject faults the same way over CoE as over CANopen SDO.
    void add_control_object(unsigned axis) {
        const auto index = static_cast<std::uint16_t>(kControlObject + axis);
        od_.add_sub(index,
                    SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Ro,
                                    u8(kControlFollowingError)),
                    "Simulation control");
        od_.add_sub(index, SubObject::make(kControlSto, "STO input active", DataType::Unsigned8,
                                           Access::Rw, u8(0)));
        od_.add_sub(index, SubObject::make(kControlOverCurrent, "Inject over-current",
                                           DataType::Unsigned8, Access::Rw, u8(0)));
        od_.add_sub(index, SubObject::make(kControlFollowingError, "Inject following error",
                                           DataType::Unsigned8, Access::Rw, u8(0)));
        od_.find(index)->code = ObjectCode::Record;
        od_.on_write(index,
                     [this, axis](std::uint16_t, std::uint8_t sub,
                                  std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                         const bool on = !d.empty() && d[0] != 0;
                         DriveCore& core = *axes_[axis];
                         if (sub == kControlSto) {
                             core.set_sto(on);
                         } else if (sub == kControlOverCurrent && on) {
                             core.inject(FaultKind::OverCurrent);
                         } else if (sub == kControlFollowingError && on) {
                             core.inject(FaultKind::FollowingError);
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
                // DS-BVS §6.2.7: pre-operational (ESM PREOP) and every axis power disabled.
                if (!p.quirks.restore_needs_preop_power_disabled) {
                    return {};
                }
                const bool power_disabled =
                    std::all_of(axes_.begin(), axes_.end(), [](const auto& a) {
                        const auto st = a->state();
                        return st == drives::cia402::State::NotReadyToSwitchOn ||
                               st == drives::cia402::State::SwitchOnDisabled ||
                               st == drives::cia402::State::ReadyToSwitchOn;
                    });
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

    DriveDef def_;
    const SimProfile& profile_;
    ObjectDictionary od_;
    ActiveErrors errors_{od_, profile_};
    std::vector<std::unique_ptr<DriveCore>> axes_;
    TimePoint last_{};
    double pending_ = 0;                     ///< seconds not yet stepped
    std::uint32_t device_type_ = 0x00020192; ///< CiA 402 drive
    bool has_slave_status_ = false;          ///< FIO 2110h
    std::vector<emcy::EmcyMessage> emergencies_;
    std::unique_ptr<ParameterStore> store_;
    AlState esm_ = AlState::Init;
    std::optional<TimePoint> restart_at_; ///< FIO: restart after 1011h
    bool restart_due_ = false;
};

} // namespace

std::vector<std::string_view> ecat_profile_names() {
    return {"fio", "akd2g", "ds-bvs", "generic", "generic-nopdo"};
}

std::unique_ptr<EscSlave> make_drive_slave(std::string_view profile, std::uint32_t serial) {
    std::string_view name;
    if (profile == "fio") {
        name = "fio";
    } else if (profile == "akd2g") {
        name = "akd2g";
    } else if (profile == "ds-bvs" || profile == "dsbvs") {
        name = "ds-bvs";
    } else if (profile == "generic" || profile == "generic-nopdo") {
        name = "generic";
    } else {
        return nullptr;
    }
    // One identity per drive (issue 15): the SimProfile's, as on the CAN simulator, with as
    // many axes as it simulates there (AKD2G: two, 1018h:02 says so). The generic slave keeps
    // an identity no profile of codrive's knows (that is its point).
    const SimProfile* sp = find_profile(name);
    const unsigned axes = std::clamp(sp->default_axes, 1U, sp->max_axes());
    DriveDef def = name == "fio"       ? fio_def()
                   : name == "akd2g"   ? akd2g_def(axes)
                   : name == "generic" ? generic_def(profile == "generic")
                                       : dsbvs_def();
    if (name != "generic") {
        def.vendor = sp->identity_vendor_id();
        def.product = sp->identity_product_code(axes);
        def.revision = sp->revision;
    }
    SiiInfo sii;
    sii.vendor_id = def.vendor;
    sii.product_code = def.product;
    sii.revision = def.revision;
    sii.serial = serial;
    sii.name = def.name;
    sii.rx_mailbox_offset = def.mbx_out;
    sii.rx_mailbox_size = def.mbx_size;
    sii.tx_mailbox_offset = def.mbx_in;
    sii.tx_mailbox_size = def.mbx_size;
    // The AKD2G takes its *.akd parameter file and its firmware over FoE (manual §2.3.3.4).
    sii.mailbox_protocols =
        profile == "akd2g" ? mbx_proto::kCoe | mbx_proto::kFoe : mbx_proto::kCoe;
    sii.fmmu_usage = {1, 2, 3};
    sii.sync_managers = {
        {def.mbx_out, def.mbx_size, 0x26, 0x01, SmType::MailboxOut},
        {def.mbx_in, def.mbx_size, 0x22, 0x01, SmType::MailboxIn},
        {def.sm2, 0, 0x64, 0x01, SmType::Outputs},
        {def.sm3, 0, 0x20, 0x01, SmType::Inputs},
    };
    auto app = std::make_unique<EcatDrive>(std::move(def), serial, *sp, axes);
    return std::make_unique<EscSlave>(std::move(sii), std::move(app), true);
}

} // namespace codrive::sim::ecat
