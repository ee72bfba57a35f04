// SPDX-License-Identifier: Apache-2.0
// PDO layout choice for a CiA 402 axis driven through process data, and the 1C32h/1C33h writes.
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/ethercat/drive_layout.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>

namespace codrive::ethercat {
namespace {

bool maps(const std::vector<PdoMapping>& pdos, std::uint16_t index) {
    return std::any_of(pdos.begin(), pdos.end(), [&](const PdoMapping& m) {
        return std::any_of(m.entries.begin(), m.entries.end(),
                           [&](const PdoEntry& e) { return e.index == index; });
    });
}

tl::expected<DriveLayout, std::string> profile_layout(const drives::Profile& profile, unsigned axis,
                                                      drives::cia402::Mode mode,
                                                      LayoutSource source) {
    // The mode of the other axes of a multi-axis drive does not matter here: the layout of
    // axis N sits at its own PDO numbers (drives::mode_pdo_configs numbers them per axis).
    std::vector<drives::cia402::Mode> modes(axis, mode);
    auto configs = drives::mode_pdo_configs(profile, modes);
    if (!configs) {
        return tl::unexpected(configs.error().message);
    }
    // mode_pdo_configs gives one RPDO and one TPDO per axis, in axis order, then the unused
    // PDO numbers disabled: this axis's pair is the last enabled one.
    std::vector<pdo::PdoConfig> mine;
    for (const auto& c : *configs) {
        if (c.enabled && !c.mapping.empty()) {
            mine.push_back(c);
        }
    }
    if (mine.size() < 2) {
        return tl::unexpected(
            fmt::format("{} has no PDO layout for mode {}", profile.title,
                        drives::cia402::mode_name(static_cast<std::int8_t>(mode))));
    }
    mine.erase(mine.begin(), mine.end() - 2);
    DriveLayout l;
    l.source = source;
    to_ecat_pdos(mine, l.rx, l.tx);
    return l;
}

bool is_absent(const std::error_code& e) {
    return e == SdoAbort::NoObject || e == SdoAbort::NoSubindex;
}

} // namespace

void to_ecat_pdos(const std::vector<pdo::PdoConfig>& configs, std::vector<PdoMapping>& rx,
                  std::vector<PdoMapping>& tx) {
    for (const auto& c : configs) {
        if (!c.enabled || c.mapping.empty()) {
            continue;
        }
        PdoMapping m;
        const bool is_rx = c.dir == PdoDir::Rpdo;
        m.index = static_cast<std::uint16_t>((is_rx ? 0x1600U : 0x1A00U) + c.number - 1U);
        for (const auto& e : c.mapping) {
            m.entries.push_back(PdoEntry{e.index, e.subindex, e.bits});
        }
        (is_rx ? rx : tx).push_back(std::move(m));
    }
}

const char* to_string(LayoutSource s) {
    switch (s) {
    case LayoutSource::Profile:
        return "the drive's profile";
    case LayoutSource::SlaveAssignment:
        return "the slave's own assignment";
    case LayoutSource::Esi:
        return "the ESI's default assignment";
    case LayoutSource::Generic:
        return "the generic CiA 402 layout";
    }
    return "?";
}

bool holds_controlword_statusword(const std::vector<PdoMapping>& rx,
                                  const std::vector<PdoMapping>& tx, std::uint16_t controlword,
                                  std::uint16_t statusword) {
    return maps(rx, controlword) && maps(tx, statusword);
}

tl::expected<DriveLayout, std::string> choose_layout(const drives::Profile& profile, unsigned axis,
                                                     drives::cia402::Mode mode,
                                                     const std::vector<PdoMapping>& current_rx,
                                                     const std::vector<PdoMapping>& current_tx,
                                                     const EsiDefaultPdos* esi) {
    if (profile.identity.vendor_id != 0) {
        return profile_layout(profile, axis, mode, LayoutSource::Profile);
    }
    if (esi != nullptr &&
        holds_controlword_statusword(esi->rx, esi->tx, profile.axis_index(0x6040, axis),
                                     profile.axis_index(0x6041, axis))) {
        return DriveLayout{LayoutSource::Esi, esi->rx, esi->tx};
    }
    if (holds_controlword_statusword(current_rx, current_tx, profile.axis_index(0x6040, axis),
                                     profile.axis_index(0x6041, axis))) {
        DriveLayout l;
        l.source = LayoutSource::SlaveAssignment;
        return l;
    }
    return profile_layout(drives::generic_profile(), axis, mode, LayoutSource::Generic);
}

const char* sync_mode_name(std::uint16_t mode) {
    switch (mode) {
    case 0:
        return "free run";
    case 1:
        return "SM synchronous";
    case 2:
        return "DC SYNC0";
    case 3:
        return "DC SYNC1";
    case 0x22:
        return "synchronous with SM2";
    default:
        return "unknown sync mode";
    }
}

std::optional<SyncMode> sync_mode_from_string(std::string_view text) {
    if (text == "free") {
        return SyncMode::FreeRun;
    }
    if (text == "sm") {
        return SyncMode::SmSynchronous;
    }
    if (text == "dc") {
        return SyncMode::DcSync0;
    }
    return std::nullopt;
}

namespace {

/// Whether 1C32h:04 (sync modes supported, ETG.1020 §21.1.3.2) offers `mode`: bit 0 free run,
/// bit 1 synchronous with the SM event, bits 4..2 the DC modes (001 = SYNC0). The AKD2G states
/// 0x0027 (manual §5.2.50).
bool supports(std::uint16_t supported, SyncMode mode) {
    switch (mode) {
    case SyncMode::FreeRun:
        return (supported & 0x0001U) != 0;
    case SyncMode::SmSynchronous:
        return (supported & 0x0002U) != 0;
    case SyncMode::DcSync0:
        return (supported & 0x001CU) != 0;
    }
    return false;
}

} // namespace

tl::expected<SyncReport, std::string> write_sync_objects(Master& master, std::size_t slave,
                                                         const SyncSettings& sync) {
    const std::string who = sync.name.empty()
                                ? master.slave_label(slave)
                                : fmt::format("{} \"{}\"", master.slave_label(slave), sync.name);
    const auto cycle_ns = static_cast<std::uint32_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(sync.cycle).count());
    SyncReport report;
    // ETG.1020 §21.1.3.2: 1C32h:05 minimum cycle time (ns); the AKD2G reports 250 µs
    // (manual 000 ~8848). A slave without it states no minimum.
    if (auto min = master.sdo_read<std::uint32_t>(slave, 0x1C32, 5)) {
        report.min_cycle_ns = *min;
        if (*min != 0 && cycle_ns < *min) {
            return tl::unexpected(fmt::format(
                "{}: cycle time {} µs is shorter than the slave's minimum cycle time {} µs "
                "(0x1C32:05)",
                who, cycle_ns / 1000U, *min / 1000U));
        }
    } else if (is_absent(min.error())) {
        report.notes.push_back(
            fmt::format("{}: has no 0x1C32:05 (it states no minimum cycle time)", who));
    } else {
        return tl::unexpected(fmt::format("{}: cannot read the minimum cycle time (0x1C32:05): {}",
                                          who, master.last_error()));
    }
    // 1C32h:01 / 1C33h:01 synchronisation type: 0 free run, 1 synchronous with the SM2 event,
    // 2 DC SYNC0 (ETG.1020 §21.1.3.1); the FIO manual has the master set them (004 ~4088).
    report.mode = static_cast<std::uint16_t>(sync.mode);
    // ETG.1020 §21.1.3.2: 1C32h:04 states the modes the slave offers; a slave without it (the
    // FIO describes 1C32h:01..03 only, manual §7.13.22) states nothing, so nothing is refused.
    if (auto supported = master.sdo_read<std::uint16_t>(slave, 0x1C32, 4)) {
        if (!supports(*supported, sync.mode)) {
            return tl::unexpected(fmt::format(
                "{}: sync mode {} ({}) is not among the slave's supported sync modes (0x1C32:04 "
                "= 0x{:04X}: bit 0 free run, bit 1 SM-synchronous, bits 4..2 DC)",
                who, report.mode, sync_mode_name(report.mode), *supported));
        }
    } else if (is_absent(supported.error())) {
        if (sync.mode != SyncMode::FreeRun) {
            report.notes.push_back(fmt::format(
                "{}: has no 0x1C32:04 (sync modes supported); sync mode {} ({}) not checked", who,
                report.mode, sync_mode_name(report.mode)));
        }
    } else {
        return tl::unexpected(fmt::format(
            "{}: cannot read the supported sync modes (0x1C32:04): {}", who, master.last_error()));
    }
    struct Write {
        std::uint16_t index;
        std::uint8_t sub;
        std::uint32_t value;
        bool u16;
        const char* what;
    };
    const std::array writes{Write{0x1C32, 1, report.mode, true, "output sync mode"},
                            Write{0x1C32, 2, cycle_ns, false, "cycle time"},
                            Write{0x1C33, 1, report.mode, true, "input sync mode"}};
    for (const Write& w : writes) {
        VoidResult r = w.u16 ? master.sdo_write<std::uint16_t>(slave, w.index, w.sub,
                                                               static_cast<std::uint16_t>(w.value))
                             : master.sdo_write<std::uint32_t>(slave, w.index, w.sub, w.value);
        if (r) {
            continue;
        }
        if (is_absent(r.error())) {
            report.notes.push_back(fmt::format("{}: has no 0x{:04X}:{:02X} ({}); not written", who,
                                               w.index, w.sub, w.what));
            continue;
        }
        if (r.error() == SdoAbort::ReadOnly) {
            // The slave sets it itself: the AKD2G's 1C32h:01/:02 are read-only, derived from
            // SYNC0 or 60C1h (manual §5.2.50).
            report.notes.push_back(fmt::format(
                "{}: 0x{:04X}:{:02X} ({}) is read-only, the slave sets it itself; not written", who,
                w.index, w.sub, w.what));
            continue;
        }
        return tl::unexpected(fmt::format("{}: writing {} 0x{:04X}:{:02X} = {} failed: {}", who,
                                          w.what, w.index, w.sub, w.value, master.last_error()));
    }
    return report;
}

tl::expected<SyncReport, std::string> configure_sync(Master& master, std::size_t slave,
                                                     const SyncSettings& sync) {
    auto report = write_sync_objects(master, slave, sync);
    if (!report || sync.mode != SyncMode::DcSync0) {
        return report;
    }
    // ETG.1020 §21.1.3.1: sync mode 2 runs the slave's application on SYNC0, which the master
    // programs in the ESC's DC unit (0x0980..0x09A3) at the cycle time.
    if (!master.configure_sync0(slave, sync.cycle, sync.shift)) {
        return tl::unexpected(fmt::format("DC SYNC0: {}", master.last_error()));
    }
    return report;
}

} // namespace codrive::ethercat
