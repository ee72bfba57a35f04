// SPDX-License-Identifier: Apache-2.0
// The device-file check can fail: copies of devices/*.eds and *.xml with one fact changed are
// fed through the same check the fact tables use, which must name the file, object and change.
#include "conformance.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace codrive::conformance {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// A temporary folder holding altered copies of the device files, removed afterwards.
class AlteredCopy {
public:
    AlteredCopy()
        : dir_(fs::temp_directory_path() / ("codrive-conformance-" + std::to_string(::getpid()))) {
        fs::create_directories(dir_);
    }
    ~AlteredCopy() {
        std::error_code ignored;
        fs::remove_all(dir_, ignored);
    }
    AlteredCopy(const AlteredCopy&) = delete;
    AlteredCopy& operator=(const AlteredCopy&) = delete;

    /// devices/<name> with the first `from` after `after` replaced by `to`; the path of the copy.
    std::string copy(const std::string& name, const std::string& after, const std::string& from,
                     const std::string& to) {
        std::string text = read_text(fs::path(CODRIVE_SOURCE_DIR) / "devices" / name);
        const auto anchor = text.find(after);
        EXPECT_NE(anchor, std::string::npos) << name << " has no " << after;
        const auto at = text.find(from, anchor == std::string::npos ? 0 : anchor);
        EXPECT_NE(at, std::string::npos) << name << " has no " << from << " after " << after;
        if (at != std::string::npos) {
            text.replace(at, from.size(), to);
        }
        const fs::path out = dir_ / name;
        std::ofstream(out, std::ios::binary) << text;
        return out.string();
    }

private:
    fs::path dir_;
};

/// The table's row for index:sub that states a default, or nullptr.
const Fact* row(std::span<const Fact> facts, std::uint16_t index, std::uint8_t sub) {
    const auto it = std::find_if(facts.begin(), facts.end(), [&](const Fact& f) {
        return f.index == index && f.sub == sub && f.value.has_value();
    });
    return it == facts.end() ? nullptr : &*it;
}

TEST(DeviceFileCheck, AnEdsWithAnotherDefaultFailsTheFact) {
    // §6.2.104: 606Dh velocity window, default 30 (1Eh); the copy says 31.
    const Fact* row_606d = row(ds_bvs_facts(), 0x606D, 0);
    ASSERT_NE(row_606d, nullptr) << "the DS-BVS table states 606Dh's default";
    const Fact& f = *row_606d;
    EXPECT_TRUE(DeviceFiles::of("ds-bvs").check("ds-bvs 606Dh:00", f).empty());
    AlteredCopy copy;
    const DeviceFiles altered(
        copy.copy("ds-bvs.eds", "[606D]", "DefaultValue=0x0000001E", "DefaultValue=0x0000001F"),
        "");
    const auto failures = altered.check("ds-bvs 606Dh:00", f);
    ASSERT_EQ(failures.size(), 1U);
    EXPECT_NE(failures[0].find("ds-bvs 606Dh:00"), std::string::npos) << failures[0];
    EXPECT_NE(failures[0].find("ds-bvs.eds: default 31, manual 30"), std::string::npos)
        << failures[0];
}

TEST(DeviceFileCheck, AnEsiWithAnotherDefaultOrAccessFailsTheFact) {
    const Fact* row_606d = row(ds_bvs_facts(), 0x606D, 0);
    ASSERT_NE(row_606d, nullptr) << "the DS-BVS table states 606Dh's default";
    const Fact& f = *row_606d;
    AlteredCopy copy;
    const DeviceFiles default_changed("",
                                      copy.copy("ds-bvs.xml", "<Index>#x606D</Index>",
                                                "<DefaultData>1E000000", "<DefaultData>1F000000"));
    const auto failures = default_changed.check("ds-bvs 606Dh:00", f);
    ASSERT_EQ(failures.size(), 1U);
    EXPECT_NE(failures[0].find("ds-bvs.xml: default 31, manual 30"), std::string::npos)
        << failures[0];
    const DeviceFiles read_only("", copy.copy("ds-bvs.xml", "<Index>#x606D</Index>",
                                              "<Access>rw</Access>", "<Access>ro</Access>"));
    const auto ro = read_only.check("ds-bvs 606Dh:00", f);
    ASSERT_EQ(ro.size(), 1U);
    EXPECT_NE(ro[0].find("ds-bvs.xml: access ro, manual rw"), std::string::npos) << ro[0];
}

TEST(DeviceFileCheck, AnObjectTheManualSaysTheDriveLacksFailsWhenTheFileListsIt) {
    // AKD2G §5.4: no 603Fh. A copy of the ESI that lists it fails the fact.
    const auto facts = akd2g_facts();
    const auto it = std::find_if(facts.begin(), facts.end(), [](const Fact& f) {
        return f.index == 0x603F && f.access == Acc::Absent;
    });
    ASSERT_NE(it, facts.end());
    EXPECT_TRUE(DeviceFiles::of("akd2g").check("akd2g 603Fh:00", *it).empty());
    AlteredCopy copy;
    const DeviceFiles listed(
        "", copy.copy("akd2g.xml", "<Objects>", "<Objects>",
                      "<Objects><Object><Index>#x603F</Index><Name>Error code</Name><Type>UINT"
                      "</Type><BitSize>16</BitSize><Info><DefaultData>0000</DefaultData></Info>"
                      "<Flags><Access>ro</Access></Flags></Object>"));
    const auto failures = listed.check("akd2g 603Fh:00", *it);
    ASSERT_EQ(failures.size(), 1U);
    EXPECT_NE(failures[0].find("akd2g.xml: the file lists it (manual: no such object)"),
              std::string::npos)
        << failures[0];
}

TEST(DeviceFileCheck, AFileThatCannotBeReadFailsEveryFactWithTheReason) {
    const Fact* row_606d = row(ds_bvs_facts(), 0x606D, 0);
    ASSERT_NE(row_606d, nullptr) << "the DS-BVS table states 606Dh's default";
    const Fact& f = *row_606d;
    const DeviceFiles missing("/nonexistent/ds-bvs.eds", "/nonexistent/ds-bvs.xml");
    const auto failures = missing.check("ds-bvs 606Dh:00", f);
    ASSERT_EQ(failures.size(), 2U);
    EXPECT_NE(failures[0].find("/nonexistent/ds-bvs.eds: cannot be read"), std::string::npos)
        << failures[0];
    EXPECT_NE(failures[1].find("/nonexistent/ds-bvs.xml: cannot be read"), std::string::npos)
        << failures[1];
}

} // namespace
} // namespace codrive::conformance
