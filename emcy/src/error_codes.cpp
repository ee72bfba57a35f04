// SPDX-License-Identifier: Apache-2.0
// The standard EMCY error-code table: CiA 301 Table 21 (emergency error codes) and the
// drive-specific codes of CiA 402 / IEC 61800-7-201 Annex (same numbering, finer classes).
#include <codrive/emcy/error_codes.hpp>

#include <algorithm>
#include <array>
#include <fmt/format.h>

namespace codrive::emcy {

namespace {

struct Row {
    std::uint16_t code;
    std::string_view text;
};

// Sorted by code for binary search. Texts follow the standard wording, shortened where the
// standard repeats its class name.
constexpr std::array kTable = std::to_array<Row>({
    {0x0000, "error reset or no error"},
    {0x1000, "generic error"},
    {0x2000, "current"},
    {0x2100, "current, device input side"},
    {0x2110, "short circuit or earth leakage (input)"},
    {0x2120, "earth leakage (input)"},
    {0x2121, "earth leakage phase L1"},
    {0x2122, "earth leakage phase L2"},
    {0x2123, "earth leakage phase L3"},
    {0x2130, "short circuit (input)"},
    {0x2131, "short circuit phases L1-L2"},
    {0x2132, "short circuit phases L2-L3"},
    {0x2133, "short circuit phases L3-L1"},
    {0x2200, "internal current"},
    {0x2211, "internal current no. 1"},
    {0x2212, "internal current no. 2"},
    {0x2213, "over-current in ramp function"},
    {0x2214, "over-current in the sequence"},
    {0x2220, "continuous over-current (device internal)"},
    {0x2221, "continuous over-current no. 1"},
    {0x2222, "continuous over-current no. 2"},
    {0x2230, "short circuit or earth leakage (device internal)"},
    {0x2240, "earth leakage (device internal)"},
    {0x2250, "short circuit (device internal)"},
    {0x2300, "current, device output side"},
    {0x2310, "continuous over-current"},
    {0x2311, "continuous over-current no. 1"},
    {0x2312, "continuous over-current no. 2"},
    {0x2320, "short circuit or earth leakage (motor side)"},
    {0x2330, "earth leakage (motor side)"},
    {0x2331, "earth leakage phase U"},
    {0x2332, "earth leakage phase V"},
    {0x2333, "earth leakage phase W"},
    {0x2340, "short circuit (motor side)"},
    {0x2341, "short circuit phases U-V"},
    {0x2342, "short circuit phases V-W"},
    {0x2343, "short circuit phases W-U"},
    {0x2350, "load level fault (I2t, thermal state)"},
    {0x2351, "load level warning (I2t, thermal state)"},
    {0x3000, "voltage"},
    {0x3100, "mains voltage"},
    {0x3110, "mains over-voltage"},
    {0x3111, "mains over-voltage phase L1"},
    {0x3112, "mains over-voltage phase L2"},
    {0x3113, "mains over-voltage phase L3"},
    {0x3120, "mains under-voltage"},
    {0x3121, "mains under-voltage phase L1"},
    {0x3122, "mains under-voltage phase L2"},
    {0x3123, "mains under-voltage phase L3"},
    {0x3130, "phase failure"},
    {0x3131, "phase failure L1"},
    {0x3132, "phase failure L2"},
    {0x3133, "phase failure L3"},
    {0x3134, "phase sequence"},
    {0x3140, "mains frequency"},
    {0x3141, "mains frequency too great"},
    {0x3142, "mains frequency too small"},
    {0x3200, "DC link voltage"},
    {0x3210, "DC link over-voltage"},
    {0x3211, "DC link over-voltage no. 1"},
    {0x3212, "DC link over-voltage no. 2"},
    {0x3220, "DC link under-voltage"},
    {0x3221, "DC link under-voltage no. 1"},
    {0x3222, "DC link under-voltage no. 2"},
    {0x3230, "load error"},
    {0x3300, "output voltage"},
    {0x3310, "output over-voltage"},
    {0x3311, "output over-voltage phase U"},
    {0x3312, "output over-voltage phase V"},
    {0x3313, "output over-voltage phase W"},
    {0x3320, "armature circuit"},
    {0x3321, "armature circuit interrupted"},
    {0x3330, "field circuit"},
    {0x3331, "field circuit interrupted"},
    {0x4000, "temperature"},
    {0x4100, "ambient temperature"},
    {0x4110, "excess ambient temperature"},
    {0x4120, "too low ambient temperature"},
    {0x4130, "supply air temperature"},
    {0x4140, "air outlet temperature"},
    {0x4200, "device temperature"},
    {0x4210, "excess device temperature"},
    {0x4220, "too low device temperature"},
    {0x4300, "drive temperature"},
    {0x4310, "excess drive temperature"},
    {0x4320, "too low drive temperature"},
    {0x4400, "supply temperature"},
    {0x4410, "excess supply temperature"},
    {0x4420, "too low supply temperature"},
    {0x5000, "device hardware"},
    {0x5100, "supply"},
    {0x5110, "supply low voltage"},
    {0x5111, "supply low voltage U1 (±15 V)"},
    {0x5112, "supply low voltage U2 (+24 V)"},
    {0x5113, "supply low voltage U3 (+5 V)"},
    {0x5114, "supply low voltage U4 (manufacturer-specific)"},
    {0x5115, "supply low voltage U5 (manufacturer-specific)"},
    {0x5116, "supply low voltage U6 (manufacturer-specific)"},
    {0x5117, "supply low voltage U7 (manufacturer-specific)"},
    {0x5118, "supply low voltage U8 (manufacturer-specific)"},
    {0x5119, "supply low voltage U9 (manufacturer-specific)"},
    {0x5120, "supply intermediate circuit"},
    {0x5200, "control"},
    {0x5210, "measurement circuit"},
    {0x5220, "computing circuit"},
    {0x5300, "operating unit"},
    {0x5400, "power section"},
    {0x5410, "output stages"},
    {0x5420, "chopper"},
    {0x5430, "input stages"},
    {0x5440, "contacts"},
    {0x5441, "contact 1 (manufacturer-specific)"},
    {0x5442, "contact 2 (manufacturer-specific)"},
    {0x5443, "contact 3 (manufacturer-specific)"},
    {0x5444, "contact 4 (manufacturer-specific)"},
    {0x5445, "contact 5 (manufacturer-specific)"},
    {0x5450, "fuses"},
    {0x5451, "fuse S1 (L1)"},
    {0x5452, "fuse S2 (L2)"},
    {0x5453, "fuse S3 (L3)"},
    {0x5454, "fuse S4 (manufacturer-specific)"},
    {0x5455, "fuse S5 (manufacturer-specific)"},
    {0x5456, "fuse S6 (manufacturer-specific)"},
    {0x5457, "fuse S7 (manufacturer-specific)"},
    {0x5458, "fuse S8 (manufacturer-specific)"},
    {0x5459, "fuse S9 (manufacturer-specific)"},
    {0x5500, "hardware memory"},
    {0x5510, "RAM"},
    {0x5520, "ROM or EPROM"},
    {0x5530, "EEPROM or non-volatile data memory"},
    {0x6000, "device software"},
    {0x6010, "software reset (watchdog)"},
    {0x6100, "internal software"},
    {0x6200, "user software"},
    {0x6300, "data set"},
    {0x6301, "data set no. 1"},
    {0x6302, "data set no. 2"},
    {0x6303, "data set no. 3"},
    {0x6304, "data set no. 4"},
    {0x6305, "data set no. 5"},
    {0x6306, "data set no. 6"},
    {0x6307, "data set no. 7"},
    {0x6308, "data set no. 8"},
    {0x6309, "data set no. 9"},
    {0x630A, "data set no. 10"},
    {0x630B, "data set no. 11"},
    {0x630C, "data set no. 12"},
    {0x630D, "data set no. 13"},
    {0x630E, "data set no. 14"},
    {0x630F, "data set no. 15"},
    {0x6310, "loss of parameters"},
    {0x6320, "parameter error"},
    {0x7000, "additional modules"},
    {0x7100, "power"},
    {0x7110, "brake chopper"},
    {0x7111, "brake chopper failure"},
    {0x7112, "brake chopper over-current"},
    {0x7113, "brake chopper protective circuit"},
    {0x7120, "motor"},
    {0x7121, "motor blocked"},
    {0x7122, "motor error or commutation malfunction"},
    {0x7123, "motor tilted"},
    {0x7200, "measurement circuit"},
    {0x7300, "sensor"},
    {0x7301, "tacho fault"},
    {0x7302, "tacho wrong polarity"},
    {0x7303, "resolver 1 fault"},
    {0x7304, "resolver 2 fault"},
    {0x7305, "incremental sensor 1 faulty"},
    {0x7306, "incremental sensor 2 faulty"},
    {0x7307, "incremental sensor 3 faulty"},
    {0x7310, "speed"},
    {0x7320, "position"},
    {0x7400, "computation circuit"},
    {0x7500, "communication"},
    {0x7510, "serial interface no. 1"},
    {0x7520, "serial interface no. 2"},
    {0x7600, "data storage (external)"},
    {0x8000, "monitoring"},
    {0x8100, "communication"},
    {0x8110, "CAN overrun (objects lost)"},
    {0x8120, "CAN in error passive mode"},
    {0x8130, "life guard error or heartbeat error"},
    {0x8140, "recovered from bus off"},
    {0x8150, "CAN-ID collision"},
    {0x8200, "protocol error"},
    {0x8210, "PDO not processed due to length error"},
    {0x8220, "PDO length exceeded"},
    {0x8230, "DAM MPDO not processed, destination object not available"},
    {0x8240, "unexpected SYNC data length"},
    {0x8250, "RPDO timeout"},
    {0x8300, "torque control"},
    {0x8311, "excess torque"},
    {0x8312, "difficult start-up"},
    {0x8313, "standstill torque"},
    {0x8321, "insufficient torque"},
    {0x8331, "torque fault"},
    {0x8400, "velocity speed controller"},
    {0x8500, "position controller"},
    {0x8600, "positioning controller"},
    {0x8611, "following error"},
    {0x8612, "reference limit"},
    {0x8700, "sync controller"},
    {0x8800, "winding controller"},
    {0x8900, "process data monitoring"},
    {0x8A00, "control"},
    {0x9000, "external error"},
    {0xF000, "additional functions"},
    {0xF001, "deceleration"},
    {0xF002, "sub-synchronous run"},
    {0xF003, "stroke operation"},
    {0xF004, "control"},
    {0xFF00, "device specific"},
});

constexpr bool sorted() {
    for (std::size_t i = 1; i < kTable.size(); ++i) {
        if (kTable[i - 1].code >= kTable[i].code) {
            return false;
        }
    }
    return true;
}
static_assert(sorted(), "EMCY code table must be sorted and unique");

const Row* find_exact(std::uint16_t code) {
    const auto* it = std::lower_bound(kTable.begin(), kTable.end(), code,
                                      [](const Row& r, std::uint16_t c) { return r.code < c; });
    return it != kTable.end() && it->code == code ? &*it : nullptr;
}

} // namespace

ErrorCodeInfo lookup_error_code(std::uint16_t code) {
    if (const Row* r = find_exact(code)) {
        return {r->text, code, true};
    }
    // The codes are hierarchical by nibble (CiA 301 §7.2.7.3.1): fall back to the class.
    for (const std::uint16_t mask :
         {std::uint16_t{0xFFF0}, std::uint16_t{0xFF00}, std::uint16_t{0xF000}}) {
        const auto cls = static_cast<std::uint16_t>(code & mask);
        if (cls == 0) {
            break; // 0000h is "no error", not a class
        }
        if (const Row* r = find_exact(cls)) {
            return {r->text, cls, false};
        }
    }
    return {};
}

std::string error_code_text(std::uint16_t code) {
    const ErrorCodeInfo info = lookup_error_code(code);
    if (info.text.empty()) {
        return "unknown error code";
    }
    if (info.exact) {
        return std::string(info.text);
    }
    return fmt::format("{} (class 0x{:04X})", info.text, info.matched);
}

} // namespace codrive::emcy
