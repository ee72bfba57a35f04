// SPDX-License-Identifier: Apache-2.0
// The shared SDO abort table.
#include <codrive/core/sdo_abort.hpp>

#include <gtest/gtest.h>

using namespace codrive;

TEST(SdoAbort, EveryCodeHasTextAndAscendingOrder) {
    std::uint32_t last = 0;
    for (SdoAbort a : all_sdo_aborts()) {
        const auto code = static_cast<std::uint32_t>(a);
        EXPECT_GT(code, last);
        last = code;
        EXPECT_TRUE(sdo_abort_text(code).has_value());
    }
    EXPECT_EQ(all_sdo_aborts().size(), 31U);
}

TEST(SdoAbort, ErrorCodeMessageCarriesCodeAndText) {
    const std::error_code ec = SdoAbort::NoObject;
    EXPECT_EQ(ec.message(), "0x06020000 object does not exist in the object dictionary");
    EXPECT_EQ(sdo_abort_describe(0x12345678), "unknown abort code");
}
