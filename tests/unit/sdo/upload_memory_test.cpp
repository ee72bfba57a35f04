// SPDX-License-Identifier: Apache-2.0
// An upload's memory follows the bytes that arrive, not the size a server announces: a garbage
// or hostile size indication (up to 4 GiB in CiA 301's 32-bit field) must not make the master
// reserve it.
#include "sdo_harness.hpp"

// The one file of unit_sdo that replaces the global operator new (counting_new.hpp).
#include <codrive/testing/counting_new.hpp>

#include <gtest/gtest.h>

namespace codrive::sdo::testing {
namespace {

TEST(SdoUploadMemory, AServerAnnouncingFourGibibytesCostsTheMasterAtMostTheReserveCap) {
    Harness h;
    // The server's initiate upload response (scs 2, size indicated) for the 12-byte device
    // name claims 0xFFFFFFFF bytes; its segments then bring the real 12.
    h.server_bus.mutate = [](Frame& f) {
        if ((f.data[0] >> 5) == 2 && (f.data[0] & 0x01U) != 0 && (f.data[0] & 0x02U) == 0) {
            f.data[4] = f.data[5] = f.data[6] = f.data[7] = 0xFF;
        }
        return true;
    };
    std::optional<SdoResult<Bytes>> r;
    std::uint64_t bytes = 0;
    {
        codrive::testing::AllocationScope scope;
        TransferOptions o;
        o.mode = Mode::Segmented;
        r = h.upload(0x1008, 0, o);
        bytes = scope.bytes();
    }
    ASSERT_TRUE(r && !*r);
    EXPECT_EQ(r->error().abort_code(), 0x06070013U) << message(r);
    EXPECT_EQ(message(r), "node 4: SDO segmented upload 0x1008:00 aborted by client: 0x06070013 "
                          "data type does not match, length of service parameter too low (server "
                          "sent 12 bytes, announced 4294967295)");
    // The 64 KiB reserve cap plus bookkeeping; with the 16 MiB cap before it, 16 MiB.
    EXPECT_LE(bytes, std::uint64_t{256} * 1024U);
    EXPECT_GE(bytes, std::uint64_t{12}); // the counter saw the upload at all
}

TEST(SdoUploadMemory, AnUploadLargerThanTheReserveStillArrivesWhole) {
    Harness h;
    const Bytes big = pattern(3 * kMaxUploadReserve + 5);
    TransferOptions o;
    o.mode = Mode::Block;
    auto w = h.download(0x2100, 0, big, o);
    ASSERT_TRUE(w && *w) << message(w);
    auto r = h.upload(0x2100, 0, o);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(**r, big);
}

} // namespace
} // namespace codrive::sdo::testing
