// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: everything an EtherCAT slave sends, as the master meets it. The master runs
// its real bring-up and CoE work (scan with SII reads, AL status, ESM transitions, SDO upload and
// download in every size, SDO information, emergencies, process data) against simulated drives
// whose answers the fuzzer corrupts on their way back (SII words, AL status codes, mailbox
// headers, CoE SDO and SDO information replies), loses, or takes with a failing receive or send
// (the interface down, or its transmit queue full).
// Whatever comes back, every call must end (on the fake clock) with a result, and every failure
// must read as a sentence naming the slave.
#include "fuzz_input.hpp"

#include <codrive/ethercat/master.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

using namespace codrive;

namespace {

/// The wire between the master and the simulated segment: the fuzzer decides, frame by frame,
/// which answer bytes arrive corrupted and which frames are lost.
class CorruptingLink final : public ethercat::IEcatLink {
public:
    CorruptingLink(sim::ecat::EcatSegment& segment, FakeClock& clock, fuzz::Input& in)
        : inner_(segment, clock), clock_(clock), in_(in) {}

    VoidResult send(std::span<const std::uint8_t> frame) override {
        if (fail_send_) { // the interface is down, or its queue full: the frame does not leave
            return fail(std::make_error_code(*std::exchange(fail_send_, std::nullopt)));
        }
        return inner_.send(frame);
    }

    Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) override {
        auto got = inner_.receive(buffer, deadline);
        if (!got || in_.empty()) {
            return got; // out of input: the slaves answer as they are
        }
        const std::uint8_t op = in_.byte();
        if (op == 0x7F) { // lost on the wire: the master waits out its deadline
            clock_.set(std::max(clock_.now(), deadline));
            return fail(CoreErrc::Timeout);
        }
        if (op == 0x7E) { // the socket fails (interface down): the frame's answers are gone
            return fail(std::make_error_code(std::errc::network_down));
        }
        if (op == 0x7D || op == 0x7C) { // this frame arrives as it is; the next send fails
            fail_send_ = op == 0x7D ? std::errc::network_down : std::errc::no_buffer_space;
            return got;
        }
        if ((op & 0x80) == 0 || *got == 0) {
            return got;
        }
        // 1..8 byte changes; offsets past the Ethernet header land in datagram headers and data
        // (register values, SII words, mailbox headers, CoE and SDO bytes).
        const int changes = (op & 0x07) + 1;
        for (int i = 0; i < changes && !in_.empty(); ++i) {
            const std::size_t at = in_.u16() % *got;
            const std::uint8_t value = in_.byte();
            buffer[at] = (op & 0x08) != 0 ? value : static_cast<std::uint8_t>(buffer[at] ^ value);
        }
        return got;
    }

    void idle(Duration d) override { inner_.idle(d); }
    [[nodiscard]] std::string name() const override { return "fuzzed segment"; }

private:
    sim::ecat::SegmentLink inner_;
    FakeClock& clock_;
    fuzz::Input& in_;
    std::optional<std::errc> fail_send_; ///< the next send's error, if it fails
};

/// A failed call leaves a sentence behind; CoE failures name the slave they concern.
void check_failure(const ethercat::Master& master, bool coe) {
    const std::string text = master.last_error();
    CODRIVE_FUZZ_CHECK(!text.empty());
    if (coe) {
        CODRIVE_FUZZ_CHECK(text.find("slave") != std::string::npos);
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::Input in(data, size);
    FakeClock clock;
    // One drive per run (the first byte picks it), so a run stays short.
    static constexpr const char* kDrives[] = {"akd2g", "fio", "ds-bvs"};
    sim::ecat::EcatSegment segment;
    segment.add(sim::ecat::make_drive_slave(kDrives[in.byte() % 3], 7));
    CorruptingLink link(segment, clock, in);
    ethercat::MasterConfig config;
    config.mailbox_timeout = milliseconds(50); // keeps a fuzz run short; the logic is the same
    ethercat::Master master(link, clock, config);
    std::size_t emergencies = 0;
    master.on_emergency([&](std::size_t slave, const emcy::EmcyMessage&) {
        CODRIVE_FUZZ_CHECK(slave < master.slaves().size());
        ++emergencies;
    });

    if (!master.scan()) {
        check_failure(master, false);
        return 0;
    }
    CODRIVE_FUZZ_CHECK(master.slaves().size() <= segment.size());
    if (!master.set_state_all(ethercat::AlState::PreOp)) {
        check_failure(master, false);
        return 0;
    }
    for (std::size_t s = 0; s < master.slaves().size(); ++s) {
        if (auto st = master.read_al_status(s); st) {
            (void)ethercat::al_status_code_text(st->code);
        }
        if (!master.slaves()[s].sii.has_coe()) {
            continue;
        }
        // Expedited, normal and segmented transfers in both directions, complete access too.
        if (!master.sdo_upload(s, 0x1018, 1)) {
            check_failure(master, true);
        }
        if (!master.sdo_upload(s, 0x1008, 0)) {
            check_failure(master, true);
        }
        if (!master.sdo_upload(s, 0x1C12, 0, true)) {
            check_failure(master, true);
        }
        const std::vector<std::uint8_t> text(300, 'x');
        if (!master.sdo_download(s, sim::ecat::kScratchStringIndex, 0, text)) {
            check_failure(master, true);
        }
        if (auto back = master.sdo_upload(s, sim::ecat::kScratchStringIndex, 0); !back) {
            check_failure(master, true);
        }
        if (!master.sdo_write<std::uint32_t>(s, 0x6081, 0, 1000)) {
            check_failure(master, true);
        }
        // SDO information: the object list and one description, fragments and all.
        if (auto list = master.sdo_info_object_list(s); !list) {
            check_failure(master, true);
        }
        if (!master.sdo_info_object(s, 0x6040)) {
            check_failure(master, true);
        }
        if (!master.sdo_info_entry(s, 0x1018, 1)) {
            check_failure(master, true);
        }
        master.poll_mailboxes();
    }
    // A few cycles of process data with asynchronous CoE work beside them.
    if (!master.set_state_all(ethercat::AlState::Op)) {
        check_failure(master, false);
        return 0;
    }
    int finished = 0;
    int queued = 0;
    for (std::size_t s = 0; s < master.slaves().size(); ++s) {
        if (master.sdo_upload_async(s, 0x6041, 0, [&](const ethercat::CoeOutcome& out) {
                ++finished;
                if (out.error) {
                    CODRIVE_FUZZ_CHECK(out.sentence.find("slave") != std::string::npos);
                }
            })) {
            ++queued;
        }
    }
    for (int cycle = 0; cycle < 40; ++cycle) {
        if (!master.exchange_process_data()) {
            CODRIVE_FUZZ_CHECK(!master.last_error().empty()); // lost, refused, not sent: said
        }
        clock.advance(milliseconds(2));
    }
    for (std::size_t s = 0; s < master.slaves().size(); ++s) {
        master.run_mailbox_until_idle(s);
    }
    CODRIVE_FUZZ_CHECK(finished == queued); // every transfer ends, exactly once
    (void)emergencies;
    return 0;
}
