// SPDX-License-Identifier: Apache-2.0
// EMCY decoding, error-code texts, error register and vendor text hooks.
#include <codrive/emcy/error_codes.hpp>
#include <codrive/emcy/error_register.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/emcy/text_provider.hpp>

#include <gtest/gtest.h>

namespace codrive::emcy {
namespace {

TEST(EmcyDecode, ParsesCodeRegisterAndManufacturerBytes) {
    auto m = parse_emcy(Frame::make(0x083, {0x10, 0x23, 0x03, 0x00, 0x01, 0x02, 0x03, 0x04}));
    ASSERT_TRUE(m);
    EXPECT_EQ(m->node, 3);
    EXPECT_EQ(m->error_code, 0x2310);
    EXPECT_EQ(m->error_register, 0x03);
    EXPECT_EQ(m->manufacturer, (std::array<std::uint8_t, 5>{0, 1, 2, 3, 4}));
    EXPECT_EQ(describe(*m), "node 3: EMCY 0x2310 continuous over-current (error register 0x03: "
                            "generic, current) [manufacturer 00 01 02 03 04]");
}

TEST(EmcyDecode, SentencesForSeveralCodes) {
    struct Case {
        std::uint16_t code;
        std::uint8_t reg;
        const char* text;
    };
    for (const auto& c : {
             Case{0x3210, 0x05,
                  "node 9: EMCY 0x3210 DC link over-voltage (error register 0x05: generic, "
                  "voltage) [manufacturer 00 00 00 00 00]"},
             Case{0x4310, 0x09,
                  "node 9: EMCY 0x4310 excess drive temperature (error register 0x09: generic, "
                  "temperature) [manufacturer 00 00 00 00 00]"},
             Case{0x7305, 0x01,
                  "node 9: EMCY 0x7305 incremental sensor 1 faulty (error register 0x01: "
                  "generic) [manufacturer 00 00 00 00 00]"},
             Case{0x8611, 0x21,
                  "node 9: EMCY 0x8611 following error (error register 0x21: generic, device "
                  "profile) [manufacturer 00 00 00 00 00]"},
             Case{0x8130, 0x11,
                  "node 9: EMCY 0x8130 life guard error or heartbeat error (error register "
                  "0x11: generic, communication) [manufacturer 00 00 00 00 00]"},
             Case{0x0000, 0x00,
                  "node 9: EMCY 0x0000 error reset or no error (error register 0x00: none) "
                  "[manufacturer 00 00 00 00 00]"},
             Case{0xFF02, 0x80,
                  "node 9: EMCY 0xFF02 device specific (class 0xFF00) (error register 0x80: "
                  "manufacturer) [manufacturer 00 00 00 00 00]"},
         }) {
        EmcyMessage m;
        m.node = 9;
        m.error_code = c.code;
        m.error_register = c.reg;
        EXPECT_EQ(describe(m), c.text);
    }
}

TEST(EmcyCodes, ExactCodesAndClassFallback) {
    EXPECT_EQ(error_code_text(0x5441), "contact 1 (manufacturer-specific)");
    EXPECT_EQ(error_code_text(0x8110), "CAN overrun (objects lost)");
    EXPECT_EQ(error_code_text(0x8240), "unexpected SYNC data length");
    EXPECT_EQ(error_code_text(0x2315), "continuous over-current (class 0x2310)");
    EXPECT_EQ(error_code_text(0x4391), "drive temperature (class 0x4300)");
    EXPECT_EQ(error_code_text(0x37AD), "voltage (class 0x3000)");
    EXPECT_EQ(error_code_text(0x0042), "unknown error code");
    const auto info = lookup_error_code(0x8612);
    EXPECT_TRUE(info.exact);
    EXPECT_EQ(info.text, "reference limit");
}

TEST(EmcyRegister, NamesEveryBit) {
    EXPECT_EQ(describe_error_register(0xFF), "generic, current, voltage, temperature, "
                                             "communication, device profile, reserved, "
                                             "manufacturer");
    EXPECT_EQ(describe_error_register(0), "none");
}

TEST(EmcyDecode, RejectsNonEmcyFramesAndTooShortPayloads) {
    EXPECT_FALSE(parse_emcy(Frame::make(0x080, {0, 0, 0, 0, 0, 0, 0, 0}))); // SYNC
    EXPECT_FALSE(parse_emcy(Frame::make(0x100, {0, 0, 0, 0, 0, 0, 0, 0})));
    EXPECT_FALSE(parse_emcy(Frame::make(0x081, {0x10, 0x23})));
    EXPECT_FALSE(parse_emcy(Frame::make_rtr(0x081, 8)));
    auto short_frame = parse_emcy(Frame::make(0x081, {0x10, 0x23, 0x03, 0xAA}));
    ASSERT_TRUE(short_frame);
    EXPECT_EQ(short_frame->length, 4);
    EXPECT_EQ(short_frame->manufacturer, (std::array<std::uint8_t, 5>{0xAA, 0, 0, 0, 0}));
}

TEST(EmcyDecode, FrameRoundTrip) {
    EmcyMessage m{5, 0x8611, 0x21, {1, 2, 3, 4, 5}, 8};
    const Frame f = make_emcy_frame(m);
    EXPECT_EQ(f.id, 0x085U);
    EXPECT_EQ(f, Frame::make(0x085, {0x11, 0x86, 0x21, 1, 2, 3, 4, 5}));
    auto back = parse_emcy(f);
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, m);
}

// Shaped like the AKD2G table (specs/akd2g.md §6): one fault number per code.
constexpr EmcyTextEntry kAkdLike[] = {
    {0x3210, "F2006 Bus over voltage"},
    {0x4310, "F2501 Power over temperature sensor"},
};

// Shaped like the Kuhnke FIO 1003h entries (specs/kuhnke-fio.md §7.2): manufacturer byte 0 is
// an error number that refines (or alone explains) the code.
constexpr EmcyTextEntry kFioLike[] = {
    {0x7305, "sensorless encoder error"},
    {0x7305, "auto setup: A/B pulses not detected", 0xFFFF, 0, 0x09},
    {0x0000, "NMT master node-guarding request too late", 0x0000, 0, 0x06},
};

TEST(EmcyTextHook, TableSuppliesVendorTextAfterStandardText) {
    const EmcyTextTable table(kAkdLike);
    EmcyMessage m{2, 0x3210, 0x05, {}, 8};
    EXPECT_EQ(describe(m, &table),
              "node 2: EMCY 0x3210 DC link over-voltage: F2006 Bus over voltage (error register "
              "0x05: generic, voltage) [manufacturer 00 00 00 00 00]");
    m.error_code = 0x2310;
    EXPECT_FALSE(table.vendor_text(m));
}

TEST(EmcyTextHook, ManufacturerByteMatchIsMoreSpecific) {
    const EmcyTextTable table(kFioLike);
    EmcyMessage m{4, 0x7305, 0x01, {0x09, 0x20, 0, 0, 0}, 8};
    EXPECT_EQ(table.vendor_text(m), "auto setup: A/B pulses not detected");
    m.manufacturer[0] = 0x07;
    EXPECT_EQ(table.vendor_text(m), "sensorless encoder error");
    m.error_code = 0x8130;
    m.manufacturer[0] = 0x06;
    EXPECT_EQ(table.vendor_text(m), "NMT master node-guarding request too late");
}

TEST(EmcyTextHook, ChainAndFunctionCompose) {
    const EmcyTextTable akd(kAkdLike);
    const EmcyTextFunction fn([](const EmcyMessage& m) -> std::optional<std::string> {
        if (m.manufacturer[0] == 2) {
            return "axis 2";
        }
        return std::nullopt;
    });
    const EmcyTextChain chain({&akd, &fn});
    EmcyMessage m{2, 0x3210, 0x05, {2, 0, 0, 0, 0}, 8};
    EXPECT_EQ(chain.vendor_text(m), "F2006 Bus over voltage; axis 2");
    m.error_code = 0x1000;
    m.manufacturer[0] = 0;
    EXPECT_FALSE(chain.vendor_text(m));
}

} // namespace
} // namespace codrive::emcy
