// SPDX-License-Identifier: Apache-2.0
// Fuzzes codrive-dump's input side end to end: gzip inflation, format detection, the candump
// log/screen parser, the pcap/pcapng reader, and every decoder behind them (text and JSON output).
#include <codrive/dump/dumper.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace codrive::dump;
    if (size == 0) {
        return 0;
    }
    // The first byte picks output options so both formatters and the filters run.
    const std::uint8_t mode = data[0];
    DumpOptions o;
    o.line.json = (mode & 1U) != 0;
    o.line.color = (mode & 2U) != 0;
    o.line.time = static_cast<TimeMode>((mode >> 2) & 3U);
    o.stats = (mode & 16U) != 0;
    o.decoder.sdo_timeout_ns = (mode & 32U) != 0 ? 1'000'000 : 1'000'000'000;
    std::size_t out_bytes = 0;
    std::size_t plain = size;
    {
        Dumper d(
            o, [&](std::string_view s) { out_bytes += s.size(); },
            [&](std::string_view s) { out_bytes += s.size(); });
        auto in = BufferedInput::from_memory(
            std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
        // A gzip input inflates first, and a BLF file's containers inflate again.
        plain = in->max_plain_bytes(size) * kMaxInflateRatio;
        (void)dump_input(*in, "fuzz", d);
        d.finish();
    }
    // Output is bounded by the input: a few hundred bytes per frame at most.
    if (out_bytes > 4096 + plain * 1024) {
        __builtin_trap();
    }
    return 0;
}
