// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: arbitrary frame sequences and time steps into an SdoServer; every response
// must be well-formed and no request may get more answers than the protocol allows.
#include "fuzz_input.hpp"

#include <codrive/testing/recording_bus.hpp>

#include <codrive/core/cob_id.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/sdo/protocol.hpp>
#include <codrive/sdo/server.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

using namespace codrive;

namespace {

constexpr NodeId kNode = 5;

/// A small dictionary covering every transfer kind: expedited (u8/u32), segmented (string,
/// octet string), write-only, range-limited and a DOMAIN kept in the dictionary.
void build_od(ObjectDictionary& od) {
    od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
               *Value::from_uint(DataType::Unsigned32, 0x00020192));
    od.add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
               Value::from_string("codrive fuzz device with a long name"));
    SubObject limited = SubObject::make(0, "Limited", DataType::Unsigned8, Access::Rw,
                                        *Value::from_uint(DataType::Unsigned8, 10));
    limited.low_limit = *Value::from_uint(DataType::Unsigned8, 5);
    limited.high_limit = *Value::from_uint(DataType::Unsigned8, 50);
    Object obj;
    obj.index = 0x2000;
    obj.name = "Limited";
    obj.subs.emplace(0, limited);
    od.insert(obj);
    od.add_var(0x2001, "Word", DataType::Unsigned32, Access::Rw, Value::zero(DataType::Unsigned32));
    od.add_var(0x2002, "Domain", DataType::Domain, Access::Rw,
               Value(DataType::Domain, std::vector<std::uint8_t>(200, 0xA5)));
    od.add_var(0x2004, "Write only", DataType::Unsigned16, Access::Wo,
               Value::zero(DataType::Unsigned16));
    od.add_var(0x2005, "Octets", DataType::OctetString, Access::Rw,
               Value(DataType::OctetString, std::vector<std::uint8_t>(20, 0x11)));
    od.add_sub(0x2010,
               SubObject::make(0, "Highest sub-index", DataType::Unsigned8, Access::Ro,
                               *Value::from_uint(DataType::Unsigned8, 2)),
               "Record");
    od.add_sub(0x2010, SubObject::make(1, "a", DataType::Integer16, Access::Rw,
                                       Value::zero(DataType::Integer16)));
    od.add_sub(0x2010, SubObject::make(2, "b", DataType::Real32, Access::Rw,
                                       Value::zero(DataType::Real32)));
}

/// Responses a request of this command may cause: a block upload start or ack sends a whole
/// sub-block (up to 127 segments, CiA 301 §7.2.4.3.14), everything else exactly one frame.
std::size_t max_responses(const Frame& request) {
    if (request.len == 0) {
        return 1;
    }
    const auto ccs = static_cast<sdo::ClientCommand>(sdo::command_bits(request.data[0]));
    return ccs == sdo::ClientCommand::BlockUpload ? sdo::kMaxBlockSize + 1U : 1U;
}

void check_response(const Frame& f, bool block_upload_context) {
    CODRIVE_FUZZ_CHECK(f.id == cob::sdo_tx(kNode));
    CODRIVE_FUZZ_CHECK(f.len == sdo::kFrameLen);
    CODRIVE_FUZZ_CHECK(!f.rtr() && !f.extended() && !f.fd() && !f.error());
    CODRIVE_FUZZ_CHECK(f.valid());
    if (block_upload_context) {
        // Inside a sub-block byte 0 is c + seqno (1..127); only 0x80 is an abort there.
        const sdo::FrameInfo seg = sdo::parse_frame(f.payload(), sdo::Sender::Server, true);
        if (seg.kind == sdo::FrameKind::BlockSegment) {
            CODRIVE_FUZZ_CHECK(seg.seqno >= 1 && seg.seqno <= sdo::kMaxBlockSize);
            return;
        }
    }
    const sdo::FrameInfo info = sdo::parse_frame(f.payload(), sdo::Sender::Server);
    CODRIVE_FUZZ_CHECK(info.kind != sdo::FrameKind::Invalid);
    if (info.kind == sdo::FrameKind::Abort) {
        if (info.abort_code == 0) {
            std::fprintf(stderr, "abort frame with code 0: %s\n", to_string(f).c_str());
        }
        CODRIVE_FUZZ_CHECK(info.abort_code != 0);
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::Input in(data, size);
    codrive::testing::RecordingBus bus{"fuzz"};
    ObjectDictionary od;
    build_od(od);

    sdo::ServerConfig config;
    config.node = kNode;
    config.timeout = milliseconds(200);
    config.block_gap_timeout = milliseconds(20);
    config.block_size = static_cast<std::uint8_t>(1 + in.byte() % sdo::kMaxBlockSize);
    config.expedited_upload = (in.byte() & 1U) == 0;
    config.crc = (in.byte() & 1U) == 0;
    sdo::SdoServer server(od, bus, config);

    // A streamed DOMAIN at 0x2003: uploads of 300 bytes, downloads kept up to 4 KiB.
    std::vector<std::uint8_t> domain_in;
    server.set_domain_upload(0x2003, 0, [](std::uint16_t, std::uint8_t) {
        auto pos = std::make_shared<std::size_t>(0);
        sdo::DomainReader r;
        r.size = 300;
        r.read = [pos](std::span<std::uint8_t> out) -> tl::expected<void, SdoAbort> {
            for (auto& b : out) {
                b = static_cast<std::uint8_t>((*pos)++);
            }
            return {};
        };
        return tl::expected<sdo::DomainReader, SdoAbort>(std::move(r));
    });
    server.set_domain_download(
        0x2003, 0,
        [&domain_in](std::uint16_t, std::uint8_t, std::optional<std::size_t> announced)
            -> tl::expected<sdo::DomainWriter, SdoAbort> {
            if (announced && *announced > 4096) {
                return tl::unexpected(SdoAbort::LengthTooHigh);
            }
            domain_in.clear();
            sdo::DomainWriter w;
            w.write =
                [&domain_in](std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                if (domain_in.size() + d.size() > 4096) {
                    return tl::unexpected(SdoAbort::OutOfMemory);
                }
                domain_in.insert(domain_in.end(), d.begin(), d.end());
                return {};
            };
            w.finish = []() -> tl::expected<void, SdoAbort> { return {}; };
            w.cancel = [&domain_in]() { domain_in.clear(); };
            return w;
        });
    // 0x2006 is refused by the access hook, as a device in the wrong state would.
    od.add_var(0x2006, "Locked", DataType::Unsigned8, Access::Rw, Value::zero(DataType::Unsigned8));
    server.set_access_hook(
        [](std::uint16_t index, std::uint8_t, sdo::Direction) -> std::optional<SdoAbort> {
            if (index == 0x2006) {
                return SdoAbort::DataTransferState;
            }
            return std::nullopt;
        });

    TimePoint now = TimePoint{} + std::chrono::hours(1);
    bool block_upload = false; ///< the last request was a block upload command
    while (!in.empty()) {
        const std::uint8_t op = in.byte();
        switch (op % 4) {
        case 0:
        case 1: { // a request on the server's channel: 8 bytes, or a short/long frame
            const std::size_t len = (op & 0x04U) == 0 ? 8U : static_cast<std::size_t>(op >> 3) % 9;
            const auto payload = in.bytes(len);
            const Frame request = Frame::make(cob::sdo_rx(kNode), payload);
            bus.sent.clear();
            const bool used = server.on_frame(request, now);
            (void)used;
            if (request.len > 0) {
                block_upload =
                    static_cast<sdo::ClientCommand>(sdo::command_bits(request.data[0])) ==
                    sdo::ClientCommand::BlockUpload;
            }
            // Never more than one response per request (a sub-block for block upload).
            CODRIVE_FUZZ_CHECK(bus.sent.size() <= max_responses(request));
            for (const Frame& f : bus.sent) {
                check_response(f, block_upload);
            }
            break;
        }
        case 2: { // time passes: 0..255 steps of 2 ms, the server's timers run
            now += milliseconds(2) * in.byte();
            if (server.next_deadline() <= now) {
                bus.sent.clear();
                server.on_tick(now);
                // A tick sends at most one frame: an early block ack or a timeout abort.
                CODRIVE_FUZZ_CHECK(bus.sent.size() <= 1);
                for (const Frame& f : bus.sent) {
                    check_response(f, false);
                }
            }
            break;
        }
        default: { // traffic not for this server: must be ignored without an answer
            Frame other =
                Frame::make(static_cast<std::uint32_t>(in.u16() & Frame::kStdMask), in.bytes(8));
            if (other.id == cob::sdo_rx(kNode)) {
                other.id = cob::sdo_tx(kNode);
            }
            if ((op & 0x10U) != 0) {
                other.flags |= Frame::kRtr;
            }
            bus.sent.clear();
            CODRIVE_FUZZ_CHECK(!server.on_frame(other, now));
            CODRIVE_FUZZ_CHECK(bus.sent.empty());
            break;
        }
        }
    }
    // Whatever state the input left, time running out returns the server to idle.
    for (int i = 0; i < 4 && server.busy(); ++i) {
        now += seconds(1);
        server.on_tick(now);
    }
    CODRIVE_FUZZ_CHECK(!server.busy());
    return 0;
}
