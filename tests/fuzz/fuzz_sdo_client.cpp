// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: an SdoClient with queued uploads and downloads of several sizes and modes is
// fed arbitrary response frames, cancels and cancel_all(); once time passes the timeout every
// transfer must have ended (success, abort or timeout) with exactly one callback, and every
// failure must read as a sentence naming the node and the object.
#include "fuzz_input.hpp"

#include <codrive/testing/recording_bus.hpp>

#include <codrive/core/cob_id.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sdo/protocol.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

using namespace codrive;

namespace {

constexpr NodeId kNode = 9;

struct Tracker {
    std::vector<int> fired; ///< callbacks per transfer (must end at exactly 1)

    std::size_t add() {
        fired.push_back(0);
        return fired.size() - 1;
    }
    void done(std::size_t slot, const sdo::SdoError* error) {
        CODRIVE_FUZZ_CHECK(slot < fired.size());
        ++fired[slot];
        CODRIVE_FUZZ_CHECK(fired[slot] == 1);
        if (error != nullptr) {
            const std::string text = error->to_string();
            CODRIVE_FUZZ_CHECK(!text.empty());
            CODRIVE_FUZZ_CHECK(text.find("node 9") != std::string::npos);
            CODRIVE_FUZZ_CHECK(text.find("0x") != std::string::npos); // names the object
            CODRIVE_FUZZ_CHECK(error->node == kNode);
            CODRIVE_FUZZ_CHECK(static_cast<bool>(error->cause));
        }
    }
    [[nodiscard]] bool all_fired() const {
        for (int f : fired) {
            if (f != 1) {
                return false;
            }
        }
        return true;
    }
};

sdo::Bytes pattern(std::size_t n) {
    sdo::Bytes b(n);
    for (std::size_t i = 0; i < n; ++i) {
        b[i] = static_cast<std::uint8_t>(i * 7 + 3);
    }
    return b;
}

void check_request(const Frame& f) {
    CODRIVE_FUZZ_CHECK(f.id == cob::sdo_rx(kNode));
    CODRIVE_FUZZ_CHECK(f.len == sdo::kFrameLen);
    CODRIVE_FUZZ_CHECK(f.valid());
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::Input in(data, size);
    codrive::testing::RecordingBus bus{"fuzz"};
    FakeClock clock;

    sdo::ClientConfig config;
    config.node = kNode;
    config.timeout = milliseconds(100);
    config.block_gap_timeout = milliseconds(10);
    config.retries = in.byte() % 3;
    config.watch_boot_up = (in.byte() & 1U) == 0;
    Tracker tracker;
    std::vector<sdo::TransferId> ids;
    {
        sdo::SdoClient client(bus, clock, config);
        auto upload = [&](std::uint16_t index, sdo::TransferOptions opt) {
            const std::size_t slot = tracker.add();
            ids.push_back(client.upload(
                index, 0,
                [&tracker, slot](sdo::SdoResult<sdo::Bytes> r) {
                    tracker.done(slot, r ? nullptr : &r.error());
                },
                std::move(opt)));
        };
        auto download = [&](std::uint16_t index, std::size_t n, sdo::Mode mode) {
            const std::size_t slot = tracker.add();
            sdo::TransferOptions opt;
            opt.mode = mode;
            opt.crc = (n % 2) == 0;
            ids.push_back(client.download(
                index, 0, pattern(n),
                [&tracker, slot](sdo::SdoResult<void> r) {
                    tracker.done(slot, r ? nullptr : &r.error());
                },
                std::move(opt)));
        };

        // The first callback queues one more transfer, as applications chain requests.
        const std::size_t first = tracker.add();
        ids.push_back(client.upload(0x1000, 0, [&](sdo::SdoResult<sdo::Bytes> r) {
            tracker.done(first, r ? nullptr : &r.error());
            const std::size_t slot = tracker.add();
            client.upload(0x1001, 0, [&tracker, slot](sdo::SdoResult<sdo::Bytes> r2) {
                tracker.done(slot, r2 ? nullptr : &r2.error());
            });
        }));
        sdo::TransferOptions seg;
        seg.mode = sdo::Mode::Segmented;
        upload(0x1008, seg);
        sdo::TransferOptions block;
        block.mode = sdo::Mode::Block;
        block.block_size = static_cast<std::uint8_t>(1 + in.byte() % sdo::kMaxBlockSize);
        block.pst = in.byte() % 8;
        block.crc = (in.byte() & 1U) == 0;
        block.progress = [](std::size_t, std::optional<std::size_t>) {};
        upload(0x2002, block);
        download(0x2001, 0, sdo::Mode::Auto);
        download(0x2001, 4, sdo::Mode::Auto);
        download(0x2005, 5, sdo::Mode::Segmented);
        download(0x2005, 20, sdo::Mode::Segmented);
        download(0x2003, 100, sdo::Mode::Block);
        download(0x2003, 1000, sdo::Mode::Block);
        // A streamed upload whose sink refuses large objects and stops after 2 KiB.
        {
            const std::size_t slot = tracker.add();
            auto got = std::make_shared<std::size_t>(0);
            sdo::UploadSink sink;
            sink.begin = [](std::optional<std::size_t> n) { return !n || *n <= 4096; };
            sink.write = [got](std::span<const std::uint8_t> d) {
                *got += d.size();
                return *got <= 2048;
            };
            sdo::TransferOptions opt;
            opt.mode = (in.byte() & 1U) != 0 ? sdo::Mode::Block : sdo::Mode::Auto;
            ids.push_back(client.upload(
                0x2003, 0, std::move(sink),
                [&tracker, slot](sdo::SdoResult<void> r) {
                    tracker.done(slot, r ? nullptr : &r.error());
                },
                std::move(opt)));
        }

        while (!in.empty()) {
            const std::uint8_t op = in.byte();
            switch (op % 8) {
            case 0:
            case 1:
            case 2:
            case 3: { // a response on the client's channel
                const std::size_t len =
                    (op & 0x08U) == 0 ? 8U : static_cast<std::size_t>(op >> 4) % 9;
                client.on_frame(Frame::make(cob::sdo_tx(kNode), in.bytes(len)), clock.now());
                break;
            }
            case 4:
            case 5: // time passes: 0..255 ms
                clock.advance(milliseconds(in.byte()));
                if (client.next_deadline() <= clock.now()) {
                    client.on_tick(clock.now());
                }
                break;
            case 6: { // another frame: boot-up / heartbeat of the node, or anything else
                Frame f = (op & 0x08U) != 0
                              ? Frame::make(cob::heartbeat(kNode), in.bytes(1))
                              : Frame::make(static_cast<std::uint32_t>(in.u16() & Frame::kStdMask),
                                            in.bytes(8));
                client.on_frame(f, clock.now());
                break;
            }
            default: // the application cancels a transfer, rarely all of them (shutdown)
                if (op == 0xFF) {
                    (void)client.cancel_all("shut down");
                    CODRIVE_FUZZ_CHECK(tracker.all_fired());
                    CODRIVE_FUZZ_CHECK(!client.busy() && client.queued() == 0);
                } else if (!ids.empty()) {
                    (void)client.cancel(ids[in.byte() % ids.size()]);
                }
                break;
            }
        }
        // Time passes well beyond every timeout: each transfer must end by then.
        for (int i = 0; i < 1000 && !tracker.all_fired(); ++i) {
            clock.advance(milliseconds(50));
            if (client.next_deadline() <= clock.now()) {
                client.on_tick(clock.now());
            }
        }
        for (const Frame& f : bus.sent) {
            check_request(f);
        }
        CODRIVE_FUZZ_CHECK(tracker.all_fired());
        CODRIVE_FUZZ_CHECK(!client.busy());
        CODRIVE_FUZZ_CHECK(client.queued() == 0);
    }
    return 0;
}
