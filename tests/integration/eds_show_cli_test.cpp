// SPDX-License-Identifier: Apache-2.0
// `codrive eds show` on a real EDS (CANopenDemo's demo device): values the file does not give are
// shown as absent, as python-canopen (an independent CiA 306 reader) reads them.
#include <codrive/testing/process.hpp>
#include <codrive/testing/text.hpp>

#include <gtest/gtest.h>

#include <string>

using namespace std::chrono_literals;
namespace ct = codrive::testing;
using codrive::testing::has;

namespace {

const std::string kDemo =
    std::string(CODRIVE_SOURCE_DIR) + "/tests/data/eds/real/canopendemo-demodevice.eds";

} // namespace

TEST(EdsShowCli, EmptyDefaultValueIsShownAsNoDefault) {
    // [1003sub1] has "DefaultValue=" (empty): no default, not 0x00000000.
    const auto r = ct::run({ct::tool_path("codrive"), "eds", "show", kDemo, "1003:1"}, 20s);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(has(r.output, "Standard error field   UNSIGNED32  ro      -    (no default)"))
        << r.output;
    EXPECT_FALSE(has(r.output, "0x00000000")) << r.output;
}

TEST(EdsShowCli, GivenDefaultsAndNodeIdExpressionsAreStillShown) {
    const auto r =
        ct::run({ct::tool_path("codrive"), "eds", "show", kDemo, "1014", "--node-id", "5"}, 20s);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(has(r.output, "0x00000085 ($NODEID+0x80)")) << r.output;
    const auto t = ct::run({ct::tool_path("codrive"), "eds", "show", kDemo, "1017"}, 20s);
    ASSERT_EQ(t.status, 0) << t.output;
    EXPECT_FALSE(has(t.output, "(no default)")) << t.output;
}
