// SPDX-License-Identifier: Apache-2.0
// One SDO client machine for CAN and CoE: the same misbehaving server answers, frame for frame,
// reach the CAN client (sdo::SdoClient on a scripted bus) and the EtherCAT master's CoE SDO (a
// scripted slave, the same 8 bytes behind a CoE header), and both end the transfer with the
// same error code and tell the server with the same abort frame (CiA 301 §7.2.4.3.17,
// ETG.1000.6 §5.6.2.7).
#include "scripted_slave.hpp"

#include <codrive/core/endian.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sdo/protocol.hpp>
#include <codrive/testing/recording_bus.hpp>

#include <gtest/gtest.h>

#include <optional>
#include <string>

namespace codrive::ethercat {
namespace {

using sdo::Payload;
using testing::ScriptedSlave;

constexpr NodeId kNode = 4;
constexpr std::uint16_t kIndex = 0x2100;
constexpr std::uint8_t kSub = 1;

using codrive::testing::RecordingBus;

/// How one transfer ended on one transport.
struct Ending {
    std::error_code cause;             ///< empty: it succeeded
    std::vector<std::uint8_t> data;    ///< uploaded data on success
    std::optional<Payload> abort_sent; ///< the client's abort frame, if it sent one
    std::string sentence;
    std::uint64_t strays = 0; ///< CoE: SM1 messages the master dropped as no transfer's answer
    Duration took{};          ///< CoE: fake time the transfer took
};

std::optional<Payload> abort_in(std::span<const std::uint8_t> frame) {
    if (frame.size() < sdo::kFrameLen ||
        sdo::parse_frame(frame.first(sdo::kFrameLen), sdo::Sender::Client).kind !=
            sdo::FrameKind::Abort) {
        return std::nullopt;
    }
    Payload p{};
    std::copy_n(frame.begin(), sdo::kFrameLen, p.begin());
    return p;
}

/// The CAN client: each scripted frame answers the request before it; when the script runs out
/// the client's timeouts run (as a silent server's would).
Ending run_can(bool upload, const std::vector<std::uint8_t>& data,
               const std::vector<Payload>& script) {
    FakeClock clock;
    RecordingBus bus{"scripted"};
    sdo::ClientConfig config;
    config.node = kNode;
    sdo::SdoClient client(bus, clock, config);
    std::optional<Ending> end;
    if (upload) {
        client.upload(kIndex, kSub, [&](sdo::SdoResult<sdo::Bytes> r) {
            end =
                r ? Ending{{}, *r, {}, {}} : Ending{r.error().cause, {}, {}, r.error().to_string()};
        });
    } else {
        client.download(kIndex, kSub, data, [&](sdo::SdoResult<void> r) {
            end = r ? Ending{} : Ending{r.error().cause, {}, {}, r.error().to_string()};
        });
    }
    for (const Payload& p : script) {
        clock.advance(milliseconds(1));
        client.on_frame(Frame::make(cob::sdo_tx(kNode), p), clock.now());
    }
    for (int i = 0; i < 20 && !end; ++i) {
        clock.advance(milliseconds(500));
        client.on_tick(clock.now());
    }
    EXPECT_TRUE(end) << "the CAN transfer never ended";
    if (!end) {
        return {};
    }
    if (!bus.sent.empty()) {
        end->abort_sent = abort_in(bus.sent.back().payload());
    }
    return *end;
}

/// The CoE SDO of the master: the same frames, each behind a CoE header (an abort travels as an
/// SDO request, ETG.1000.6 §5.6.2.7). The first `late` frames are answers of an earlier transfer
/// that timed out: they wait in SM1, with the one after them, for the first request.
Ending run_coe(bool upload, const std::vector<std::uint8_t>& data,
               const std::vector<Payload>& script, std::size_t late = 0) {
    FakeClock clock;
    ScriptedSlave link(clock, MailboxType::Coe);
    Master master(link, clock);
    master.slaves().push_back(testing::scripted_slave_info(mbx_proto::kCoe));
    for (std::size_t i = 0; i < script.size(); ++i) {
        const Payload& p = script[i];
        const bool abort = sdo::parse_frame(p, sdo::Sender::Server).kind == sdo::FrameKind::Abort;
        std::vector<std::uint8_t> coe(kCoeHeaderSize);
        put_le<std::uint16_t>(coe.data(),
                              coe_header(abort ? CoeService::SdoRequest : CoeService::SdoResponse));
        coe.insert(coe.end(), p.begin(), p.end());
        link.answer_raw(std::move(coe), i < late);
    }
    const TimePoint start = clock.now();
    Ending end;
    if (upload) {
        auto r = master.sdo_upload(0, kIndex, kSub);
        if (r) {
            end.data = *r;
        } else {
            end.cause = r.error();
        }
    } else if (auto r = master.sdo_download(0, kIndex, kSub, data); !r) {
        end.cause = r.error();
    }
    end.sentence = master.last_error();
    end.strays = master.stats().stray_mailbox_messages;
    end.took = clock.now() - start;
    const auto& sent = link.requests();
    if (!sent.empty() && sent.back().size() >= kCoeHeaderSize + sdo::kFrameLen) {
        end.abort_sent =
            abort_in(std::span<const std::uint8_t>(sent.back()).subspan(kCoeHeaderSize));
    }
    return end;
}

std::error_code abort_error(SdoAbort code) {
    return {static_cast<int>(code), sdo_abort_category()};
}

/// How one script ended on each transport.
struct Endings {
    Ending can;
    Ending coe;
};

/// Runs the script on both transports and checks they end alike with `cause` (and, on success,
/// with the same data); returns both endings for further checks.
Endings expect_same(bool upload, const std::vector<std::uint8_t>& data,
                    const std::vector<Payload>& script, std::error_code cause,
                    std::optional<SdoAbort> client_abort, std::size_t late = 0) {
    const Ending can = run_can(upload, data, script);
    const Ending coe = run_coe(upload, data, script, late);
    EXPECT_EQ(can.cause, cause) << can.sentence;
    EXPECT_EQ(coe.cause, cause) << coe.sentence;
    if (!cause) {
        EXPECT_EQ(can.data, coe.data);
    }
    if (client_abort) {
        const Payload want =
            sdo::make_abort(kIndex, kSub, static_cast<std::uint32_t>(*client_abort));
        EXPECT_EQ(can.abort_sent, want) << "CAN: " << can.sentence;
        EXPECT_EQ(coe.abort_sent, want) << "CoE: " << coe.sentence;
    } else {
        EXPECT_FALSE(can.abort_sent) << can.sentence;
        EXPECT_FALSE(coe.abort_sent) << coe.sentence;
    }
    return {can, coe};
}

Payload segment(bool toggle, bool last, std::vector<std::uint8_t> data) {
    return sdo::make_upload_segment(toggle, last, data);
}

TEST(SdoOneMachine, AGoodSegmentedUploadGivesTheSameBytesOnBothTransports) {
    const std::vector<Payload> script = {
        sdo::make_initiate_upload_segmented(kIndex, kSub, 10),
        segment(false, false, {1, 2, 3, 4, 5, 6, 7}),
        segment(true, true, {8, 9, 10}),
    };
    const Ending can = run_can(true, {}, script);
    const Ending coe = run_coe(true, {}, script);
    EXPECT_FALSE(can.cause) << can.sentence;
    EXPECT_FALSE(coe.cause) << coe.sentence;
    const std::vector<std::uint8_t> want = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    EXPECT_EQ(can.data, want);
    EXPECT_EQ(coe.data, want);
}

TEST(SdoOneMachine, AnAnswerForAnotherSubIndexFailsAsWrongObjectOnBoth) {
    const std::array<std::uint8_t, 2> value = {1, 2};
    const Ending coe =
        expect_same(true, {}, {sdo::make_initiate_upload_expedited(kIndex, kSub + 1, value)},
                    make_error_code(sdo::SdoErrc::WrongObject), SdoAbort::General)
            .coe;
    EXPECT_EQ(coe.sentence,
              "slave 0 (DRIVE): SDO upload 0x2100:01 failed: response for a different "
              "object: server answered for 0x2100:02 instead of 0x2100:01");
}

// A transfer that timed out leaves its late answer in the slave's SM1, ahead of the next
// transfer's answer (on CAN it crosses the next request on the bus). It names another object, so
// it is dropped and the transfer takes the answer behind it.
TEST(SdoOneMachine, ALateAnswerForAnotherObjectIsDroppedAndTheAnswerBehindItTakenOnBoth) {
    const std::array<std::uint8_t, 2> stale = {9, 9};
    const std::array<std::uint8_t, 2> value = {1, 2};
    const Endings both = expect_same(true, {},
                                     {sdo::make_initiate_upload_expedited(0x1010, 1, stale),
                                      sdo::make_initiate_upload_expedited(kIndex, kSub, value)},
                                     {}, std::nullopt, 1);
    EXPECT_EQ(both.can.data, (std::vector<std::uint8_t>{1, 2}));
    EXPECT_EQ(both.coe.data, (std::vector<std::uint8_t>{1, 2}));
    EXPECT_EQ(both.coe.strays, 1U);
}

// The restore of a PDO assignment: an upload of 1C12h timed out and its answer came late; the
// download of 1C12h that follows must not take it for its own (an upload response, same object).
TEST(SdoOneMachine, ALateUploadAnswerOfTheSameObjectDoesNotEndTheDownloadAfterItOnBoth) {
    const std::array<std::uint8_t, 1> count = {2};
    const Ending coe = expect_same(false, {0},
                                   {sdo::make_initiate_upload_expedited(kIndex, kSub, count),
                                    sdo::make_initiate_download_response(kIndex, kSub)},
                                   {}, std::nullopt, 1)
                           .coe;
    EXPECT_EQ(coe.sentence, "");
    EXPECT_EQ(coe.strays, 1U);
}

// When nothing but such an answer comes, the timeout says so instead of "mailbox silent".
TEST(SdoOneMachine, ACoeTimeoutAfterADroppedAnswerSaysTheSlaveWasNotSilent) {
    const std::array<std::uint8_t, 1> count = {2};
    const Ending coe =
        run_coe(false, {0}, {sdo::make_initiate_upload_expedited(kIndex, kSub, count)});
    EXPECT_EQ(coe.cause, make_error_code(EcatErrc::MailboxTimeout));
    EXPECT_EQ(coe.sentence,
              "slave 0 (DRIVE): CoE SDO download 0x2100:01 timed out after 1000 ms (no "
              "answer to it; 1 other message read and dropped)");
}

/// A master on a scripted slave whose SM1 holds `answers` (CoE payloads, header first), all
/// there after the first request; the sentence of `run`, and what the master counted.
template <class Run>
std::pair<std::string, std::uint64_t> coe_with(std::vector<std::vector<std::uint8_t>> answers,
                                               Run run) {
    FakeClock clock;
    ScriptedSlave link(clock, MailboxType::Coe);
    Master master(link, clock);
    master.slaves().push_back(testing::scripted_slave_info(mbx_proto::kCoe));
    for (std::size_t i = 0; i < answers.size(); ++i) {
        link.answer_raw(std::move(answers[i]), i + 1 < answers.size());
    }
    run(master);
    return {master.last_error(), master.stats().stray_mailbox_messages};
}

std::vector<std::uint8_t> coe_message(CoeService service, const Payload& frame) {
    std::vector<std::uint8_t> coe(kCoeHeaderSize);
    put_le<std::uint16_t>(coe.data(), coe_header(service));
    coe.insert(coe.end(), frame.begin(), frame.end());
    return coe;
}

// A CoE SDO message too short to hold the SDO frame is malformed, not a late answer: it ends
// the transfer at once, with the abort a frame of no known kind gets.
TEST(SdoOneMachine, ACoeSdoMessageShorterThanTheFrameEndsTheTransferAtOnce) {
    std::vector<std::uint8_t> short_answer(kCoeHeaderSize);
    put_le<std::uint16_t>(short_answer.data(), coe_header(CoeService::SdoResponse));
    short_answer.insert(short_answer.end(), {0x43, 0x00, 0x21});
    std::error_code cause;
    const auto [sentence, strays] = coe_with({short_answer}, [&](Master& m) {
        auto r = m.sdo_upload(0, kIndex, kSub);
        cause = r ? std::error_code() : r.error();
    });
    EXPECT_EQ(cause, abort_error(SdoAbort::UnknownCommand)) << sentence;
    EXPECT_EQ(sentence, "slave 0 (DRIVE): SDO upload 0x2100:01 aborted by the master "
                        "0x05040001 (client/server command specifier not valid or unknown): the "
                        "answer is 5 bytes, shorter than a CoE SDO message (10 bytes)");
    EXPECT_EQ(strays, 0U);
}

// Complete access answers may name the sub-index the access starts from (ETG.1000.6
// §5.6.2.1.1): a late upload answer for 2100h:00 before a complete-access download of 2100h
// from sub 1 is dropped as another transfer's, but it names the same object, not another one.
TEST(SdoOneMachine, ALateAnswerForTheSameIndexIsNotCalledAnotherObjectUnderCompleteAccess) {
    const std::array<std::uint8_t, 1> count = {2};
    const auto [sentence, strays] =
        coe_with({coe_message(CoeService::SdoResponse,
                              sdo::make_initiate_upload_expedited(kIndex, 0, count))},
                 [](Master& m) {
                     const std::vector<std::uint8_t> data = {1, 0, 0, 0};
                     (void)m.sdo_download(0, kIndex, 1, data, true);
                 });
    EXPECT_EQ(sentence, "slave 0 (DRIVE): CoE SDO download 0x2100:01 timed out after 1000 ms (no "
                        "answer to it; 1 other message read and dropped)");
    EXPECT_EQ(strays, 1U);
}

// A message of another CoE service (an SDO information answer left from an earlier request) is
// dropped too, and the timeout counts it with the rest.
TEST(SdoOneMachine, AMessageOfAnotherCoeServiceIsCountedInTheTimeoutSentence) {
    const auto [sentence, strays] = coe_with(
        {coe_message(CoeService::SdoInformation, Payload{0x02, 0x00, 0x00, 0x00, 0x10, 0x10})},
        [](Master& m) { (void)m.sdo_upload(0, kIndex, kSub); });
    EXPECT_EQ(sentence, "slave 0 (DRIVE): CoE SDO upload 0x2100:01 timed out after 1000 ms (no "
                        "answer to it; 1 other message read and dropped)");
    EXPECT_EQ(strays, 1U);
}

// The late abort of a transfer that timed out names that transfer's object (CiA 301
// §7.2.4.3.17): it ends nothing else, and its code is not put on this transfer.
TEST(SdoOneMachine, ALateAbortOfAnEarlierTransferDoesNotEndThisOneOnBoth) {
    const std::array<std::uint8_t, 2> value = {1, 2};
    const Ending coe =
        expect_same(true, {},
                    {sdo::make_abort(0x1010, 1, static_cast<std::uint32_t>(SdoAbort::DataTransfer)),
                     sdo::make_initiate_upload_expedited(kIndex, kSub, value)},
                    {}, std::nullopt, 1)
            .coe;
    EXPECT_EQ(coe.data, (std::vector<std::uint8_t>{1, 2}));
    EXPECT_EQ(coe.strays, 1U);
}

// Dropped answers do not restart the step's timeout: a slave whose SM1 only ever holds answers
// of other transfers fails the transfer after mailbox_timeout, naming what it answered for.
TEST(SdoOneMachine, AStreamOfAnswersForAnotherObjectCannotKeepACoeTransferAlive) {
    const std::array<std::uint8_t, 2> stale = {9, 9};
    const std::vector<Payload> script(3000, sdo::make_initiate_upload_expedited(0x1010, 1, stale));
    const Ending coe = run_coe(true, {}, script, script.size());
    EXPECT_EQ(coe.cause, make_error_code(sdo::SdoErrc::WrongObject)) << coe.sentence;
    EXPECT_EQ(coe.sentence,
              "slave 0 (DRIVE): SDO upload 0x2100:01 failed: response for a different "
              "object: server answered for 0x1010:01 instead of 0x2100:01");
    EXPECT_LT(coe.took, MasterConfig{}.mailbox_timeout + milliseconds(100));
    EXPECT_GT(coe.strays, 100U);
}

TEST(SdoOneMachine, AReservedCommandSpecifierInsteadOfTheInitiateResponseAbortsOnBoth) {
    Payload reserved{};
    reserved[0] = 0xE0; // scs 7: reserved (CiA 301 §7.2.4.3); dropped, then the timeout
    const Ending coe = expect_same(true, {}, {reserved}, abort_error(SdoAbort::UnknownCommand),
                                   SdoAbort::UnknownCommand)
                           .coe;
    EXPECT_EQ(coe.sentence, "slave 0 (DRIVE): SDO upload 0x2100:01 aborted by the master "
                            "0x05040001 (client/server command specifier not valid or unknown): "
                            "no valid response to the initiate request; frames with a reserved "
                            "command specifier came instead");
}

TEST(SdoOneMachine, AToggleErrorAbortsWithTheToggleCodeOnBoth) {
    const Ending coe = expect_same(true, {},
                                   {sdo::make_initiate_upload_segmented(kIndex, kSub, 14),
                                    segment(true, false, {1, 2, 3, 4, 5, 6, 7})},
                                   abort_error(SdoAbort::ToggleBit), SdoAbort::ToggleBit)
                           .coe;
    EXPECT_EQ(coe.sentence,
              "slave 0 (DRIVE): SDO upload 0x2100:01 aborted by the master 0x05030000 (toggle bit "
              "not alternated): segment after 0 of 14 bytes had toggle 1, expected 0");
}

TEST(SdoOneMachine, AZeroLengthSegmentThatIsNotTheLastIsAProtocolErrorNotALoop) {
    // The server would answer every segment request with an empty one: without the progress
    // guard the client would ask forever.
    expect_same(true, {},
                {sdo::make_initiate_upload_segmented(kIndex, kSub, 14), segment(false, false, {}),
                 segment(true, false, {}), segment(false, false, {})},
                abort_error(SdoAbort::General), SdoAbort::General);
}

TEST(SdoOneMachine, MoreDataThanIndicatedAbortsWithLengthTooHighOnBoth) {
    expect_same(true, {},
                {sdo::make_initiate_upload_segmented(kIndex, kSub, 3),
                 segment(false, true, {1, 2, 3, 4, 5, 6, 7})},
                abort_error(SdoAbort::LengthTooHigh), SdoAbort::LengthTooHigh);
}

TEST(SdoOneMachine, LessDataThanIndicatedAbortsWithLengthTooLowOnBoth) {
    expect_same(
        true, {},
        {sdo::make_initiate_upload_segmented(kIndex, kSub, 20), segment(false, true, {1, 2, 3})},
        abort_error(SdoAbort::LengthTooLow), SdoAbort::LengthTooLow);
}

TEST(SdoOneMachine, AServerAbortEndsTheTransferWithItsCodeAndIsNotAnswered) {
    const Ending coe =
        expect_same(true, {},
                    {sdo::make_abort(kIndex, kSub, static_cast<std::uint32_t>(SdoAbort::NoObject))},
                    abort_error(SdoAbort::NoObject), std::nullopt)
            .coe;
    EXPECT_EQ(coe.sentence, "slave 0 (DRIVE): SDO upload 0x2100:01 aborted 0x06020000 (object "
                            "does not exist in the object dictionary)");
}

TEST(SdoOneMachine, AReservedCommandSpecifierMidTransferAbortsWithUnknownCommandOnBoth) {
    Payload reserved{};
    reserved[0] = 0xE0; // scs 7: reserved (CiA 301 §7.2.4.3)
    expect_same(true, {}, {sdo::make_initiate_upload_segmented(kIndex, kSub, 14), reserved},
                abort_error(SdoAbort::UnknownCommand), SdoAbort::UnknownCommand);
}

TEST(SdoOneMachine, ADownloadSegmentResponseWithTheWrongToggleAbortsOnBoth) {
    // 200 bytes: more than one 128-byte CoE mailbox carries, so CoE segments too.
    const std::vector<std::uint8_t> data(200, 0x5A);
    expect_same(false, data,
                {sdo::make_initiate_download_response(kIndex, kSub),
                 sdo::make_download_segment_response(true)},
                abort_error(SdoAbort::ToggleBit), SdoAbort::ToggleBit);
}

} // namespace
} // namespace codrive::ethercat
