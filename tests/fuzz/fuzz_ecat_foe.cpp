// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: whatever a slave answers to an FoE read or write (any mailbox type, opcode,
// packet number, length), the master's FoE transfer ends exactly once, within its timeouts, with
// data no larger than asked for or a sentence naming the slave and the file; nothing crashes.
#include "fuzz_input.hpp"

#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/foe.hpp>
#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/master.hpp>

#include <deque>

using namespace codrive;
using namespace codrive::ethercat;

namespace {

constexpr std::uint16_t kSm0 = 0x1000;
constexpr std::uint16_t kSm1 = 0x1080;
constexpr std::uint16_t kMailbox = 128;

/// A slave whose every mailbox read returns the next message cut from the fuzzer input (WKC 1)
/// or nothing (WKC 0) once the input is used up; every write is taken.
class FuzzLink final : public IEcatLink {
public:
    FuzzLink(fuzz::Input& in, FakeClock& clock) : in_(in), clock_(clock) {}
    VoidResult send(std::span<const std::uint8_t> frame) override {
        clock_.advance(milliseconds(1));
        auto datagrams = decode_frame(frame);
        if (!datagrams) {
            return {};
        }
        for (auto& d : *datagrams) {
            d.wkc = 1;
            if (d.command == Command::Fprd && (d.address >> 16) == kSm1) {
                if (in_.empty()) {
                    d.wkc = 0;
                    continue;
                }
                // Mostly FoE, sometimes another mailbox type or a malformed header.
                const std::uint8_t kind = in_.byte();
                MailboxMessage m;
                m.header.type =
                    (kind & 0x07) == 0 ? static_cast<MailboxType>(kind >> 4) : MailboxType::Foe;
                m.header.counter = static_cast<std::uint8_t>(kind >> 5);
                const auto body = in_.bytes(in_.byte() % (kMailbox - kMailboxHeaderSize + 1));
                m.payload.assign(body.begin(), body.end());
                auto bytes = m.encode(kMailbox);
                if ((kind & 0x0F) == 0x08) {
                    bytes[0] = 0xFF; // a length past the mailbox
                }
                std::copy(bytes.begin(), bytes.end(), d.data.begin());
            }
        }
        if (auto out = encode_frame(*datagrams)) {
            pending_.push_back(std::move(*out));
        }
        return {};
    }
    Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) override {
        if (pending_.empty()) {
            clock_.set(deadline);
            return fail(CoreErrc::Timeout);
        }
        auto f = std::move(pending_.front());
        pending_.pop_front();
        const std::size_t n = std::min(buffer.size(), f.size());
        std::copy_n(f.begin(), n, buffer.begin());
        return n;
    }
    void idle(Duration d) override { clock_.advance(d); }
    [[nodiscard]] std::string name() const override { return "fuzz link"; }

private:
    fuzz::Input& in_;
    FakeClock& clock_;
    std::deque<std::vector<std::uint8_t>> pending_;
};

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
        std::abort();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::Input in(data, size);
    const bool write = (in.byte() & 1) != 0;
    FakeClock clock;
    FuzzLink link(in, clock);
    Master master(link, clock);
    SlaveInfo s;
    s.station_address = 0x1001;
    s.state = AlState::PreOp;
    s.sii.name = "FUZZ";
    s.sii.rx_mailbox_offset = kSm0;
    s.sii.rx_mailbox_size = kMailbox;
    s.sii.tx_mailbox_offset = kSm1;
    s.sii.tx_mailbox_size = kMailbox;
    s.sii.mailbox_protocols = mbx_proto::kFoe;
    master.slaves().push_back(s);

    int calls = 0;
    CoeOutcome out;
    FoeOptions o;
    o.max_read_bytes = 4096;
    o.busy_timeout = milliseconds(50);
    auto done = [&](CoeOutcome r) {
        ++calls;
        out = std::move(r);
    };
    const VoidResult queued =
        write ? master.foe_write_async(0, "f.akd", std::vector<std::uint8_t>(300, 7), done, o)
              : master.foe_read_async(0, "f.akd", done, o);
    check(queued.has_value(), "the transfer is queued");
    const TimePoint start = clock.now();
    while (calls == 0 && clock.now() - start < seconds(60)) {
        (void)master.run_mailbox_cycle();
    }
    check(calls == 1, "the transfer ends exactly once");
    // Each step has its own 1 s timeout; a slave cannot keep it going with garbage, only with
    // well-formed DATA/ACK/BUSY, which the input's length bounds.
    check(clock.now() - start < seconds(60), "the transfer ends within its timeouts");
    if (out.error) {
        check(out.sentence.rfind("slave 0 (FUZZ): FoE ", 0) == 0, "the sentence names the slave");
        check(out.sentence.find("'f.akd'") != std::string::npos, "the sentence names the file");
    } else if (!write) {
        check(out.data.size() <= o.max_read_bytes, "a read stays within max_read_bytes");
    }
    return 0;
}
