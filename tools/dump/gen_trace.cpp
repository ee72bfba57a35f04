// SPDX-License-Identifier: Apache-2.0
// codrive-gen-trace: writes a synthetic CANopen candump log (a CiA 402 line of drives in cyclic
// synchronous position mode) for benchmarks: configuration by SDO, then SYNC, PDOs, heartbeats,
// periodic SDO reads (expedited and segmented) and the odd EMCY.
#include <fmt/format.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace {

struct Out {
    std::string buf;
    std::int64_t ts_us = 1'700'000'000'000'000;
    std::uint64_t frames = 0;
    void frame(std::uint32_t id, std::initializer_list<std::uint8_t> data) {
        fmt::format_to(std::back_inserter(buf), "({}.{:06}) can0 {:03X}#", ts_us / 1'000'000,
                       ts_us % 1'000'000, id);
        for (auto b : data) {
            fmt::format_to(std::back_inserter(buf), "{:02X}", b);
        }
        buf.push_back('\n');
        ++frames;
        if (buf.size() > (1U << 20)) {
            flush();
        }
    }
    void flush() {
        std::fwrite(buf.data(), 1, buf.size(), stdout);
        buf.clear();
    }
};

std::uint8_t b(std::uint32_t v, int i) {
    return static_cast<std::uint8_t>(v >> (8 * i));
}

// An expedited SDO download request and its response.
void sdo_write(Out& o, unsigned node, std::uint16_t idx, std::uint8_t sub, std::uint32_t v,
               unsigned len) {
    const auto cs = static_cast<std::uint8_t>(0x23 | ((4 - len) << 2));
    o.frame(0x600 + node, {cs, b(idx, 0), b(idx, 1), sub, b(v, 0), b(v, 1), b(v, 2), b(v, 3)});
    o.ts_us += 300;
    o.frame(0x580 + node, {0x60, b(idx, 0), b(idx, 1), sub, 0, 0, 0, 0});
    o.ts_us += 200;
}

} // namespace

int main(int argc, char** argv) {
    const std::uint64_t want = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1'000'000;
    constexpr unsigned kNodes = 4;
    Out o;
    // Configure TPDO1 = statusword + position actual, RPDO1 = controlword + target position.
    for (unsigned n = 1; n <= kNodes; ++n) {
        sdo_write(o, n, 0x1A00, 0, 0, 1);
        sdo_write(o, n, 0x1A00, 1, 0x60410010, 4);
        sdo_write(o, n, 0x1A00, 2, 0x60640020, 4);
        sdo_write(o, n, 0x1A00, 0, 2, 1);
        sdo_write(o, n, 0x1600, 0, 0, 1);
        sdo_write(o, n, 0x1600, 1, 0x60400010, 4);
        sdo_write(o, n, 0x1600, 2, 0x607A0020, 4);
        sdo_write(o, n, 0x1600, 0, 2, 1);
        o.frame(0x000, {0x01, static_cast<std::uint8_t>(n)});
    }
    std::uint32_t cycle = 0;
    const char name[] = "AKD2G-S-DUAL";
    while (o.frames < want) {
        ++cycle;
        o.frame(0x080, {});
        o.ts_us += 50;
        for (unsigned n = 1; n <= kNodes; ++n) {
            const std::uint32_t pos = cycle * 10 + n;
            o.frame(0x200 + n, {0x0F, 0x00, b(pos, 0), b(pos, 1), b(pos, 2), b(pos, 3)});
            o.ts_us += 120;
            o.frame(0x180 + n, {0x37, 0x06, b(pos, 0), b(pos, 1), b(pos, 2), b(pos, 3)});
            o.ts_us += 120;
        }
        if (cycle % 100 == 0) {
            for (unsigned n = 1; n <= kNodes; ++n) {
                o.frame(0x700 + n, {0x05});
                o.ts_us += 120;
            }
        }
        if (cycle % 50 == 0) {
            // Segmented upload of 1008h (12 bytes in two segments).
            const unsigned n = 1 + cycle / 50 % kNodes;
            o.frame(0x600 + n, {0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0});
            o.ts_us += 150;
            o.frame(0x580 + n, {0x41, 0x08, 0x10, 0x00, 12, 0, 0, 0});
            o.ts_us += 150;
            o.frame(0x600 + n, {0x60, 0, 0, 0, 0, 0, 0, 0});
            o.ts_us += 150;
            auto c = [&](int i) { return static_cast<std::uint8_t>(name[i]); };
            o.frame(0x580 + n, {0x00, c(0), c(1), c(2), c(3), c(4), c(5), c(6)});
            o.ts_us += 150;
            o.frame(0x600 + n, {0x70, 0, 0, 0, 0, 0, 0, 0});
            o.ts_us += 150;
            o.frame(0x580 + n, {0x1B, c(7), c(8), c(9), c(10), c(11), 0, 0});
            o.ts_us += 150;
            o.frame(0x600 + n, {0x40, 0x41, 0x60, 0x00, 0, 0, 0, 0});
            o.ts_us += 150;
            o.frame(0x580 + n, {0x4B, 0x41, 0x60, 0x00, 0x37, 0x06, 0, 0});
            o.ts_us += 150;
        }
        if (cycle % 5000 == 0) {
            o.frame(0x080 + 2, {0x10, 0x23, 0x03, 0, 1, 2, 3, 4});
            o.frame(0x080 + 2, {0, 0, 0, 0, 0, 0, 0, 0});
        }
        o.ts_us += 1000;
    }
    o.flush();
    std::fprintf(stderr, "codrive-gen-trace: %llu frames\n",
                 static_cast<unsigned long long>(o.frames));
    return 0;
}
