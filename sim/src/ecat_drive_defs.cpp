// SPDX-License-Identifier: Apache-2.0
// The EtherCAT side of the simulated drives as data, from their manuals (see ecat_drive_defs.hpp).
#include "ecat_drive_defs.hpp"

#include <codrive/drives/profile.hpp>
#include <codrive/ethercat/al_state.hpp>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

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

// AKD2G, manual §3.10 (~line 2442) and §5.2.20-§5.2.49: free maps 1600h-1603h / 1A00h-1A03h
// (sub-indexes 0 to 32 on EtherCAT); by default 1600h/1A00h carry axis 1's CSP objects and, on a
// dual-axis drive, 1601h/1A01h axis 2's (§3.11.2), assigned in 1C12h/1C13h (at most 10 PDOs
// each, §5.2.48/§5.2.49). Fixed maps: 1620h (3601h:01) and 1A20h (3580h) for the drive; per axis
// 1700h (CSP), 1701h (PV), 1702h (PT), 1704h (60B8h as §5.2.25 gives it; the §3.10 table's
// "60BBh" there is the touch probe position, a TxPDO object), 1B00h (CSP), 1B01h (PV), 1B02h (PT),
// 1B03h (60B9h), 1B04h (60BAh, 60BBh), 1B05h (60BCh, 60BDh), 1B06h (60FDh); axis 2 at +20h
// with its objects at +800h (§5.2.26-§5.2.29, §5.2.40-§5.2.46). Sync managers (§3.3): mailbox
// out at 1800h, mailbox in at 1C00h ("up to 512" bytes, the length given by the device
// description file and firmware: 128 here, as the other simulated slaves), process data out
// 1100h, in 1140h (max. 64 bytes each).
DriveDef akd2g_def(unsigned axes) {
    DriveDef d;
    d.name = "AKD2G";
    d.profile = "akd2g";
    d.mbx_out = 0x1800;
    d.mbx_in = 0x1C00;
    d.mbx_size = 128;
    d.sm2 = 0x1100;
    d.sm3 = 0x1140;
    d.map_slots = 32;
    pdo::PdoQuirks rules = pdo::quirks::akd2g();
    rules.max_entries = 32; // §5.2.20: 0 to 32 on EtherCAT (8 on CAN)
    d.map_rules = rules;
    const auto on_axis = [](std::uint32_t entry, unsigned axis) {
        return axis == 2 && (entry >> 16) >= 0x6000 ? entry + 0x08000000U : entry;
    };
    for (std::uint16_t i = 0; i < 4; ++i) {
        std::vector<std::uint32_t> rx;
        std::vector<std::uint32_t> tx;
        if (i < axes) {
            rx = {on_axis(0x60400010, i + 1U), on_axis(0x607A0020, i + 1U)};
            tx = {on_axis(0x60410010, i + 1U), on_axis(0x60640020, i + 1U),
                  on_axis(0x60F40020, i + 1U)};
            d.rx_assign.push_back(static_cast<std::uint16_t>(0x1600 + i));
            d.tx_assign.push_back(static_cast<std::uint16_t>(0x1A00 + i));
        }
        d.rx.push_back({static_cast<std::uint16_t>(0x1600 + i), rx});
        d.tx.push_back({static_cast<std::uint16_t>(0x1A00 + i), tx});
    }
    d.rx.push_back({0x1620, {0x36010120}, true});
    d.tx.push_back({0x1A20, {0x35800020}, true});
    for (unsigned a = 1; a <= axes; ++a) {
        const auto at = [a](std::uint16_t index) {
            return static_cast<std::uint16_t>(index + (a - 1) * 0x20);
        };
        const auto m = [&](std::initializer_list<std::uint32_t> es) {
            std::vector<std::uint32_t> v;
            for (std::uint32_t e : es) {
                v.push_back(on_axis(e, a));
            }
            return v;
        };
        d.rx.push_back({at(0x1700), m({0x60400010, 0x607A0020}), true});
        d.rx.push_back({at(0x1701), m({0x60400010, 0x60FF0020}), true});
        d.rx.push_back({at(0x1702), m({0x60400010, 0x60710010}), true});
        d.rx.push_back({at(0x1704), m({0x60B80010}), true}); // 1703h reserved
        d.tx.push_back({at(0x1B00), m({0x60410010, 0x60640020, 0x60F40020}), true});
        d.tx.push_back({at(0x1B01), m({0x60410010, 0x60640020, 0x606C0020}), true});
        d.tx.push_back({at(0x1B02), m({0x60410010, 0x60640020, 0x60770010}), true});
        d.tx.push_back({at(0x1B03), m({0x60B90010}), true});
        d.tx.push_back({at(0x1B04), m({0x60BA0020, 0x60BB0020}), true});
        d.tx.push_back({at(0x1B05), m({0x60BC0020, 0x60BD0020}), true});
        d.tx.push_back({at(0x1B06), m({0x60FD0020}), true});
    }
    d.assign_max = 10;
    // §3.1 "AL Status Code": 0x0000, 0x0011 (invalid requested state change, also for bootstrap
    // requests), 0x0017 (invalid sync manager configuration, I -> P and P -> S); "No other codes
    // are supported." The process data watchdog shows on the ERR LED (double flash, §1 X11,
    // ~line 1063): the drive leaves OP with the error flag but writes no code for it.
    d.al_code = [](std::uint16_t code) -> std::uint16_t {
        switch (code) {
        case al_code::kInvalidStateChange:
        case al_code::kUnknownState:
        case al_code::kBootstrapNotSupported:
            return al_code::kInvalidStateChange;
        case al_code::kInvalidMailboxConfigPreop:
        case al_code::kInvalidSmConfig:
        case al_code::kInvalidOutputConfig:
        case al_code::kInvalidInputConfig:
            return al_code::kInvalidSmConfig;
        default:
            return al_code::kNoError;
        }
    };
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
        {0x1608, {0x60400010, 0x607A0020, 0x60FF0020, 0x60710010, 0x60FE0120, 0x60600008}, true},
        // §6.2.20: motion sequence map (4700h sub 1..8 after the controlword).
        {0x1609,
         {0x60400010, 0x47000108, 0x47000210, 0x47000308, 0x47000420, 0x47000520, 0x47000620,
          0x47000720, 0x47000820},
         true}};
    d.tx = {
        {0x1A00, {}},
        {0x1A01, {}},
        {0x1A02, {}},
        {0x1A03, {}},
        {0x1A04, {0x60410010, 0x60640020, 0x60FD0020}, true},
        {0x1A05, {0x60410010, 0x60640020, 0x606C0020, 0x60FD0020}, true},
        {0x1A06, {0x60410010, 0x60640020, 0x606C0020, 0x60770010, 0x60FD0020}, true},
        // §6.2.26
        {0x1A07, {0x60410010, 0x60640020, 0x606C0020, 0x60780010, 0x60FD0020}, true},
        {0x1A08, {0x60410010, 0x60640020, 0x606C0020, 0x60770010, 0x60FD0020, 0x60610008}, true},
        // §6.2.28
        {0x1A09, {0x60410010, 0x47010010, 0x60640020, 0x606C0020, 0x60770010, 0x60FD0020}, true}};
    d.rx_assign = {0x1608};
    d.tx_assign = {0x1A08};
    d.assign_max = 1;
    d.map_slots = 10;         // §6.2.14.2, §6.2.22: entries 01h..0Ah
    d.rx_assign_low = 0x1600; // §6.2.30.2: 1C12h:01 takes 1600h..1609h
    d.rx_assign_high = 0x1609;
    d.tx_assign_low = 0x1A00; // §6.2.31.2: 1C13h:01 takes 1A00h..1A08h
    d.tx_assign_high = 0x1A08;
    d.sm_channels = 8; // §6.2.29: 1C00h sub 0 = 8, channels 4..7 = 0
    return d;
}

} // namespace codrive::sim::ecat
