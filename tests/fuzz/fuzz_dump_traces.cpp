// SPDX-License-Identifier: Apache-2.0
// Fuzzes every trace reader of codrive-dump (candump, PEAK trc, Vector asc, CSV, pcap/pcapng, BLF)
// and the pcap/pcapng writer: the first byte picks a reader (or content detection), the rest is the
// file. Readers must end (End or Fatal), never crash, and report every malformed entry.
#include <codrive/dump/pcap.hpp>
#include <codrive/dump/trace_format.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace codrive::dump;
    if (size == 0) {
        return 0;
    }
    static auto pcap = PcapWriter::open("/dev/null", PcapWriter::Format::Pcap);
    static auto pcapng = PcapWriter::open("/dev/null", PcapWriter::Format::Pcapng);
    const std::uint8_t pick = data[0];
    auto in = BufferedInput::from_memory(
        std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
    auto reader =
        pick < 6 ? make_trace_reader(static_cast<TraceFormat>(pick), *in) : open_trace_reader(*in);
    TraceRecord r;
    // Every step consumes input, so the number of steps is bounded by the input size (inflated,
    // for a gzip input).
    // A BLF file's containers are zlib streams too, so inflated bytes may inflate again.
    const std::size_t max_steps = in->max_plain_bytes(size) * kMaxInflateRatio + 2;
    for (std::size_t steps = 0;; ++steps) {
        if (steps > max_steps) {
            __builtin_trap(); // a reader that does not advance would hang the tool
        }
        const auto status = reader->next(r);
        if (status == ReadStatus::End || status == ReadStatus::Fatal) {
            break;
        }
        if (status == ReadStatus::Malformed) {
            if (reader->error().empty()) {
                __builtin_trap(); // a skipped entry must say why
            }
            continue;
        }
        if (r.frame.len > (r.frame.fd() ? 64 : 8)) {
            __builtin_trap();
        }
        if (pcap && pcapng) {
            (*pcap)->write(r);
            (*pcapng)->write(r);
        }
    }
    return 0;
}
