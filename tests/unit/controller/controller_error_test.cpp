// SPDX-License-Identifier: Apache-2.0
// The controller's errors: a ControllerErrc to branch on and the unchanged sentence, for the
// failures found before any bus is opened (bus file, configuration); no I/O but a temp file.
#include <codrive/controller/controller.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace codrive;
using namespace codrive::controller;

namespace {

/// A bus file in the temp directory, removed again.
struct TempBusFile {
    std::filesystem::path path;
    explicit TempBusFile(const std::string& text) {
        path = std::filesystem::temp_directory_path() /
               ("codrive-ctlerr-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yml");
        std::ofstream(path) << text;
    }
    ~TempBusFile() { std::filesystem::remove(path); }
    TempBusFile(const TempBusFile&) = delete;
    TempBusFile& operator=(const TempBusFile&) = delete;
};

} // namespace

TEST(ControllerErrors, ABusFileWithFindingsIsBusFileInvalidWithEveryFindingOneALine) {
    // Node id 300 is out of range and the profile is unknown: two findings, both reported.
    const TempBusFile file("bus:\n"
                           "  interface: vcan0\n"
                           "nodes:\n"
                           "  - id: 300\n"
                           "  - id: 2\n"
                           "    profile: akd3g\n");
    const auto findings = check_bus_file(file.path.string());
    ASSERT_GE(findings.size(), 2U);
    auto c = Controller::from_file(file.path.string());
    ASSERT_FALSE(c);
    EXPECT_EQ(c.error().code, ControllerErrc::BusFileInvalid);
    EXPECT_NE(c.error().code, ControllerErrc::NodeBootFailed);
    EXPECT_FALSE(c.error().cause);
    std::string want;
    for (const auto& f : findings) {
        want += f + "\n";
    }
    EXPECT_EQ(c.error().detail, want);
    EXPECT_EQ(c.error().message(), want);
    EXPECT_EQ(c.error().to_string(), want);
    EXPECT_NE(c.error().detail.find(file.path.string() + ":4:"), std::string::npos)
        << c.error().detail;
}

TEST(ControllerErrors, AMissingBusFileIsBusFileInvalidNamingTheFile) {
    const std::string path = "/nonexistent/codrive/bus.yml";
    auto c = Controller::from_file(path);
    ASSERT_FALSE(c);
    EXPECT_EQ(c.error().code, ControllerErrc::BusFileInvalid);
    EXPECT_EQ(c.error().detail, path + ": cannot read the bus file\n");
}

TEST(ControllerErrors, NoBusAtAllIsInvalidConfiguration) {
    auto c = Controller::create({}, {}, {});
    ASSERT_FALSE(c);
    EXPECT_EQ(c.error().code, ControllerErrc::InvalidConfiguration);
    EXPECT_EQ(c.error().detail, "no bus configured");
}

TEST(ControllerErrors, TheCategoryNamesEveryCode) {
    const std::error_code ec = ControllerErrc::NodeBootFailed;
    EXPECT_STREQ(ec.category().name(), "codrive.controller");
    EXPECT_EQ(ec.message(), "a node failed its boot-up");
    EXPECT_EQ(to_string(ControllerErrc::NodeBootFailed), "node_boot_failed");
    EXPECT_EQ(to_string(ControllerErrc::BusFileInvalid), "bus_file_invalid");
    // Every code has its own message and name (none falls through to "unknown").
    for (int v = static_cast<int>(ControllerErrc::BusFileInvalid);
         v <= static_cast<int>(ControllerErrc::SyncFailed); ++v) {
        const auto e = static_cast<ControllerErrc>(v);
        EXPECT_NE(make_error_code(e).message(), "unknown controller error") << v;
        EXPECT_NE(to_string(e), "unknown") << v;
    }
    // A controller code never equals a lower layer's code with the same value.
    EXPECT_NE(ec, std::error_code(static_cast<int>(ControllerErrc::NodeBootFailed),
                                  std::generic_category()));
}
