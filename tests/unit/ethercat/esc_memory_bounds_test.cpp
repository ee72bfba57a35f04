// SPDX-License-Identifier: Apache-2.0
// The simulated ESC against sync managers and FMMUs whose area runs past its 64 KiB of memory:
// their start and length are 16 bits each, so a master may configure such an SM (fuzz_slave_replies
// did, from a corrupted SII: regressions/slave_replies/sm3_area_past_esc_memory) or an FMMU whose
// physical window crosses 0xFFFF. The simulator moves data only inside its memory, and goes on
// answering.
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/registers.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

#include <array>
#include <optional>
#include <vector>

namespace codrive::ethercat {
namespace {

using sim::ecat::make_drive_slave;

class EscMemoryBounds : public codrive::testing::SimSegmentTest {
protected:
    EscMemoryBounds() { segment_.add(make_drive_slave("akd2g", 1)); }

    /// SM `n` enabled at `start` for `length` bytes, its control byte kept.
    void place_sm(unsigned n, std::uint16_t start, std::uint16_t length) {
        auto control = master_.read_registers(0, reg::sm(n) + 4, 1);
        ASSERT_TRUE(control) << master_.last_error();
        const std::array<std::uint8_t, 8> sm = {static_cast<std::uint8_t>(start),
                                                static_cast<std::uint8_t>(start >> 8),
                                                static_cast<std::uint8_t>(length),
                                                static_cast<std::uint8_t>(length >> 8),
                                                (*control)[0],
                                                0,
                                                SyncManager::kActivateEnable,
                                                0};
        ASSERT_TRUE(master_.write_registers(0, reg::sm(n), sm)) << master_.last_error();
    }
};

TEST_F(EscMemoryBounds, InputsOfAnSmPastTheEndOfMemoryStopAtTheEnd) {
    bring_up(AlState::SafeOp);
    place_sm(3, 0xFFF8, 0x0100);
    // Every frame the slave processes packs its inputs: under ASan a write past the memory
    // ended the process here.
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(master_.read_registers(0, reg::kAlStatus, 2)) << master_.last_error();
    }
}

// The master's output FMMU moved so that its physical window starts 8 bytes before the end of
// the memory: an LRW writes the first 8 output bytes there and the rest nowhere. Before the
// bound, the simulator wrote the whole window, past the end of its memory (a heap overflow
// under ASan).
TEST_F(EscMemoryBounds, OutputsWrittenThroughAnFmmuPastTheEndOfMemoryLandOnlyInside) {
    bring_up(AlState::Op);
    auto out = master_.outputs(0);
    ASSERT_GT(out.size(), 8U) << "the test needs more than 8 output bytes";
    std::optional<unsigned> writer;
    for (unsigned f = 0; f < 8 && !writer; ++f) {
        auto raw = master_.read_registers(0, reg::fmmu(f), 16);
        ASSERT_TRUE(raw) << master_.last_error();
        const Fmmu fm = Fmmu::decode(*raw);
        if ((fm.activate & 1) != 0 && (fm.type & Fmmu::kWrite) != 0) {
            writer = f;
        }
    }
    ASSERT_TRUE(writer) << "the master programmed no output FMMU";
    const std::array<std::uint8_t, 2> end = {0xF8, 0xFF};
    ASSERT_TRUE(master_.write_registers(0, reg::fmmu(*writer) + 8, end)) << master_.last_error();

    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = static_cast<std::uint8_t>(0xA0 + i);
    }
    // The write lands (2 for the outputs, 1 for the inputs), and the slave answers after it.
    EXPECT_EQ(master_.exchange_process_data().value_or(0), master_.expected_wkc())
        << master_.last_error();
    auto tail = master_.read_registers(0, 0xFFF8, 8);
    ASSERT_TRUE(tail) << master_.last_error();
    const std::vector<std::uint8_t> want(out.begin(), out.begin() + 8);
    EXPECT_EQ(*tail, want);
    EXPECT_EQ(segment_.slave(0).state(), AlState::Op);
}

// The mirror of the test above: the input FMMU's physical window starts 8 bytes before the end
// of the memory. The LRW reads those 8 bytes into the first input bytes and counts, as a write
// through such a window does; the rest of the inputs are left as the frame carried them.
TEST_F(EscMemoryBounds, InputsReadThroughAnFmmuPastTheEndOfMemoryComeOnlyFromInside) {
    bring_up(AlState::Op);
    ASSERT_GT(master_.inputs(0).size(), 8U) << "the test needs more than 8 input bytes";
    std::optional<unsigned> reader;
    for (unsigned f = 0; f < 8 && !reader; ++f) {
        auto raw = master_.read_registers(0, reg::fmmu(f), 16);
        ASSERT_TRUE(raw) << master_.last_error();
        const Fmmu fm = Fmmu::decode(*raw);
        if ((fm.activate & 1) != 0 && (fm.type & Fmmu::kRead) != 0 &&
            fm.physical_start >= 0x1000) { // process data RAM, not an SM status byte
            reader = f;
        }
    }
    ASSERT_TRUE(reader) << "the master programmed no input FMMU";
    const std::array<std::uint8_t, 2> end = {0xF8, 0xFF};
    ASSERT_TRUE(master_.write_registers(0, reg::fmmu(*reader) + 8, end)) << master_.last_error();
    const std::array<std::uint8_t, 8> tail = {0xB0, 0xB1, 0xB2, 0xB3, 0xB4, 0xB5, 0xB6, 0xB7};
    ASSERT_TRUE(master_.write_registers(0, 0xFFF8, tail)) << master_.last_error();

    EXPECT_EQ(master_.exchange_process_data().value_or(0), master_.expected_wkc())
        << master_.last_error();
    const auto in = master_.inputs(0);
    EXPECT_EQ(std::vector<std::uint8_t>(in.begin(), in.begin() + 8),
              std::vector<std::uint8_t>(tail.begin(), tail.end()));
    EXPECT_EQ(segment_.slave(0).state(), AlState::Op);
}

// SM1 moved in PRE-OP so that it ends past the memory: the answer to the next request is put
// only in the part inside it. The master, which reads SM1 where it configured it, reads what was
// left there and fails the transfer with a sentence naming it; the slave goes on answering.
TEST_F(EscMemoryBounds, AMailboxAnswerForAnSmPastTheEndOfMemoryIsPutOnlyInside) {
    bring_up(AlState::PreOp);
    place_sm(1, 0xFFF0, master_.slaves()[0].sii.tx_mailbox_size);
    auto r = master_.sdo_upload(0, 0x1000, 0);
    ASSERT_FALSE(r);
    EXPECT_EQ(master_.last_error().rfind("slave 0 (AKD2G): SDO upload 0x1000:00", 0), 0U)
        << master_.last_error();
    EXPECT_TRUE(master_.read_registers(0, reg::kAlStatus, 2)) << master_.last_error();
    EXPECT_EQ(segment_.slave(0).state(), AlState::PreOp);
}

// An FMMU whose logical window ends past 4 GiB (0xFFFFF900 + 2 KiB): a 4-byte read at its start
// moves 4 bytes. Before the overlap was computed in 64 bits it wrapped, and the ESC read 2 KiB
// into the 4-byte datagram, past the end of the frame.
TEST_F(EscMemoryBounds, AnFmmuWindowPastTheTopOfTheLogicalSpaceMovesOnlyTheDatagramsBytes) {
    bring_up(AlState::SafeOp);
    Fmmu fm;
    fm.logical_start = 0xFFFFF900;
    fm.length = 0x0800;
    fm.physical_start = 0x0000; // type, revision, build: always readable
    fm.type = Fmmu::kRead;
    fm.activate = 1;
    ASSERT_TRUE(master_.write_registers(0, reg::fmmu(7), fm.encode())) << master_.last_error();
    const std::array<Datagram, 1> lrd = {Datagram::logical(Command::Lrd, 0xFFFFF900, 4)};
    auto frame = encode_frame(lrd);
    ASSERT_TRUE(frame);
    ASSERT_TRUE(segment_.process(*frame, clock_.now()));
    auto back = decode_frame(*frame);
    ASSERT_TRUE(back);
    ASSERT_EQ(back->size(), 1U);
    EXPECT_EQ((*back)[0].wkc, 1);
    auto direct = master_.read_registers(0, 0x0000, 4);
    ASSERT_TRUE(direct) << master_.last_error();
    EXPECT_EQ((*back)[0].data, *direct);
}

} // namespace
} // namespace codrive::ethercat
