// SPDX-License-Identifier: Apache-2.0
// The fact checker and the summary line of the conformance suite.
#include "conformance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <map>

namespace codrive::conformance {

namespace {

struct Tally {
    unsigned checked = 0;
    unsigned failed = 0;
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
        std::string per_drive;
        for (const auto& [drive, t] : tallies()) {
            per_drive += fmt::format("{}{} {}", per_drive.empty() ? "" : ", ", drive, t.checked);
            failed += t.failed;
        }
        std::printf("conformance: %s facts checked per drive, %u failed\n", per_drive.c_str(),
                    failed);
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

std::int64_t decode(DataType t, const std::vector<std::uint8_t>& d) {
    const std::uint64_t raw = get_le_n(d.data(), d.size());
    if (is_signed_integer(t) && !d.empty() && d.size() < 8) {
        const unsigned bits = static_cast<unsigned>(d.size() * 8);
        const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
        return static_cast<std::int64_t>((raw ^ sign) - sign);
    }
    return static_cast<std::int64_t>(raw);
}

std::string name_of(std::string_view drive, const Fact& f) {
    return fmt::format("{} {:04X}h:{:02X} ({})", drive, f.index, f.sub, f.section);
}

/// The simulator through the protocol; returns the failures.
std::vector<std::string> check_sim(std::string_view drive, Probe& probe, const Fact& f) {
    std::vector<std::string> out;
    const std::string what = name_of(drive, f);
    const Reply r = probe.upload(f.index, f.sub);
    if (f.access == Acc::Absent) {
        if (r.ok || (r.abort != 0x06020000U && r.abort != 0x06090011U)) {
            out.push_back(fmt::format("{}: simulator has it (manual: no such object)", what));
        }
        return out;
    }
    if (!r.ok) {
        out.push_back(fmt::format("{}: simulator aborts the upload 0x{:08X}", what, r.abort));
        return out;
    }
    if (r.data.size() != data_type_size(f.type)) {
        out.push_back(fmt::format("{}: simulator answers {} bytes, {} has {}", what, r.data.size(),
                                  to_string(f.type), data_type_size(f.type)));
        return out;
    }
    if (f.value && decode(f.type, r.data) != *f.value) {
        out.push_back(fmt::format("{}: simulator default {}, manual {}", what,
                                  decode(f.type, r.data), *f.value));
    }
    // Access: writing the value back must succeed on rw and abort 06010002h on ro.
    const Reply w = probe.download(f.index, f.sub, r.data);
    if (f.access == Acc::Rw && !w.ok) {
        out.push_back(
            fmt::format("{}: simulator refuses a write (0x{:08X}), manual: rw", what, w.abort));
    } else if (f.access == Acc::Ro && (w.ok || w.abort != 0x06010002U)) {
        out.push_back(fmt::format("{}: simulator write gives {}, manual: ro (06010002h)", what,
                                  w.ok ? std::string("success") : fmt::format("{:08X}", w.abort)));
    }
    return out;
}

/// The master's profile (drives::device_objects): same type, default, access class.
std::vector<std::string> check_profile(std::string_view drive, const drives::Profile& p,
                                       const Fact& f) {
    std::vector<std::string> out;
    if (!f.in_profile) {
        return out;
    }
    const std::string what = name_of(drive, f);
    const auto objects = drives::device_objects(p, 1);
    const auto it = std::find_if(objects.begin(), objects.end(), [&](const drives::ObjectSpec& s) {
        return s.index == f.index && s.subindex == f.sub;
    });
    if (f.access == Acc::Absent) {
        if (p.has_object(f.index)) {
            out.push_back(
                fmt::format("{}: master profile lists it (manual: no such object)", what));
        }
        return out;
    }
    if (it == objects.end()) {
        out.push_back(fmt::format("{}: master profile does not describe it", what));
        return out;
    }
    if (it->type != f.type) {
        out.push_back(fmt::format("{}: master profile type {}, manual {}", what,
                                  to_string(it->type), to_string(f.type)));
    }
    if (f.value && it->default_value != *f.value) {
        out.push_back(fmt::format("{}: master profile default {}, manual {}", what,
                                  it->default_value, *f.value));
    }
    if (writable(it->access) != (f.access == Acc::Rw)) {
        out.push_back(fmt::format("{}: master profile access {}, manual {}", what,
                                  writable(it->access) ? "rw" : "ro",
                                  f.access == Acc::Rw ? "rw" : "ro"));
    }
    return out;
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

void check_facts(std::string_view drive, const drives::Profile& profile, Probe& probe,
                 std::span<const Fact> facts) {
    Tally& t = tallies()[std::string(drive)];
    for (const Fact& f : facts) {
        auto failures = check_sim(drive, probe, f);
        const auto master = check_profile(drive, profile, f);
        failures.insert(failures.end(), master.begin(), master.end());
        ++t.checked;
        if (!failures.empty()) {
            ++t.failed;
        }
        for (const auto& m : failures) {
            ADD_FAILURE() << m;
        }
    }
}

} // namespace codrive::conformance
