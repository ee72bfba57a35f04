// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: EtherCAT frame/datagram decoding and mailbox decoding with arbitrary bytes;
// whatever decodes must re-encode and decode to the same datagrams and messages.
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/mailbox.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

using namespace codrive::ethercat;

namespace {

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
        std::abort();
    }
}

bool same(const Datagram& a, const Datagram& b) {
    return a.command == b.command && a.index == b.index && a.address == b.address &&
           a.data == b.data && a.irq == b.irq && a.wkc == b.wkc;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> in(data, size);

    if (auto datagrams = decode_frame(in); datagrams && !datagrams->empty()) {
        (void)frame_index(in);
        auto frame = encode_frame(*datagrams);
        if (frame) {
            auto again = decode_frame(*frame);
            check(again.has_value(), "re-encoded frame decodes");
            check(again->size() == datagrams->size(), "same datagram count");
            for (std::size_t i = 0; i < again->size(); ++i) {
                check(same((*again)[i], (*datagrams)[i]), "same datagram after round trip");
            }
            // The master's matching of a reply against the datagrams it sent.
            std::vector<Datagram> sent = *datagrams;
            check(decode_frame_into(*frame, sent).has_value(), "reply matches what was sent");
        }
    }
    // In-place walk, as a simulated slave processes a passing frame.
    std::vector<std::uint8_t> copy(in.begin(), in.end());
    (void)for_each_datagram(copy, [](DatagramRef& d) {
        (void)d.adp();
        (void)d.ado();
        d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
        for (auto& b : d.data) {
            b = static_cast<std::uint8_t>(b ^ 0xFF);
        }
    });

    if (auto msg = MailboxMessage::decode(in); msg) {
        const auto bytes = msg->encode();
        auto again = MailboxMessage::decode(bytes);
        check(again.has_value(), "re-encoded mailbox decodes");
        check(again->payload == msg->payload, "same mailbox payload");
        check(again->header.type == msg->header.type &&
                  again->header.counter == msg->header.counter,
              "same mailbox header");
        (void)mailbox_error_text(static_cast<std::uint16_t>(size));
    }
    return 0;
}
