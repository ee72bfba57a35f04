// SPDX-License-Identifier: Apache-2.0
// Fuzzes the conversation decoder directly with binary frames (no text parsing in between), so
// the fuzzer reaches deep SDO block/segment and PDO mapping states quickly; the statistics of
// --stats follow every frame, and those of --report (buckets, histograms, JSON) every frame of
// an input of odd length. Building the report cost about as much as decoding a whole input, and
// hardly depends on it (fixed node rows and histograms): on every input it halved the rate.
#include "fuzz_input.hpp"

#include <codrive/dump/decoder.hpp>
#include <codrive/dump/report_data.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace codrive;
    using namespace codrive::dump;
    fuzz::Input in(data, size);
    Stats stats(250000);
    const bool report = (size % 2) != 0; // libFuzzer's mutations reach both lengths
    if (report) {
        stats.enable_report(); // the report's buckets and histograms see every frame too
    }
    DecoderOptions o;
    o.sdo_timeout_ns = 5'000'000;
    Decoder decoder(o, &stats);
    Decoded out;
    std::vector<Note> notes;
    TraceRecord r;
    std::int64_t ts = 1'000'000'000;
    while (!in.empty()) {
        // Frame: id (2 bytes; bits 11..15 pick flags and the time step), len (its top bits
        // pick the interface, a record without a timestamp and a step back), data. The second
        // interface's clock runs 3 s ahead of the first: times of two interfaces interleave.
        const std::uint16_t head = in.u16();
        Frame f;
        f.id = head & Frame::kStdMask;
        if ((head & 0x800U) != 0) {
            f.flags = Frame::kRtr;
        }
        const std::uint8_t len = in.byte();
        f.len = static_cast<std::uint8_t>(len % 9);
        const auto bytes = in.bytes(f.len);
        std::copy(bytes.begin(), bytes.end(), f.data.begin());
        ts += static_cast<std::int64_t>(head >> 12) * 1'000'000;
        if ((len & 0x40U) != 0 && (head >> 12) == 15) {
            ts = ts > 2'000'000'000 ? ts - 2'000'000'000 : 0; // another capture appended
        }
        const bool second = (len & 0x80U) != 0;
        r.iface = second ? "fuzz1" : "fuzz";
        r.has_ts = (len & 0x20U) == 0 || (head >> 12) != 0;
        r.frame = f;
        r.ts_ns = second ? ts + 3'000'000'000 : ts;
        decoder.decode(r, out, notes);
        if (out.severity >= Severity::Warning) {
            stats.on_event(ts, out.node, out.service == Service::Emcy, to_string(out.severity),
                           to_string(out.service),
                           std::string_view(out.text.data(), out.text.size()));
        }
        notes.clear();
    }
    decoder.finish(notes);
    (void)stats.table();
    if (report) {
        (void)report_json(stats, ReportInfo{"fuzz", "fuzz"});
    }
    return 0;
}
