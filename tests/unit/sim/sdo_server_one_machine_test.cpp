// SPDX-License-Identifier: Apache-2.0
// One SDO server machine for CAN and CoE: the same malformed or edge requests, frame for frame,
// reach the CAN server (sdo::SdoServer on a recording bus) and the simulated EtherCAT slave's CoE
// server (the same 8 bytes behind a CoE header), and both answer with the same abort frame
// (CiA 301 §7.2.4.3.17, ETG.1000.6 §5.6.2.7). CoE's own differences (normal transfer, long
// segments, complete access, no block transfer) are checked against ETG.1000.6 §5.6.2.
#include <codrive/core/endian.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/ethercat/mailbox.hpp>
#include <codrive/sdo/protocol.hpp>
#include <codrive/sdo/server.hpp>
#include <codrive/sim/ecat/coe_server.hpp>
#include <codrive/testing/recording_bus.hpp>

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace codrive::sim::ecat {
namespace {

using ethercat::AlState;
using ethercat::CoeService;
using ethercat::kCoeHeaderSize;
using sdo::Payload;

constexpr NodeId kNode = 4;
constexpr std::size_t kMailbox = 128; ///< SM1 size of the simulated slaves

using codrive::testing::RecordingBus;

/// The dictionary every case starts from: VARs rw/ro, a long string and a RECORD.
void add_objects(ObjectDictionary& od) {
    od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
               Value(DataType::Unsigned32, {0x92, 0x01, 0x02, 0x00}));
    od.add_var(0x2000, "Writable u32", DataType::Unsigned32, Access::Rw,
               Value(DataType::Unsigned32, {1, 2, 3, 4}));
    std::string text;
    for (int i = 0; i < 300; ++i) {
        text.push_back(static_cast<char>('A' + i % 26));
    }
    od.add_var(0x2001, "Long string", DataType::VisibleString, Access::Rw,
               Value::from_string(text));
    od.add_sub(0x2100,
               SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8, Access::Rw,
                               Value(DataType::Unsigned8, {2})),
               "Record");
    od.add_sub(0x2100, SubObject::make(1, "First", DataType::Unsigned16, Access::Rw,
                                       Value(DataType::Unsigned16, {0x11, 0x22})));
    od.add_sub(0x2100, SubObject::make(2, "Second", DataType::Unsigned32, Access::Rw,
                                       Value(DataType::Unsigned32, {0x33, 0x44, 0x55, 0x66})));
}

/// Every answer to the requests, as SDO bytes (the 8-byte frame, on CoE with data after it).
using Answers = std::vector<std::vector<std::uint8_t>>;

Answers run_can(const std::vector<Payload>& requests) {
    ObjectDictionary od;
    add_objects(od);
    RecordingBus bus;
    sdo::ServerConfig config;
    config.node = kNode;
    sdo::SdoServer server(od, bus, config);
    for (const Payload& p : requests) {
        EXPECT_TRUE(server.on_frame(Frame::make(cob::sdo_rx(kNode), p), TimePoint{}));
    }
    Answers out;
    for (const Frame& f : bus.sent) {
        EXPECT_EQ(f.id, cob::sdo_tx(kNode));
        out.emplace_back(f.payload().begin(), f.payload().end());
    }
    return out;
}

/// The CoE SDO of the simulated slave in PRE-OP. An abort travels as an SDO request, every
/// other answer as an SDO response (ETG.1000.6 §5.6.2.7).
Answers run_coe(const std::vector<std::vector<std::uint8_t>>& requests) {
    ObjectDictionary od;
    add_objects(od);
    CoeServer server(od, kMailbox);
    Answers out;
    for (const auto& sdo_bytes : requests) {
        std::vector<std::uint8_t> coe(kCoeHeaderSize);
        put_le<std::uint16_t>(coe.data(), ethercat::coe_header(CoeService::SdoRequest));
        coe.insert(coe.end(), sdo_bytes.begin(), sdo_bytes.end());
        for (const auto& reply : server.handle(coe, AlState::PreOp)) {
            EXPECT_GE(reply.size(), kCoeHeaderSize + sdo::kFrameLen) << "shorter than 10 bytes";
            const bool abort =
                sdo::parse_frame(std::span(reply).subspan(kCoeHeaderSize, 8), sdo::Sender::Server)
                    .kind == sdo::FrameKind::Abort;
            EXPECT_EQ(ethercat::coe_service(get_le<std::uint16_t>(reply.data())),
                      abort ? CoeService::SdoRequest : CoeService::SdoResponse);
            out.emplace_back(reply.begin() + kCoeHeaderSize, reply.end());
        }
    }
    return out;
}

Answers run_coe(const std::vector<Payload>& requests) {
    std::vector<std::vector<std::uint8_t>> r;
    for (const Payload& p : requests) {
        r.emplace_back(p.begin(), p.end());
    }
    return run_coe(r);
}

/// The abort code the last answer carries (nullopt: the last answer is no abort).
std::optional<std::uint32_t> abort_code(const Answers& answers, std::uint16_t index,
                                        std::uint8_t sub) {
    if (answers.empty()) {
        return std::nullopt;
    }
    const auto info = sdo::parse_frame(std::span(answers.back()).first(8), sdo::Sender::Server);
    if (info.kind != sdo::FrameKind::Abort) {
        return std::nullopt;
    }
    EXPECT_EQ(info.index, index);
    EXPECT_EQ(info.subindex, sub);
    return info.abort_code;
}

/// Both transports answer `requests` with the abort `code` naming index:sub, the same frame.
void expect_same_abort(const std::vector<Payload>& requests, SdoAbort code, std::uint16_t index,
                       std::uint8_t sub) {
    const Answers can = run_can(requests);
    const Answers coe = run_coe(requests);
    EXPECT_EQ(abort_code(can, index, sub), static_cast<std::uint32_t>(code))
        << "CAN: " << sdo_abort_describe(static_cast<std::uint32_t>(code));
    EXPECT_EQ(abort_code(coe, index, sub), static_cast<std::uint32_t>(code))
        << "CoE: " << sdo_abort_describe(static_cast<std::uint32_t>(code));
    ASSERT_FALSE(can.empty());
    ASSERT_FALSE(coe.empty());
    EXPECT_EQ(can.back(), coe.back()) << "the abort frames differ";
    EXPECT_EQ(can.size(), coe.size()) << "a different number of answers";
}

std::vector<std::uint8_t> u32(std::uint32_t v) {
    return {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8),
            static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 24)};
}

TEST(SdoServerOneMachine, WrongToggleAbortsTheSameOnCanAndCoe) {
    const auto data = u32(7);
    expect_same_abort({sdo::make_initiate_download_segmented(0x2000, 0, 4),
                       sdo::make_download_segment(true, true, data)},
                      SdoAbort::ToggleBit, 0x2000, 0);
}

TEST(SdoServerOneMachine, UnknownCommandSpecifierAbortsTheSameOnCanAndCoe) {
    Payload p = sdo::make_initiate_upload(0x2000, 0);
    p[0] = 0xE0; // ccs 7: reserved in CiA 301 and ETG.1000.6
    expect_same_abort({p}, SdoAbort::UnknownCommand, 0, 0);
}

TEST(SdoServerOneMachine, ExpeditedSizeBelowTheTypeAbortsTheSameOnCanAndCoe) {
    const std::vector<std::uint8_t> two{1, 2};
    expect_same_abort({sdo::make_initiate_download_expedited(0x2000, 0, two)},
                      SdoAbort::LengthTooLow, 0x2000, 0);
}

TEST(SdoServerOneMachine, SegmentsShortOfTheIndicatedSizeAbortTheSameOnCanAndCoe) {
    // 0x2001 is a string: the indicated 10 bytes pass the type check, 3 arrive.
    const std::vector<std::uint8_t> three{'a', 'b', 'c'};
    expect_same_abort({sdo::make_initiate_download_segmented(0x2001, 0, 10),
                       sdo::make_download_segment(false, true, three)},
                      SdoAbort::LengthMismatch, 0x2001, 0);
}

TEST(SdoServerOneMachine, MissingSubIndexAbortsTheSameOnCanAndCoe) {
    expect_same_abort({sdo::make_initiate_upload(0x2100, 5)}, SdoAbort::NoSubindex, 0x2100, 5);
}

TEST(SdoServerOneMachine, MissingObjectAbortsTheSameOnCanAndCoe) {
    expect_same_abort({sdo::make_initiate_upload(0x2FFF, 0)}, SdoAbort::NoObject, 0x2FFF, 0);
}

TEST(SdoServerOneMachine, WriteToReadOnlyAbortsTheSameOnCanAndCoe) {
    const auto data = u32(1);
    expect_same_abort({sdo::make_initiate_download_expedited(0x1000, 0, data)}, SdoAbort::ReadOnly,
                      0x1000, 0);
}

TEST(SdoServerOneMachine, SegmentAfterTheLastAbortsTheSameOnCanAndCoe) {
    const auto data = u32(9);
    expect_same_abort({sdo::make_initiate_download_segmented(0x2000, 0, 4),
                       sdo::make_download_segment(false, true, data),
                       sdo::make_download_segment(true, true, data)},
                      SdoAbort::UnknownCommand, 0x2000, 0);
}

TEST(SdoServerOneMachine, UploadSegmentWithoutATransferAbortsTheSameOnCanAndCoe) {
    expect_same_abort({sdo::make_upload_segment_request(false)}, SdoAbort::UnknownCommand, 0, 0);
}

TEST(SdoServerOneMachine, ShortRequestIsReadPaddedTheSameOnCanAndCoe) {
    // A request of fewer than 8 bytes is read with its reserved tail as zeros (sdo::parse_frame),
    // on both transports: 40 00 20 is the initiate upload of 2000h:00.
    const Payload full = sdo::make_initiate_upload(0x2000, 0);
    const std::vector<std::uint8_t> three(full.begin(), full.begin() + 3);
    RecordingBus bus;
    ObjectDictionary od;
    add_objects(od);
    sdo::SdoServer can(od, bus, sdo::ServerConfig{.node = kNode});
    can.on_frame(Frame::make(cob::sdo_rx(kNode), three), TimePoint{});
    const Answers coe = run_coe(std::vector<std::vector<std::uint8_t>>{three});
    ASSERT_EQ(bus.sent.size(), 1U);
    ASSERT_EQ(coe.size(), 1U);
    const std::vector<std::uint8_t> can_answer(bus.sent[0].payload().begin(),
                                               bus.sent[0].payload().end());
    EXPECT_EQ(can_answer, coe[0]);
    const auto info = sdo::parse_frame(coe[0], sdo::Sender::Server);
    EXPECT_EQ(info.kind, sdo::FrameKind::InitiateUploadResponse);
    EXPECT_EQ(info.index, 0x2000);
    EXPECT_EQ(info.data[3], 4);
}

TEST(SdoServerOneMachine, CompleteAccessOnAVarIsRefusedOnCoeAndReservedOnCan) {
    Payload p = sdo::make_initiate_upload(0x2000, 0);
    p[0] = static_cast<std::uint8_t>(p[0] | sdo::kCompleteAccessBit);
    // CoE: complete access is for ARRAY and RECORD objects (ETG.1000.6 §5.6.2.1.1).
    EXPECT_EQ(abort_code(run_coe({p}), 0x2000, 0),
              static_cast<std::uint32_t>(SdoAbort::UnsupportedAccess));
    // CAN: bit 4 of an initiate upload request is reserved ("x", CiA 301 §7.2.4.3.6): an
    // ordinary expedited upload.
    const Answers can = run_can({p});
    ASSERT_EQ(can.size(), 1U);
    const auto info = sdo::parse_frame(can[0], sdo::Sender::Server);
    EXPECT_EQ(info.kind, sdo::FrameKind::InitiateUploadResponse);
    EXPECT_TRUE(info.expedited);
    EXPECT_EQ(info.data[0], 1);
}

TEST(SdoServerOneMachine, CompleteAccessBeyondSubIndexOneIsRefusedOnCoe) {
    Payload p = sdo::make_initiate_upload(0x2100, 2);
    p[0] = static_cast<std::uint8_t>(p[0] | sdo::kCompleteAccessBit);
    EXPECT_EQ(abort_code(run_coe({p}), 0x2100, 2),
              static_cast<std::uint32_t>(SdoAbort::UnsupportedAccess));
}

TEST(SdoServerOneMachine, BlockTransferIsAnUnknownCommandOnCoe) {
    // CoE has no block transfer (ETG.1000.6 §5.6.2); the same request starts one on CAN.
    const std::vector<Payload> req{sdo::make_block_upload_initiate(0x2001, 0, true, 16, 0)};
    EXPECT_EQ(abort_code(run_coe(req), 0x2001, 0),
              static_cast<std::uint32_t>(SdoAbort::UnknownCommand));
    const Answers can = run_can(req);
    ASSERT_EQ(can.size(), 1U);
    EXPECT_EQ(sdo::parse_frame(can[0], sdo::Sender::Server).kind,
              sdo::FrameKind::BlockUploadInitiateResponse);
}

/// The bytes of an upload of index:sub driven to its end on one transport (no abort expected).
std::vector<std::uint8_t> upload_all(bool coe, std::uint16_t index, std::uint8_t sub,
                                     bool complete_access, std::size_t& answers) {
    std::vector<std::vector<std::uint8_t>> requests;
    Payload first = sdo::make_initiate_upload(index, sub);
    if (complete_access) {
        first[0] = static_cast<std::uint8_t>(first[0] | sdo::kCompleteAccessBit);
    }
    std::vector<std::uint8_t> data;
    ObjectDictionary od;
    add_objects(od);
    RecordingBus bus;
    sdo::SdoServer can(od, bus, sdo::ServerConfig{.node = kNode});
    CoeServer slave(od, kMailbox);
    const auto ask = [&](const Payload& p) {
        if (!coe) {
            bus.sent.clear();
            can.on_frame(Frame::make(cob::sdo_rx(kNode), p), TimePoint{});
            EXPECT_EQ(bus.sent.size(), 1U);
            return std::vector<std::uint8_t>(bus.sent.at(0).payload().begin(),
                                             bus.sent.at(0).payload().end());
        }
        std::vector<std::uint8_t> m(kCoeHeaderSize);
        put_le<std::uint16_t>(m.data(), ethercat::coe_header(CoeService::SdoRequest));
        m.insert(m.end(), p.begin(), p.end());
        auto r = slave.handle(m, AlState::PreOp);
        EXPECT_EQ(r.size(), 1U);
        EXPECT_LE(r.at(0).size() + 6, kMailbox) << "an answer larger than the mailbox";
        return std::vector<std::uint8_t>(r.at(0).begin() + kCoeHeaderSize, r.at(0).end());
    };
    answers = 1;
    auto reply = ask(first);
    auto info = sdo::parse_frame(std::span(reply).first(8), sdo::Sender::Server);
    EXPECT_EQ(info.kind, sdo::FrameKind::InitiateUploadResponse);
    if (info.expedited) {
        return {info.data.begin(), info.data.begin() + info.data_len};
    }
    const std::size_t size = info.size;
    data.insert(data.end(), reply.begin() + 8, reply.end()); // CoE normal transfer
    bool toggle = false;
    while (data.size() < size && answers < 100) {
        reply = ask(sdo::make_upload_segment_request(toggle));
        ++answers;
        info = sdo::parse_frame(std::span(reply).first(8), sdo::Sender::Server);
        EXPECT_EQ(info.kind, sdo::FrameKind::UploadSegmentResponse);
        EXPECT_EQ(info.toggle, toggle);
        data.insert(data.end(), info.data.begin(), info.data.begin() + info.data_len);
        data.insert(data.end(), reply.begin() + 8, reply.end()); // CoE long segment
        if (info.last) {
            break;
        }
        toggle = !toggle;
    }
    EXPECT_EQ(data.size(), size);
    return data;
}

TEST(SdoServerOneMachine, LongValueComesInNormalTransferAndMailboxSizedSegmentsOnCoe) {
    std::size_t can_answers = 0;
    std::size_t coe_answers = 0;
    const auto over_can = upload_all(false, 0x2001, 0, false, can_answers);
    const auto over_coe = upload_all(true, 0x2001, 0, false, coe_answers);
    ASSERT_EQ(over_can.size(), 300U);
    EXPECT_EQ(over_coe, over_can);
    // CAN: 1 + ceil(300 / 7) answers; CoE: the normal response carries 128 - 6 - 10 = 112 bytes,
    // each segment 128 - 6 - 3 = 119 (ETG.1000.6 §5.6.2.5-6): 112 + 119 + 69.
    EXPECT_EQ(can_answers, 1U + 43U);
    EXPECT_EQ(coe_answers, 3U);
}

TEST(SdoServerOneMachine, CompleteAccessPadsSubIndexZeroAndWritesTheRecordBack) {
    std::size_t answers = 0;
    const auto whole = upload_all(true, 0x2100, 0, true, answers);
    // ETG.1000.6 §5.6.2.1.1 / ETG.1020 §12.2: sub 0 padded to 16 bits, then subs 1..n packed.
    EXPECT_EQ(whole, (std::vector<std::uint8_t>{2, 0, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66}));
    const auto from_one = upload_all(true, 0x2100, 1, true, answers);
    EXPECT_EQ(from_one, (std::vector<std::uint8_t>{0x11, 0x22, 0x33, 0x44, 0x55, 0x66}));

    // Download in normal transfer: the data after the size in the initiate request.
    ObjectDictionary od;
    add_objects(od);
    CoeServer slave(od, kMailbox);
    std::vector<std::uint8_t> m(kCoeHeaderSize);
    put_le<std::uint16_t>(m.data(), ethercat::coe_header(CoeService::SdoRequest));
    Payload p = sdo::make_initiate_download_segmented(0x2100, 0, 8);
    p[0] = static_cast<std::uint8_t>(p[0] | sdo::kCompleteAccessBit);
    m.insert(m.end(), p.begin(), p.end());
    const std::vector<std::uint8_t> record{2, 0, 0xAA, 0xBB, 1, 2, 3, 4};
    m.insert(m.end(), record.begin(), record.end());
    const auto r = slave.handle(m, AlState::PreOp);
    ASSERT_EQ(r.size(), 1U);
    EXPECT_EQ(
        sdo::parse_frame(std::span(r[0]).subspan(kCoeHeaderSize, 8), sdo::Sender::Server).kind,
        sdo::FrameKind::InitiateDownloadResponse);
    EXPECT_EQ(od.get<std::uint16_t>(0x2100, 1), 0xBBAA);
    EXPECT_EQ(od.get<std::uint32_t>(0x2100, 2), 0x04030201U);
}

TEST(SdoServerOneMachine, EmptyNormalTransferDownloadIsCompleteOnCoe) {
    // ETG.1000.6 §5.6.2.2: the initiate request holds all of an announced 0 bytes; the master's
    // client machine takes the initiate response as the end, so the slave must have written.
    ObjectDictionary od;
    add_objects(od);
    CoeServer slave(od, kMailbox);
    std::vector<std::uint8_t> m(kCoeHeaderSize);
    put_le<std::uint16_t>(m.data(), ethercat::coe_header(CoeService::SdoRequest));
    const Payload p = sdo::make_initiate_download_segmented(0x2001, 0, 0);
    m.insert(m.end(), p.begin(), p.end());
    const auto r = slave.handle(m, AlState::PreOp);
    ASSERT_EQ(r.size(), 1U);
    EXPECT_EQ(
        sdo::parse_frame(std::span(r[0]).subspan(kCoeHeaderSize, 8), sdo::Sender::Server).kind,
        sdo::FrameKind::InitiateDownloadResponse);
    EXPECT_TRUE(od.read(0x2001, 0)->empty());
    EXPECT_FALSE(slave.sdo_server().busy());
}

TEST(SdoServerOneMachine, PdoMappingWritesOutsidePreOpAreRefusedAtTheInitiateRequest) {
    ObjectDictionary od;
    od.add_sub(0x1C12,
               SubObject::make(0, "Number of entries", DataType::Unsigned8, Access::Rw,
                               Value(DataType::Unsigned8, {0})),
               "RxPDO assign");
    CoeServer slave(od, kMailbox);
    std::vector<std::uint8_t> m(kCoeHeaderSize);
    put_le<std::uint16_t>(m.data(), ethercat::coe_header(CoeService::SdoRequest));
    const std::vector<std::uint8_t> one{1};
    const Payload p = sdo::make_initiate_download_expedited(0x1C12, 0, one);
    m.insert(m.end(), p.begin(), p.end());
    // ETG.1000.6 §5.6.7.4: PDO assignment changes in PRE-OP only.
    const auto r = slave.handle(m, AlState::SafeOp);
    ASSERT_EQ(r.size(), 1U);
    const Answers answers{{r[0].begin() + kCoeHeaderSize, r[0].end()}};
    EXPECT_EQ(abort_code(answers, 0x1C12, 0),
              static_cast<std::uint32_t>(SdoAbort::DataTransferState));
    EXPECT_EQ(slave.handle(m, AlState::PreOp).size(), 1U);
    EXPECT_EQ(od.get<std::uint8_t>(0x1C12, 0), 1);
}

} // namespace
} // namespace codrive::sim::ecat
