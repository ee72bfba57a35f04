// SPDX-License-Identifier: Apache-2.0
// The capture-file constants the pcap/pcapng reader and writer share: file magics, pcapng block
// types (IETF draft-ietf-opsawg-pcapng) and the SocketCAN frame layout (linux/can.h).
#pragma once

#include <cstddef>
#include <cstdint>

namespace codrive::dump::pcap_format {

inline constexpr std::uint32_t kPcapMagicUs = 0xA1B2C3D4; ///< classic pcap, microseconds
inline constexpr std::uint32_t kPcapMagicNs = 0xA1B23C4D; ///< classic pcap, nanoseconds
// pcapng: section header, interface description, simple and enhanced packet blocks.
inline constexpr std::uint32_t kNgShb = 0x0A0D0D0A;
inline constexpr std::uint32_t kNgIdb = 0x00000001;
inline constexpr std::uint32_t kNgSpb = 0x00000003;
inline constexpr std::uint32_t kNgEpb = 0x00000006;
inline constexpr std::uint32_t kNgByteOrder = 0x1A2B3C4D;

// linux/can.h: CAN_EFF_FLAG, CAN_RTR_FLAG, CAN_ERR_FLAG in can_id; canfd_frame.flags CANFD_BRS
// 0x01, CANFD_ESI 0x02, CANFD_FDF 0x04; CAN_MTU and CANFD_MTU.
inline constexpr std::uint32_t kCanEff = 0x80000000U;
inline constexpr std::uint32_t kCanRtr = 0x40000000U;
inline constexpr std::uint32_t kCanErr = 0x20000000U;
inline constexpr std::uint8_t kCanFdBrs = 0x01;
inline constexpr std::uint8_t kCanFdFdf = 0x04;
inline constexpr std::uint8_t kCanFdDefinedFlags = 0x07;
inline constexpr std::size_t kCanMtu = 16;
inline constexpr std::size_t kCanFdMtu = 72;

} // namespace codrive::dump::pcap_format
