// SPDX-License-Identifier: Apache-2.0
// The fact checker and the summary line of the conformance suite.
#include "conformance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <map>
#include <utility>

namespace codrive::conformance {

std::int64_t decode(DataType t, const std::vector<std::uint8_t>& d) {
    const std::uint64_t raw = get_le_n(d.data(), d.size());
    if (is_signed_integer(t) && !d.empty() && d.size() < 8) {
        const unsigned bits = static_cast<unsigned>(d.size() * 8);
        const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
        return static_cast<std::int64_t>((raw ^ sign) - sign);
    }
    return static_cast<std::int64_t>(raw);
}

std::pair<std::int64_t, std::int64_t> type_range(DataType t) {
    const auto bits = static_cast<unsigned>(data_type_size(t) * 8);
    if (is_signed_integer(t)) {
        return {-(std::int64_t{1} << (bits - 1)), (std::int64_t{1} << (bits - 1)) - 1};
    }
    return {0, bits >= 63 ? INT64_MAX : (std::int64_t{1} << bits) - 1};
}

namespace {

struct Tally {
    unsigned checked = 0;      ///< facts checked at all (any of the four ways)
    unsigned failed = 0;       ///< facts that failed any way
    unsigned file_checked = 0; ///< facts checked against a device file
    unsigned file_failed = 0;  ///< facts a device file gets wrong
    unsigned sim_failed = 0;   ///< facts a simulator or the master's profile gets wrong
    unsigned unexpected = 0;   ///< failed facts no known divergence covers (they fail the test)
};

std::map<std::string, Tally>& tallies() {
    static std::map<std::string, Tally> t;
    return t;
}

/// Prints the summary once every test has run.
class SummaryEnvironment final : public ::testing::Environment {
public:
    void TearDown() override {
        unsigned failed = 0;
        unsigned file_failed = 0;
        unsigned sim_failed = 0;
        unsigned unexpected = 0;
        std::string per_drive;
        std::string per_drive_file;
        for (const auto& [drive, t] : tallies()) {
            per_drive += fmt::format("{}{} {}", per_drive.empty() ? "" : ", ", drive, t.checked);
            per_drive_file +=
                fmt::format("{}{} {}", per_drive_file.empty() ? "" : ", ", drive, t.file_checked);
            failed += t.failed;
            file_failed += t.file_failed;
            sim_failed += t.sim_failed;
            unexpected += t.unexpected;
        }
        // A fact differs if any way of checking it fails; a difference a known divergence
        // covers is printed and counted but passes, an unexpected one fails its test. The other
        // parts say how many were checked against devices/*.eds and *.xml and how many differ
        // there and on the simulators and profiles.
        std::printf("conformance: %s facts checked per drive, %u differ from the manual (%u known "
                    "divergences, %u unexpected); device files (EDS, ESI): %s facts checked, %u "
                    "differ; simulators and profiles: %u differ\n",
                    per_drive.c_str(), failed, failed - unexpected, unexpected,
                    per_drive_file.c_str(), file_failed, sim_failed);
    }
};

[[maybe_unused]] const auto* const kSummary =
    ::testing::AddGlobalTestEnvironment(new SummaryEnvironment);

std::uint32_t abort_of(const std::error_code& e) {
    if (e.category() == make_error_code(SdoAbort::NoObject).category()) {
        return static_cast<std::uint32_t>(e.value());
    }
    return 0xFFFFFFFFU; // not an SDO abort (timeout, protocol error)
}

std::string name_of(std::string_view drive, const Fact& f) {
    return fmt::format("{} {:04X}h:{:02X} ({}, manual line {})", drive, f.index, f.sub, f.section,
                       f.line);
}

std::vector<std::uint8_t> encode(DataType t, std::int64_t v) {
    std::vector<std::uint8_t> b(data_type_size(t));
    for (std::size_t i = 0; i < b.size(); ++i) {
        b[i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * i));
    }
    return b;
}

std::string reply_text(const Reply& r) {
    return r.ok ? std::string("success") : fmt::format("abort {:08X}h", r.abort);
}

/// Out-of-range writes (CiA 301 §7.2.4.3.17: 06090030h value range exceeded, 06090031h too high,
/// 06090032h too low) where the manual gives limits narrower than the type.
void check_limits(const std::string& what, Probe& probe, const Fact& f,
                  std::vector<std::string>& out) {
    const auto [type_low, type_high] = type_range(f.type);
    if (f.low && *f.low > type_low) {
        const Reply r = probe.download(f.index, f.sub, encode(f.type, *f.low - 1));
        if (r.ok || (r.abort != 0x06090030U && r.abort != 0x06090032U)) {
            out.push_back(fmt::format("{}: writing {} (below the manual's {}) gives {}", what,
                                      *f.low - 1, *f.low, reply_text(r)));
        }
    }
    if (f.high && *f.high < type_high) {
        const Reply r = probe.download(f.index, f.sub, encode(f.type, *f.high + 1));
        if (r.ok || (r.abort != 0x06090030U && r.abort != 0x06090031U)) {
            out.push_back(fmt::format("{}: writing {} (above the manual's {}) gives {}", what,
                                      *f.high + 1, *f.high, reply_text(r)));
        }
    }
}

bool is_pdo_map(std::uint16_t index) {
    return (index >= 0x1600 && index <= 0x17FF) || (index >= 0x1A00 && index <= 0x1BFF);
}

/// Objects CiA 301 lets a master change only while the PDO is invalid: the mapping entries and
/// count (§7.5.2.36/§7.5.2.38) and the inhibit time (§7.5.2.35: sub 03h "shall not be changed
/// while the PDO exists").
bool needs_invalid_pdo(const Fact& f) {
    const bool comm =
        (f.index >= 0x1400 && f.index <= 0x15FF) || (f.index >= 0x1800 && f.index <= 0x19FF);
    return f.access == Acc::Rw && (is_pdo_map(f.index) || (comm && f.sub == 3));
}

/// Writes a PDO mapping sub-index (or the inhibit time) the way CiA 301 §7.5.2.35/§7.5.2.37 and the
/// manuals (DS-BVS §6.2.14 a-c) describe: the PDO made invalid in its communication parameter
/// (where the drive lets the master write it), sub 0 set to 0, the entry written, then both
/// restored.
Reply remap(Probe& probe, const Fact& f, const std::vector<std::uint8_t>& value) {
    const auto comm = is_pdo_map(f.index) ? static_cast<std::uint16_t>(f.index - 0x200) : f.index;
    const Reply cob = probe.upload(comm, 1);
    bool invalidated = false;
    if (cob.ok && cob.data.size() == 4) {
        const std::uint32_t id = get_le<std::uint32_t>(cob.data.data());
        invalidated = probe.write<std::uint32_t>(comm, 1, id | 0x80000000U).ok;
    }
    const Reply count = probe.upload(f.index, 0);
    Reply w;
    if (f.sub == 0 || !is_pdo_map(f.index)) {
        w = probe.download(f.index, f.sub, value);
    } else {
        probe.write<std::uint8_t>(f.index, 0, 0);
        w = probe.download(f.index, f.sub, value);
        if (count.ok) {
            probe.download(f.index, 0, count.data);
        }
    }
    if (invalidated) {
        probe.download(comm, 1, cob.data);
    }
    return w;
}

/// The simulator through one protocol; appends the failures.
void check_sim(const std::string& what, Probe& probe, const Fact& f,
               std::vector<std::string>& out) {
    const Reply r = probe.upload(f.index, f.sub);
    if (f.access == Acc::Absent) {
        if (r.ok || (r.abort != 0x06020000U && r.abort != 0x06090011U)) {
            out.push_back(fmt::format("{}: simulator has it (manual: no such object)", what));
        }
        return;
    }
    if (!r.ok) {
        out.push_back(fmt::format("{}: simulator aborts the upload 0x{:08X}", what, r.abort));
        return;
    }
    if (r.data.size() != data_type_size(f.type)) {
        out.push_back(fmt::format("{}: simulator answers {} bytes, {} has {}", what, r.data.size(),
                                  to_string(f.type), data_type_size(f.type)));
        return;
    }
    if (f.value && decode(f.type, r.data) != *f.value) {
        out.push_back(fmt::format("{}: simulator default {}, manual {}", what,
                                  decode(f.type, r.data), *f.value));
    }
    // Access: writing the value back must succeed on rw and abort 06010002h on ro.
    const Reply w =
        needs_invalid_pdo(f) ? remap(probe, f, r.data) : probe.download(f.index, f.sub, r.data);
    if (f.access == Acc::Rw && !w.ok) {
        out.push_back(
            fmt::format("{}: simulator refuses a write (0x{:08X}), manual: rw", what, w.abort));
    } else if (f.access == Acc::Ro && (w.ok || w.abort != 0x06010002U)) {
        out.push_back(fmt::format("{}: simulator write gives {}, manual: ro (06010002h)", what,
                                  reply_text(w)));
    }
    if (f.access == Acc::Rw) {
        check_limits(what, probe, f, out);
    }
}

/// The profile's description of index:sub for any of its axes, or nullopt.
std::optional<drives::ObjectSpec> find_spec(const drives::Profile& p, std::uint16_t index,
                                            std::uint8_t sub) {
    static std::map<const drives::Profile*, std::vector<drives::ObjectSpec>> cache;
    auto [it, fresh] = cache.try_emplace(&p);
    if (fresh) {
        for (unsigned axis = 1; axis <= std::max<unsigned>(p.max_axes, 1); ++axis) {
            const auto objects = drives::device_objects(p, axis);
            it->second.insert(it->second.end(), objects.begin(), objects.end());
        }
    }
    for (const drives::ObjectSpec& s : it->second) {
        if (s.index == index && s.subindex == sub) {
            return s;
        }
    }
    return std::nullopt;
}

/// The master's profile (drives::device_objects): same type, default, access class and limits.
/// Every CiA 402 object (6000h..6FFFh) must be described; other objects are compared where the
/// profile describes them (communication objects belong to the CANopen/CoE stack).
bool check_profile(const std::string& what, const drives::Profile& p, const Fact& f,
                   std::vector<std::string>& out) {
    const auto spec = find_spec(p, f.index, f.sub);
    if (f.access == Acc::Absent) {
        if (spec || (f.index < 0x6800 && p.has_object(f.index) && f.index >= 0x6000)) {
            out.push_back(
                fmt::format("{}: master profile lists it (manual: no such object)", what));
        }
        return true;
    }
    const auto base = static_cast<std::uint16_t>(f.index >= 0x6800 ? f.index - 0x800 : f.index);
    if (!spec && base == 0x60E3 && f.sub >= 1) {
        // 60E3h is built from the profile's homing method list, in the manual's order.
        const auto& methods = p.homing_methods;
        if (f.sub > methods.size() || (f.value && methods[f.sub - 1U] != *f.value)) {
            out.push_back(fmt::format("{}: master profile homing method {}, manual {}", what,
                                      f.sub > methods.size() ? std::string("none")
                                                             : std::to_string(methods[f.sub - 1U]),
                                      f.value.value_or(0)));
        }
        return true;
    }
    if (!spec && f.sub == 0) {
        // Sub 0 of a record the profile describes: "highest sub-index supported", UNSIGNED8 ro.
        const auto first = find_spec(p, f.index, 1);
        if (first && first->record) {
            if (f.type != DataType::Unsigned8 || f.access != Acc::Ro) {
                out.push_back(fmt::format("{}: master profile has sub 0 as UNSIGNED8 ro", what));
            }
            return true;
        }
    }
    if (!spec) {
        if (f.index >= 0x6000 && f.index < 0x7000) {
            out.push_back(fmt::format("{}: master profile does not describe it", what));
            return true;
        }
        return false;
    }
    if (spec->type != f.type) {
        out.push_back(fmt::format("{}: master profile type {}, manual {}", what,
                                  to_string(spec->type), to_string(f.type)));
    }
    if (f.value && p.documents_defaults && spec->default_value != *f.value) {
        out.push_back(fmt::format("{}: master profile default {}, manual {}", what,
                                  spec->default_value, *f.value));
    }
    if (writable(spec->access) != (f.access == Acc::Rw)) {
        out.push_back(fmt::format("{}: master profile access {}, manual {}", what,
                                  writable(spec->access) ? "rw" : "ro",
                                  f.access == Acc::Rw ? "rw" : "ro"));
    }
    const auto [type_low, type_high] = type_range(f.type);
    const std::int64_t low = f.low.value_or(type_low);
    const std::int64_t high = f.high.value_or(type_high);
    if ((f.low || f.high) && (!spec->has_limits || spec->low != low || spec->high != high)) {
        out.push_back(fmt::format("{}: master profile range {}, manual {}..{}", what,
                                  spec->has_limits ? fmt::format("{}..{}", spec->low, spec->high)
                                                   : std::string("none"),
                                  low, high));
    }
    return true;
}

} // namespace

Reply CanProbe::upload(std::uint16_t index, std::uint8_t sub) {
    auto r = fixture_.read<sdo::Bytes>(index, sub);
    if (!r) {
        return Reply{false, {}, r.error().abort_code().value_or(0xFFFFFFFFU)};
    }
    return Reply{true, std::vector<std::uint8_t>(r->begin(), r->end()), 0};
}

Reply CanProbe::download(std::uint16_t index, std::uint8_t sub, std::vector<std::uint8_t> data) {
    auto r = fixture_.write<sdo::Bytes>(index, sub, sdo::Bytes(data.begin(), data.end()));
    if (!r) {
        return Reply{false, {}, r.error().abort_code().value_or(0xFFFFFFFFU)};
    }
    return Reply{true, {}, 0};
}

EcatProbe::EcatProbe(std::string_view profile) {
    segment_.add(sim::ecat::make_drive_slave(profile, 1));
    EXPECT_TRUE(master_.scan()) << master_.last_error();
    EXPECT_TRUE(master_.set_state_all(ethercat::AlState::PreOp)) << master_.last_error();
}

Reply EcatProbe::upload(std::uint16_t index, std::uint8_t sub) {
    auto r = master_.sdo_upload(0, index, sub);
    if (!r) {
        return Reply{false, {}, abort_of(r.error())};
    }
    return Reply{true, std::move(*r), 0};
}

Reply EcatProbe::download(std::uint16_t index, std::uint8_t sub, std::vector<std::uint8_t> data) {
    auto r = master_.sdo_download(0, index, sub, data);
    if (!r) {
        return Reply{false, {}, abort_of(r.error())};
    }
    return Reply{true, {}, 0};
}

/// The known divergence that covers a fact in one place, or nullptr.
const KnownDivergence* find_known(std::span<const KnownDivergence> known, const Fact& f, In in) {
    for (const KnownDivergence& d : known) {
        const bool covers = d.last != 0 ? (f.index >= d.index && f.index <= d.last)
                                        : (f.index == d.index && f.sub == d.sub);
        if (covers && d.in == in) {
            return &d;
        }
    }
    return nullptr;
}

void check_facts(std::string_view drive, const drives::Profile& profile, Probe* can, Probe* ecat,
                 const DeviceFiles& files, std::span<const Fact> facts,
                 std::span<const KnownDivergence> known) {
    Tally& t = tallies()[std::string(drive)];
    std::map<const KnownDivergence*, unsigned> seen; // failing facts per known divergence
    for (const Fact& f : facts) {
        std::vector<std::string> failures;
        const std::string what = name_of(drive, f);
        bool checked = false;
        if (can != nullptr && f.bus != Bus::Ecat) {
            check_sim(what + " CAN", *can, f, failures);
            checked = true;
        }
        if (ecat != nullptr && f.bus != Bus::Can) {
            check_sim(what + " CoE", *ecat, f, failures);
            checked = true;
        }
        checked = check_profile(what, profile, f, failures) || checked;
        const bool file_checked = files.applies(f);
        const std::vector<std::string> file_failures = files.check(what, f);
        if (!checked && !file_checked) {
            continue; // no simulator for its bus here, not a profile object, no file
        }
        ++t.checked;
        t.file_checked += file_checked ? 1U : 0U;
        t.failed += failures.empty() && file_failures.empty() ? 0U : 1U;
        t.file_failed += file_failures.empty() ? 0U : 1U;
        t.sim_failed += failures.empty() ? 0U : 1U;
        bool fact_unexpected = false;
        for (const auto& [in, list] : {std::pair{In::SimOrProfile, &std::as_const(failures)},
                                       std::pair{In::DeviceFile, &file_failures}}) {
            if (list->empty()) {
                continue;
            }
            const KnownDivergence* k = find_known(known, f, in);
            if (k == nullptr) {
                for (const auto& m : *list) {
                    ADD_FAILURE() << m;
                }
                fact_unexpected = true;
                continue;
            }
            ++seen[k];
            for (const auto& m : *list) {
                std::printf("known divergence: %s [%s]\n", m.c_str(), k->reason);
            }
        }
        t.unexpected += fact_unexpected ? 1U : 0U;
    }
    // A known divergence no fact shows any more is fixed: the list and the docs must say so.
    for (const KnownDivergence& d : known) {
        if (seen.find(&d) == seen.end()) {
            ADD_FAILURE() << fmt::format(
                "{} {:04X}h{}: listed as a known divergence{} ({}) but conforms now: remove it "
                "from the list and docs/conformance.md",
                drive, d.index,
                d.last != 0 ? fmt::format("-{:04X}h", d.last) : fmt::format(":{:02X}", d.sub),
                d.in == In::DeviceFile ? " of the device files" : "", d.reason);
        }
    }
}

} // namespace codrive::conformance
