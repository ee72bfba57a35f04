// SPDX-License-Identifier: Apache-2.0
// `codrive eds export` / `codrive esi export` as devices/regenerate.sh runs them: they write the
// committed devices/ files byte for byte, and refuse an unknown profile or too many axes.
#include <codrive/testing/process.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace std::chrono_literals;
namespace ct = codrive::testing;

namespace {

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

const std::filesystem::path kDevices = std::filesystem::path(CODRIVE_SOURCE_DIR) / "devices";

// The profiles devices/regenerate.sh exports (its `for profile in ...` line).
std::vector<std::string> regenerated_profiles() {
    const std::string script = read_text(kDevices / "regenerate.sh");
    std::smatch m;
    std::vector<std::string> out;
    if (std::regex_search(script, m, std::regex("for profile in ([a-z0-9 -]+); do"))) {
        std::istringstream words(m[1].str());
        for (std::string w; words >> w;) {
            out.push_back(w);
        }
    }
    return out;
}

} // namespace

TEST(DeviceExportCli, RegenerateScriptCoversEveryCommittedFile) {
    std::vector<std::string> committed;
    for (const auto& e : std::filesystem::directory_iterator(kDevices)) {
        if (e.path().extension() == ".eds") {
            committed.push_back(e.path().stem().string());
        }
    }
    std::sort(committed.begin(), committed.end());
    auto listed = regenerated_profiles();
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(listed, committed);
    EXPECT_EQ(listed, (std::vector<std::string>{"akd2g", "ds-bvs", "fio"}));
}

TEST(DeviceExportCli, ExportWritesTheCommittedFilesByteForByte) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("codrive-export-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const std::string& profile : regenerated_profiles()) {
        for (const char* kind : {"eds", "esi"}) {
            const std::string ext = std::string(kind) == "eds" ? ".eds" : ".xml";
            const auto out = dir / (profile + ext);
            const auto r = ct::run({ct::tool_path("codrive"), kind, "export", "--profile", profile,
                                    "-o", out.string()},
                                   20s);
            ASSERT_EQ(r.status, 0) << r.output;
            EXPECT_EQ(read_text(out), read_text(kDevices / (profile + ext)))
                << profile << ext << ": run devices/regenerate.sh";
        }
    }
    std::filesystem::remove_all(dir);
}

TEST(DeviceExportCli, UnknownProfileAndTooManyAxesAreUsageErrorsWithASentence) {
    auto r = ct::run({ct::tool_path("codrive"), "eds", "export", "--profile", "akd3g"}, 20s);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("codrive eds export: unknown profile `akd3g` (known: akd2g, ds-bvs, "
                            "fio, generic)"),
              std::string::npos)
        << r.output;
    r = ct::run({ct::tool_path("codrive"), "esi", "export", "--profile", "fio", "--axes", "2"},
                20s);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("codrive esi export: profile `fio` has at most 1 axis, not 2"),
              std::string::npos)
        << r.output;
    r = ct::run({ct::tool_path("codrive"), "esi", "export", "--profile", "fio", "-o",
                 "/nonexistent-dir/fio.xml"},
                20s);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("codrive esi export: cannot write /nonexistent-dir/fio.xml"),
              std::string::npos)
        << r.output;
}
