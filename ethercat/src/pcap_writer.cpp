// SPDX-License-Identifier: Apache-2.0
// pcap writer: global header + per-record headers (pcap file format, LINKTYPE_ETHERNET = 1).
#include <codrive/ethercat/pcap_writer.hpp>

#include <codrive/core/endian.hpp>

#include <cerrno>
#include <chrono>

namespace codrive::ethercat {

PcapWriter::~PcapWriter() {
    close();
}

VoidResult PcapWriter::open(const std::string& path) {
    close();
    file_ = std::fopen(path.c_str(), "wb");
    if (file_ == nullptr) {
        return fail_errno(errno);
    }
    std::uint8_t h[24]{};
    put_le<std::uint32_t>(h, 0xA1B2C3D4);
    put_le<std::uint16_t>(h + 4, 2);
    put_le<std::uint16_t>(h + 6, 4);
    put_le<std::uint32_t>(h + 16, 65535);
    put_le<std::uint32_t>(h + 20, 1);
    if (std::fwrite(h, 1, sizeof(h), file_) != sizeof(h)) {
        return fail_errno(errno);
    }
    return {};
}

void PcapWriter::write(std::span<const std::uint8_t> frame) {
    if (file_ == nullptr) {
        return;
    }
    const auto us = std::chrono::duration_cast<std::chrono::microseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
    std::uint8_t h[16]{};
    put_le<std::uint32_t>(h, static_cast<std::uint32_t>(us / 1'000'000));
    put_le<std::uint32_t>(h + 4, static_cast<std::uint32_t>(us % 1'000'000));
    put_le<std::uint32_t>(h + 8, static_cast<std::uint32_t>(frame.size()));
    put_le<std::uint32_t>(h + 12, static_cast<std::uint32_t>(frame.size()));
    std::fwrite(h, 1, sizeof(h), file_);
    std::fwrite(frame.data(), 1, frame.size(), file_);
    ++frames_;
}

void PcapWriter::close() {
    if (file_ != nullptr) {
        std::fclose(file_);
        file_ = nullptr;
    }
}

} // namespace codrive::ethercat
