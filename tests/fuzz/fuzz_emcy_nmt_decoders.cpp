// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: arbitrary frames into the small decoders and monitors that face the bus —
// EMCY decode/describe and consumer, NMT command parse and slave, heartbeat consumer, node
// guarding, SYNC consumer, TIME decode and consumer. Nothing may crash, and what decodes must
// re-encode to the same bytes.
#include "fuzz_input.hpp"

#include <codrive/testing/recording_bus.hpp>

#include <codrive/core/cob_id.hpp>
#include <codrive/emcy/consumer.hpp>
#include <codrive/emcy/error_codes.hpp>
#include <codrive/emcy/error_register.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/emcy/text_provider.hpp>
#include <codrive/nmt/command.hpp>
#include <codrive/nmt/heartbeat_consumer.hpp>
#include <codrive/nmt/node_guarding.hpp>
#include <codrive/nmt/slave.hpp>
#include <codrive/sync/consumer.hpp>
#include <codrive/sync/time.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

using namespace codrive;

namespace {

constexpr std::array<emcy::EmcyTextEntry, 3> kVendorRows{{
    {0x2310, "vendor over-current", 0xFFFF, -1, 0},
    {0xFF00, "vendor specific", 0xFF00, 0, 0x01},
    {0x0000, "any code", 0x0000, 4, 0xAA},
}};

/// Every service under test, fed the same frames.
struct Services {
    codrive::testing::RecordingBus bus{"fuzz"};
    emcy::EmcyConsumer emcy;
    nmt::HeartbeatConsumer heartbeats;
    nmt::NodeGuardingMaster guarding{bus};
    nmt::NmtSlave slave{4};
    sync::SyncConsumer sync_consumer;
    sync::TimeConsumer time_consumer;
    std::size_t events = 0;
    bool pending_reset = false;

    explicit Services(TimePoint now, std::uint8_t counter_overflow) {
        emcy.set_text_provider(std::make_shared<emcy::EmcyTextTable>(kVendorRows));
        emcy.set_handler([this](const emcy::EmcyEvent& e) {
            CODRIVE_FUZZ_CHECK(!e.text.empty());
            ++events;
        });
        auto check_event = [this](const nmt::ErrorControlEvent& e) {
            CODRIVE_FUZZ_CHECK(!e.text.empty());
            ++events;
        };
        heartbeats.set_handler(check_event);
        guarding.set_handler(check_event);
        for (NodeId n = 1; n <= 8; ++n) {
            (void)heartbeats.configure(n, milliseconds(50 * n));
        }
        (void)guarding.add(2, milliseconds(20), 3, now);
        (void)guarding.add(7, milliseconds(35), 2, now);
        sync::SyncConsumerConfig sc;
        sc.node = 4;
        sc.cycle_period = milliseconds(10);
        sc.counter_overflow = counter_overflow;
        CODRIVE_FUZZ_CHECK(sync_consumer.configure(sc).has_value());
        sync_consumer.set_handler([this](const sync::SyncEvent& e) {
            CODRIVE_FUZZ_CHECK(!e.text.empty());
            ++events;
        });
        // The owner re-initialises after the command was handled (as a device would).
        slave.set_reset_handler([this](nmt::NmtCommand) { pending_reset = true; });
    }

    void feed(const Frame& f, TimePoint now) {
        (void)emcy.on_frame(f, now);
        heartbeats.on_frame(f, now);
        guarding.on_frame(f, now);
        (void)slave.on_frame(f, now);
        if (pending_reset) {
            pending_reset = false;
            slave.boot_up();
        }
        sync_consumer.on_frame(f, now);
        time_consumer.on_frame(f, now);
    }
    void tick(TimePoint now) {
        for (ITimed* t : std::array<ITimed*, 3>{&heartbeats, &guarding, &sync_consumer}) {
            if (t->next_deadline() <= now) {
                t->on_tick(now);
            }
        }
    }
};

/// Stateless decoders: decode, describe, re-encode.
void decode_one(const Frame& f) {
    if (auto m = emcy::parse_emcy(f); m) {
        CODRIVE_FUZZ_CHECK(valid_node_id(m->node));
        CODRIVE_FUZZ_CHECK(!emcy::describe(*m).empty());
        const Frame again = emcy::make_emcy_frame(*m);
        CODRIVE_FUZZ_CHECK(again.id == f.id);
        // The 3..8 bytes that were on the wire come back unchanged.
        for (std::size_t i = 0; i < f.len && i < 8; ++i) {
            CODRIVE_FUZZ_CHECK(again.data[i] == f.data[i]);
        }
        (void)emcy::error_code_text(m->error_code);
        (void)emcy::describe_error_register(m->error_register);
    }
    if (auto m = emcy::parse_emcy(f, 0x11); m) {
        CODRIVE_FUZZ_CHECK(m->node == 0x11);
    }
    if (auto c = nmt::parse_command_frame(f); c) {
        CODRIVE_FUZZ_CHECK(!nmt::to_string(c->command).empty());
        const auto again = nmt::make_command_frame(c->command, c->node);
        CODRIVE_FUZZ_CHECK(again.has_value());
        CODRIVE_FUZZ_CHECK(again->data[0] == f.data[0] && again->data[1] == f.data[1]);
        (void)nmt::expected_state_name(c->command);
    }
    if (auto t = sync::decode_time_of_day(f.payload()); t) {
        CODRIVE_FUZZ_CHECK(t->ms_after_midnight < sync::kMsPerDay);
        const auto bytes = sync::encode(*t);
        const auto back = sync::decode_time_of_day(bytes);
        CODRIVE_FUZZ_CHECK(back.has_value() && *back == *t);
        (void)sync::to_string(*t);
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::Input in(data, size);
    TimePoint now = TimePoint{} + std::chrono::hours(1);
    const std::uint8_t overflow_pick = in.byte() % 4;
    const std::uint8_t overflow = overflow_pick == 0 ? 0 : (overflow_pick == 1 ? 2 : 240);
    Services s(now, overflow);

    while (!in.empty()) {
        const std::uint8_t op = in.byte();
        if (op % 8 == 7) { // time passes: 0..255 ms
            now += milliseconds(in.byte());
            s.tick(now);
            continue;
        }
        // Ids concentrated on the ranges the services listen to (000h NMT, 080h SYNC,
        // 081h..0FFh EMCY, 100h TIME, 700h..77Fh heartbeat) plus any 11-bit id.
        static constexpr std::array<std::uint32_t, 6> kBases{0x000, 0x080, 0x080,
                                                             0x100, 0x700, 0x000};
        const std::uint8_t pick = in.byte();
        std::uint32_t id = kBases[(op % 8) % kBases.size()];
        if (op % 8 == 1 || op % 8 == 2 || op % 8 == 4) {
            id += pick & 0x7FU;
        } else if (op % 8 == 5) {
            id = static_cast<std::uint32_t>((pick << 3) | (op >> 5)) & Frame::kStdMask;
        }
        const std::size_t len = static_cast<std::size_t>(op >> 4) % 9;
        Frame f = Frame::make(id, in.bytes(len));
        if (op % 8 == 6) {
            f.flags = static_cast<std::uint8_t>(pick & 0x1FU); // RTR / extended / FD / error
            if (f.extended()) {
                f.id = (static_cast<std::uint32_t>(in.u16()) << 13 | f.id) & Frame::kExtMask;
            }
        }
        decode_one(f);
        s.feed(f, now);
    }
    // Monitors keep running on their own with no input.
    now += seconds(2);
    s.tick(now);
    for (NodeId n = 1; n <= kMaxNodeId; ++n) {
        (void)s.emcy.history(n);
        (void)s.emcy.active(n);
        CODRIVE_FUZZ_CHECK(s.emcy.active(n).count <= emcy::ActiveErrors::kMaxCodes);
    }
    return 0;
}
