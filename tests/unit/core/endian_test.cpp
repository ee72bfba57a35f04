// SPDX-License-Identifier: Apache-2.0
// Little-endian codecs.
#include <codrive/core/endian.hpp>

#include <array>
#include <gtest/gtest.h>

using namespace codrive;

TEST(Endian, RoundTripsIntegersAndFloats) {
    std::array<std::uint8_t, 8> b{};
    put_le<std::uint32_t>(b.data(), 0x11223344);
    EXPECT_EQ(b[0], 0x44);
    EXPECT_EQ(b[3], 0x11);
    EXPECT_EQ(get_le<std::uint32_t>(b.data()), 0x11223344U);
    put_le<std::int16_t>(b.data(), -2);
    EXPECT_EQ(get_le<std::int16_t>(b.data()), -2);
    put_le<float>(b.data(), 1.5F);
    EXPECT_FLOAT_EQ(get_le<float>(b.data()), 1.5F);
    put_le<double>(b.data(), -0.25);
    EXPECT_DOUBLE_EQ(get_le<double>(b.data()), -0.25);
}

TEST(Endian, VariableWidth) {
    std::array<std::uint8_t, 8> b{};
    put_le_n(b.data(), 0xABCDEF, 3);
    EXPECT_EQ(get_le_n(b.data(), 3), 0xABCDEFU);
    EXPECT_EQ(b[3], 0);
}
