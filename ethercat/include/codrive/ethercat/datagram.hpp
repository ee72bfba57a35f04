// SPDX-License-Identifier: Apache-2.0
// EtherCAT frames and datagrams (ETG.1000.4 §5.3/§5.4): commands, codec, working-counter rules.
#pragma once

#include <codrive/core/error.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace codrive::ethercat {

/// Ethertype of EtherCAT frames (IEEE 802.3 assigned).
inline constexpr std::uint16_t kEthertype = 0x88A4;
inline constexpr std::size_t kEthernetHeaderSize = 14;
inline constexpr std::size_t kEcatHeaderSize = 2;
/// Datagram header (10 bytes) plus working counter (2 bytes).
inline constexpr std::size_t kDatagramOverhead = 12;
/// Largest Ethernet frame without FCS; the smallest one is padded to 60 bytes.
inline constexpr std::size_t kMaxFrameSize = 1514;
inline constexpr std::size_t kMinFrameSize = 60;
/// Room left for datagram data in one frame with a single datagram.
inline constexpr std::size_t kMaxDatagramData =
    kMaxFrameSize - kEthernetHeaderSize - kEcatHeaderSize - kDatagramOverhead;

using MacAddress = std::array<std::uint8_t, 6>;
inline constexpr MacAddress kBroadcastMac{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
/// The source address the master puts in its frames (locally administered, unicast).
inline constexpr MacAddress kMasterMac{0x02, 0x00, 0x00, 0xEC, 0xA7, 0x01};

/// Datagram commands (ETG.1000.4 Table 12).
enum class Command : std::uint8_t {
    Nop = 0,
    Aprd = 1,  ///< auto-increment physical read
    Apwr = 2,  ///< auto-increment physical write
    Aprw = 3,  ///< auto-increment physical read/write
    Fprd = 4,  ///< configured-address physical read
    Fpwr = 5,  ///< configured-address physical write
    Fprw = 6,  ///< configured-address physical read/write
    Brd = 7,   ///< broadcast read
    Bwr = 8,   ///< broadcast write
    Brw = 9,   ///< broadcast read/write
    Lrd = 10,  ///< logical read
    Lwr = 11,  ///< logical write
    Lrw = 12,  ///< logical read/write
    Armw = 13, ///< auto-increment read, multiple write
    Frmw = 14, ///< configured-address read, multiple write
};

/// "APRD", "LRW", ... ("?" for unknown values).
[[nodiscard]] std::string_view to_string(Command c);
[[nodiscard]] bool is_valid_command(std::uint8_t raw);

enum class Addressing : std::uint8_t { None, AutoIncrement, Configured, Broadcast, Logical };
[[nodiscard]] Addressing addressing_of(Command c);
[[nodiscard]] bool command_reads(Command c);  ///< the datagram returns data from slaves
[[nodiscard]] bool command_writes(Command c); ///< the datagram carries data to slaves

/// Working-counter increment by one slave (ETG.1000.4 §5.4.3): a successful read adds 1, a
/// successful write adds 1, a read/write adds 1 for the read and 2 for the write; ARMW/FRMW add
/// 1 (the reading slave reads, the others write).
[[nodiscard]] std::uint16_t wkc_increment(Command c, bool read_done, bool write_done);
/// The working counter a datagram must return when `slaves` slaves each perform the full
/// access (e.g. LRW to slaves with inputs and outputs: 3 each).
[[nodiscard]] std::uint16_t expected_wkc(Command c, std::uint16_t slaves);

/// One datagram as the master builds it and receives it back.
struct Datagram {
    Command command = Command::Nop;
    std::uint8_t index = 0;
    std::uint32_t address = 0; ///< ADP (low 16 bits) + ADO (high 16 bits), or logical address
    std::vector<std::uint8_t> data;
    std::uint16_t irq = 0;
    std::uint16_t wkc = 0;
    bool circulated = false; ///< C bit: the frame has circulated (ETG.1000.4 §5.4.1.2)

    /// Physical-addressed datagram: position/station `adp`, register `ado`.
    static Datagram physical(Command c, std::uint16_t adp, std::uint16_t ado, std::size_t size);
    static Datagram physical(Command c, std::uint16_t adp, std::uint16_t ado,
                             std::span<const std::uint8_t> payload);
    static Datagram logical(Command c, std::uint32_t logical_address, std::size_t size);

    [[nodiscard]] std::uint16_t adp() const { return static_cast<std::uint16_t>(address); }
    [[nodiscard]] std::uint16_t ado() const { return static_cast<std::uint16_t>(address >> 16); }
    /// Wire size of this datagram (header + data + WKC).
    [[nodiscard]] std::size_t wire_size() const { return kDatagramOverhead + data.size(); }
};

/// Bytes one frame needs for these datagrams (Ethernet header included, before padding).
[[nodiscard]] std::size_t frame_size(std::span<const Datagram> datagrams);

/// Encodes an Ethernet frame (broadcast destination, `source` MAC, ethertype 88A4h, EtherCAT
/// header, datagrams with the M bit on all but the last, padding to 60 bytes) into `out`.
/// Returns the frame length. Errors: FrameTooLarge, InvalidArgument (no datagram, or `out` too
/// small).
Result<std::size_t> encode_frame(std::span<const Datagram> datagrams, std::span<std::uint8_t> out,
                                 const MacAddress& source = kMasterMac);
/// As above into a new vector.
Result<std::vector<std::uint8_t>> encode_frame(std::span<const Datagram> datagrams,
                                               const MacAddress& source = kMasterMac);

/// Decodes every datagram of a received Ethernet frame. Errors: InvalidFrame (not 88A4h, wrong
/// EtherCAT type, lengths past the end, unknown command).
Result<std::vector<Datagram>> decode_frame(std::span<const std::uint8_t> frame);

/// Copies data, WKC and IRQ of a received frame into the datagrams it answers, checking that it
/// carries the same number of datagrams with the same commands, indexes and sizes. Errors:
/// InvalidFrame (malformed), ProtocolError (a different frame), without touching `datagrams`.
VoidResult decode_frame_into(std::span<const std::uint8_t> frame, std::span<Datagram> datagrams);

/// A datagram inside a frame buffer, processed in place (the slave-side view: an ESC reads and
/// writes the data and increments the WKC as the frame passes).
struct DatagramRef {
    Command command = Command::Nop;
    std::uint8_t index = 0;
    std::uint8_t* header = nullptr; ///< start of the 10-byte header
    std::span<std::uint8_t> data;
    [[nodiscard]] std::uint32_t address() const;
    void set_address(std::uint32_t a) const;
    [[nodiscard]] std::uint16_t adp() const { return static_cast<std::uint16_t>(address()); }
    [[nodiscard]] std::uint16_t ado() const { return static_cast<std::uint16_t>(address() >> 16); }
    void set_adp(std::uint16_t adp) const;
    [[nodiscard]] std::uint16_t wkc() const;
    void set_wkc(std::uint16_t wkc) const;
};

/// Walks the datagrams of an Ethernet frame in place. Errors: InvalidFrame (nothing is visited
/// if the frame is malformed).
VoidResult for_each_datagram(std::span<std::uint8_t> frame,
                             const std::function<void(DatagramRef&)>& visit);

/// The first datagram's index of a frame (frames are matched by it), or nullopt if malformed.
[[nodiscard]] std::optional<std::uint8_t> frame_index(std::span<const std::uint8_t> frame);

} // namespace codrive::ethercat
