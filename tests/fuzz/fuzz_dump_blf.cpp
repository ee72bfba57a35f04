// SPDX-License-Identifier: Apache-2.0
// Fuzzes codrive-dump's Vector BLF reader. The first byte picks what the rest is: 0..0x7F a whole
// file; otherwise the object stream inside the containers, which the harness wraps in a valid
// file header and containers (stored, or zlib-compressed when bit 0 is set; container size from
// the low bits), so the fuzzer reaches the object decoding behind the zlib layer. The reader must
// end (End or Fatal), never crash or hang, and say why it skipped an object.
#include <codrive/dump/blf_reader.hpp>

#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace {

void put(std::string& s, std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) {
        s += static_cast<char>((v >> (8 * i)) & 0xFF);
    }
}

std::string wrap(std::uint8_t mode, std::string_view stream) {
    std::string f = "LOGG";
    put(f, 144, 4);
    f.resize(40, '\0');
    put(f, 2026, 2); // measurement start 2026-11-24 (the day of week is not read)
    put(f, 11, 2);
    put(f, 0, 2);
    put(f, 24, 2);
    f.resize(144, '\0');
    const bool compress = (mode & 1) != 0;
    const std::size_t chunk = 16U + 8U * (mode & 0x3E);
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
        const auto part = stream.substr(at, chunk);
        std::string body(part);
        if (compress) {
            uLongf n = compressBound(static_cast<uLong>(part.size()));
            body.resize(n);
            if (compress2(reinterpret_cast<Bytef*>(body.data()), &n,
                          reinterpret_cast<const Bytef*>(part.data()),
                          static_cast<uLong>(part.size()), Z_BEST_SPEED) != Z_OK) {
                return f;
            }
            body.resize(n);
        }
        f += "LOBJ";
        put(f, 16, 2);
        put(f, 1, 2);
        put(f, static_cast<std::uint32_t>(32 + body.size()), 4);
        put(f, 10, 4);
        put(f, compress ? 2 : 0, 2);
        put(f, 0, 6);
        put(f, static_cast<std::uint32_t>(part.size()), 4);
        put(f, 0, 4);
        f += body;
        f.resize((f.size() + 3) / 4 * 4, '\0');
    }
    return f;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace codrive::dump;
    if (size == 0) {
        return 0;
    }
    const std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
    const std::string file = data[0] < 0x80 ? std::string(rest) : wrap(data[0], rest);
    auto in = BufferedInput::from_memory(file);
    BlfReader reader(*in);
    TraceRecord r;
    // Every step consumes at least one object header, so steps are bounded by the size
    // (inflated, for a gzip file).
    // BLF containers are zlib streams too, so inflated bytes may inflate again.
    const std::size_t max_steps = in->max_plain_bytes(file.size()) * kMaxInflateRatio + 2;
    for (std::size_t steps = 0;; ++steps) {
        if (steps > max_steps) {
            __builtin_trap();
        }
        const auto status = reader.next(r);
        if (status == ReadStatus::End || status == ReadStatus::Fatal) {
            if (status == ReadStatus::Fatal && reader.error().empty()) {
                __builtin_trap(); // a corrupt file must say why
            }
            break;
        }
        if (status == ReadStatus::Malformed) {
            if (reader.error().empty()) {
                __builtin_trap();
            }
            continue;
        }
        if (r.frame.len > (r.frame.fd() ? 64 : 8) || !r.has_ts) {
            __builtin_trap();
        }
    }
    return 0;
}
