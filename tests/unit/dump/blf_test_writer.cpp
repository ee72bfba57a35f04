// SPDX-License-Identifier: Apache-2.0
// Test-only Vector BLF writer (the reader's layout, written independently of it, with zlib).
#include "blf_test_writer.hpp"

#include <zlib.h>

#include <algorithm>
#include <stdexcept>

namespace codrive::dump::testing {
namespace {

void put16(std::string& s, std::uint32_t v) {
    s += static_cast<char>(v & 0xFF);
    s += static_cast<char>((v >> 8) & 0xFF);
}
void put32(std::string& s, std::uint32_t v) {
    put16(s, v & 0xFFFF);
    put16(s, v >> 16);
}
void put64(std::string& s, std::uint64_t v) {
    put32(s, static_cast<std::uint32_t>(v));
    put32(s, static_cast<std::uint32_t>(v >> 32));
}
void pad4(std::string& s) {
    while (s.size() % 4 != 0) {
        s += '\0';
    }
}

// Civil date of a day count since 1970-01-01 (proleptic Gregorian).
void civil_from_days(std::int64_t z, std::int64_t& y, unsigned& m, unsigned& d) {
    z += 719468;
    const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const auto doe = static_cast<unsigned>(z - era * 146097);
    const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const unsigned mp = (5 * doy + 2) / 153;
    d = doy - (153 * mp + 2) / 5 + 1;
    m = mp < 10 ? mp + 3 : mp - 9;
    y = static_cast<std::int64_t>(yoe) + era * 400 + (m <= 2 ? 1 : 0);
}

std::string id_field(const Frame& f) {
    std::string s;
    put32(s, f.extended() ? (f.id | 0x80000000U) : f.id);
    return s;
}

} // namespace

std::string blf_object(std::uint32_t type, const std::string& payload, std::uint64_t timestamp,
                       std::uint32_t flags, std::uint16_t header_version) {
    const std::uint32_t header_size = header_version == 2 ? 40 : 32;
    std::string s = "LOBJ";
    put16(s, header_size);
    put16(s, header_version);
    put32(s, header_size + static_cast<std::uint32_t>(payload.size()));
    put32(s, type);
    put32(s, flags);
    if (header_version == 2) {
        s += '\0'; // timestamp status
        s += '\0';
        put16(s, 0); // object version
        put64(s, timestamp);
        put64(s, 0); // original timestamp
    } else {
        put16(s, 0); // client index
        put16(s, 0); // object version
        put64(s, timestamp);
    }
    return s + payload;
}

std::string blf_object(BlfObjectType type, const std::string& payload, std::uint64_t timestamp,
                       std::uint32_t flags, std::uint16_t header_version) {
    return blf_object(static_cast<std::uint32_t>(type), payload, timestamp, flags, header_version);
}

std::string blf_event_object(const BlfEvent& e, std::int64_t start_ns, const BlfWriteOptions& o) {
    const auto rel = static_cast<std::uint64_t>(e.ts_ns - start_ns);
    const std::uint64_t ts = o.ten_micros ? rel / 10'000 : rel;
    const std::uint32_t flags = o.ten_micros ? 1 : 2;
    const Frame& f = e.frame;
    std::string p;
    const auto data = [&](std::size_t n) {
        std::string d(n, '\0');
        std::copy_n(f.data.begin(), std::min<std::size_t>(f.len, n), d.begin());
        return d;
    };
    switch (e.type) {
    case BlfObjectType::CanMessage:
    case BlfObjectType::CanMessage2:
        put16(p, e.channel);
        p += static_cast<char>(f.rtr() ? 0x80 : 0x00);
        p += static_cast<char>(f.len);
        p += id_field(f);
        p += data(8);
        if (e.type == BlfObjectType::CanMessage2) {
            put32(p, 0); // frame length in ns
            p += '\x6F'; // bit count
            p += '\0';
            put16(p, 0);
        }
        break;
    case BlfObjectType::CanFdMessage:
        put16(p, e.channel);
        p += static_cast<char>(f.rtr() ? 0x80 : 0x00);
        p += static_cast<char>(f.fd() ? fd_len_to_dlc(f.len) : f.len);
        p += id_field(f);
        put32(p, 0); // frame length
        p += '\0';   // bit count
        p += static_cast<char>((f.fd() ? 0x01 : 0) | ((f.flags & Frame::kBrs) != 0 ? 0x02 : 0));
        p += static_cast<char>(f.rtr() ? 0 : f.len);
        p += std::string(5, '\0');
        p += data(64);
        break;
    case BlfObjectType::CanFdMessage64: {
        p += static_cast<char>(e.channel);
        p += static_cast<char>(f.fd() ? fd_len_to_dlc(f.len) : f.len);
        p += static_cast<char>(f.rtr() ? 0 : f.len);
        p += '\0'; // tx count
        p += id_field(f);
        put32(p, 0); // frame length
        std::uint32_t fl = f.rtr() ? 0x0010 : 0;
        fl |= f.fd() ? 0x1000U : 0U;
        fl |= (f.flags & Frame::kBrs) != 0 ? 0x2000U : 0U;
        put32(p, fl);
        put32(p, 0); // bit timing arbitration
        put32(p, 0); // bit timing data
        put32(p, 0); // BRS offset
        put32(p, 0); // CRC delimiter offset
        put16(p, 0); // bit count
        p += '\0';   // direction
        p += '\0';   // extended data offset
        put32(p, 0); // CRC
        p += f.rtr() ? std::string() : data(f.len);
        break;
    }
    case BlfObjectType::CanError:
    case BlfObjectType::CanErrorExt:
        put16(p, e.channel);
        put16(p, 0);
        put32(p, 0);
        p += std::string(24, '\0');
        break;
    case BlfObjectType::CanOverload:
        put16(p, e.channel);
        p += std::string(6, '\0');
        break;
    case BlfObjectType::CanDriverError:
    case BlfObjectType::CanDriverErrorExt:
        // Transmit and receive error counters from the SocketCAN error frame (data[6], data[7]).
        put16(p, e.channel);
        p += static_cast<char>(f.data[6]);
        p += static_cast<char>(f.data[7]);
        put32(p, 0); // error code
        if (e.type == BlfObjectType::CanDriverErrorExt) {
            p += std::string(24, '\0'); // flags, state, reserved
        }
        break;
    case BlfObjectType::CanFdError64:
        p += static_cast<char>(e.channel);
        p += std::string(79, '\0');
        break;
    case BlfObjectType::LogContainer:
        throw std::invalid_argument("not an event");
    }
    return blf_object(e.type, p, ts, flags, o.header_version);
}

std::string blf_file(std::int64_t start_ns, const std::string& stream, const BlfWriteOptions& o) {
    std::string f = "LOGG";
    put32(f, 144);
    f += std::string(8, '\0'); // application and binlog versions
    put64(f, 0);               // file size (not read)
    put64(f, stream.size());   // uncompressed size
    put32(f, 0);               // object count
    put32(f, 0);
    std::int64_t y = 1970;
    unsigned m = 1;
    unsigned d = 1;
    const std::int64_t day_ns = 86'400'000'000'000LL;
    civil_from_days(start_ns / day_ns, y, m, d);
    const std::int64_t in_day = start_ns % day_ns;
    put16(f, static_cast<std::uint32_t>(y));
    put16(f, m);
    put16(f, 0); // day of week (not read)
    put16(f, d);
    put16(f, static_cast<std::uint32_t>(in_day / 3'600'000'000'000LL));
    put16(f, static_cast<std::uint32_t>(in_day / 60'000'000'000LL % 60));
    put16(f, static_cast<std::uint32_t>(in_day / 1'000'000'000LL % 60));
    put16(f, static_cast<std::uint32_t>(in_day / 1'000'000LL % 1000));
    f += std::string(16, '\0'); // stop time
    f.resize(144, '\0');
    for (std::size_t at = 0; at < stream.size(); at += o.container_bytes) {
        const auto chunk = stream.substr(at, o.container_bytes);
        std::string body;
        if (o.compress) {
            uLongf n = compressBound(static_cast<uLong>(chunk.size()));
            body.resize(n);
            if (compress2(reinterpret_cast<Bytef*>(body.data()), &n,
                          reinterpret_cast<const Bytef*>(chunk.data()),
                          static_cast<uLong>(chunk.size()), Z_DEFAULT_COMPRESSION) != Z_OK) {
                throw std::runtime_error("zlib compress2 failed");
            }
            body.resize(n);
        } else {
            body = chunk;
        }
        std::string c = "LOBJ";
        put16(c, 16);
        put16(c, 1);
        put32(c, static_cast<std::uint32_t>(32 + body.size()));
        put32(c, static_cast<std::uint32_t>(BlfObjectType::LogContainer));
        put16(c, o.compress ? 2 : 0);
        c += std::string(6, '\0');
        put32(c, static_cast<std::uint32_t>(chunk.size()));
        c += std::string(4, '\0');
        c += body;
        pad4(c);
        f += c;
    }
    return f;
}

std::string blf_file(const std::vector<BlfEvent>& events, const BlfWriteOptions& o) {
    const std::int64_t start = events.empty() ? 0 : events.front().ts_ns / 1'000'000 * 1'000'000;
    std::string stream;
    for (const auto& e : events) {
        stream += blf_event_object(e, start, o);
        pad4(stream);
    }
    return blf_file(start, stream, o);
}

} // namespace codrive::dump::testing
