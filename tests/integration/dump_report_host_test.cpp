// SPDX-License-Identifier: Apache-2.0
// codrive-dump --report as a user sees it: the commands docs/codrive-dump.md shows, then the page
// opened in headless Chromium (Debian's `chromium`, no network): it loads without console
// errors, every chart has data points from the trace, and a screenshot is kept under the build
// directory (test-artifacts/codrive-dump-report.png).
#include "dump_scratch.hpp"

#include <codrive/testing/process.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

using namespace std::chrono_literals;
namespace ct = codrive::testing;

namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Chromium headless as root in a scratch profile, every message (console included) on stderr.
std::string chromium(const ct::dump::Scratch& scratch, const std::string& args) {
    const auto r = scratch.shell("chromium --headless --disable-gpu --no-sandbox "
                                 "--enable-logging=stderr --v=0 --user-data-dir=chromium-profile " +
                                     args + " 2>chromium.err",
                                 120s);
    EXPECT_EQ(r.status, 0) << args << "\n" << slurp(scratch.path() + "/chromium.err");
    return r.output;
}

} // namespace

TEST(DumpReportHost, DocumentedReportOpensInChromiumWithEveryChartFilled) {
    const auto commands =
        ct::dump::documented_commands("tests/integration/dump_report_host_test.cpp");
    ASSERT_EQ(commands.size(), 2U) << "docs/codrive-dump.md lost its --report commands";
    ct::dump::Scratch scratch("report");
    for (const auto& c : commands) {
        const auto r = scratch.shell(c + " 2>&1", 120s);
        ASSERT_EQ(r.status, 0) << c << "\n" << r.output;
    }
    const std::string page_path = scratch.path() + "/report.html";
    const std::string page = slurp(page_path);
    ASSERT_GT(page.size(), 50'000U) << "uPlot is not inlined";
    // Self-contained: nothing is loaded from elsewhere.
    for (const char* ref :
         {"src=\"http", "href=\"http", "src='http", "url(http", "@import", "<link", "<iframe"}) {
        EXPECT_EQ(page.find(ref), std::string::npos) << ref;
    }

    const std::string dom = chromium(scratch, "--dump-dom file://" + page_path);
    const std::string err = slurp(scratch.path() + "/chromium.err");
    // A console message or an uncaught exception is logged as "...:CONSOLE...".
    EXPECT_EQ(err.find(":CONSOLE"), std::string::npos) << err;
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(dom, m, std::regex("<pre id=\"codrive-check\"[^>]*>([^<]*)</pre>")))
        << "the page script did not finish:\n"
        << dom.substr(0, 2000);
    const std::string check = m[1];
    EXPECT_NE(check.find("\"errors\":[]"), std::string::npos) << check;
    for (const char* chart : {"chart-load", "chart-hb", "chart-sync", "chart-sdo", "chart-pdo",
                              "chart-latency", "chart-events"}) {
        std::smatch c;
        ASSERT_TRUE(
            std::regex_search(check, c, std::regex(std::string("\"") + chart + "\":([0-9]+)")))
            << chart << " missing: " << check;
        EXPECT_GT(std::stoul(c[1]), 0U) << chart << " has no data points: " << check;
    }
    // The generated line has four drives; their rows and the EMCY events are in the tables.
    EXPECT_NE(check.find("\"nodes\":4"), std::string::npos) << check;
    EXPECT_EQ(check.find("\"events\":0"), std::string::npos) << check;
    EXPECT_NE(dom.find("continuous over-current"), std::string::npos);
    // uPlot drew: one canvas per chart.
    std::size_t canvases = 0;
    for (auto at = dom.find("<canvas"); at != std::string::npos; at = dom.find("<canvas", at + 1)) {
        ++canvases;
    }
    EXPECT_EQ(canvases, 7U);

    // The screenshot, kept as the test's artefact next to the tools of this build.
    const auto artefacts =
        std::filesystem::path(ct::tool_path("codrive-dump")).parent_path().parent_path() /
        "test-artifacts";
    std::filesystem::create_directories(artefacts);
    const auto png = artefacts / "codrive-dump-report.png";
    std::filesystem::remove(png);
    (void)chromium(scratch, "--hide-scrollbars --window-size=1200,3800 --screenshot=" +
                                png.string() + " file://" + page_path);
    ASSERT_TRUE(std::filesystem::exists(png));
    EXPECT_GT(std::filesystem::file_size(png), 50'000U) << "a blank page?";
}
