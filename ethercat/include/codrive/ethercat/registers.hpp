// SPDX-License-Identifier: Apache-2.0
// EtherCAT slave controller (ESC) registers (ETG.1000.4 §6, ET1100 datasheet register map):
// addresses and the sync manager / FMMU records shared by the master and the simulated slaves.
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace codrive::ethercat {

namespace reg {
inline constexpr std::uint16_t kType = 0x0000;
inline constexpr std::uint16_t kRevision = 0x0001;
inline constexpr std::uint16_t kBuild = 0x0002;
inline constexpr std::uint16_t kFmmuCount = 0x0004;
inline constexpr std::uint16_t kSmCount = 0x0005;
inline constexpr std::uint16_t kRamSize = 0x0006;
inline constexpr std::uint16_t kPortDescriptor = 0x0007;
inline constexpr std::uint16_t kFeatures = 0x0008; ///< bit 2: distributed clocks available
inline constexpr std::uint16_t kStationAddress = 0x0010;
inline constexpr std::uint16_t kStationAlias = 0x0012;
inline constexpr std::uint16_t kDlControl = 0x0100;
inline constexpr std::uint16_t kDlStatus = 0x0110;
inline constexpr std::uint16_t kAlControl = 0x0120;
inline constexpr std::uint16_t kAlStatus = 0x0130;
inline constexpr std::uint16_t kAlStatusCode = 0x0134;
inline constexpr std::uint16_t kWatchdogDivider = 0x0400;
inline constexpr std::uint16_t kWatchdogPdi = 0x0410;
inline constexpr std::uint16_t kWatchdogProcessData = 0x0420;
inline constexpr std::uint16_t kSiiConfig = 0x0500;
inline constexpr std::uint16_t kSiiControl = 0x0502;
inline constexpr std::uint16_t kSiiAddress = 0x0504;
inline constexpr std::uint16_t kSiiData = 0x0508;
inline constexpr std::uint16_t kFmmu0 = 0x0600;
inline constexpr std::uint16_t kSm0 = 0x0800;
inline constexpr std::uint16_t kDcReceiveTimePort0 = 0x0900;
inline constexpr std::uint16_t kDcSystemTime = 0x0910;
inline constexpr std::uint16_t kDcReceiveTimeLocal = 0x0918; ///< ECAT processing unit time
inline constexpr std::uint16_t kDcSystemTimeOffset = 0x0920;
inline constexpr std::uint16_t kDcSystemTimeDelay = 0x0928;
inline constexpr std::uint16_t kDcSystemTimeDifference = 0x092C;
inline constexpr std::uint16_t kDcSpeedCounterStart = 0x0930;
inline constexpr std::uint16_t kDcSpeedCounterDiff = 0x0932;
inline constexpr std::uint16_t kDcSystemTimeDifferenceFilterDepth = 0x0934;
inline constexpr std::uint16_t kDcSpeedCounterFilterDepth = 0x0935;
inline constexpr std::uint16_t kDcCyclicUnitControl = 0x0980;
inline constexpr std::uint16_t kDcActivation = 0x0981; ///< bit 0 cyclic op, bit 1 SYNC0
inline constexpr std::uint16_t kDcSyncStartTime = 0x0990;
inline constexpr std::uint16_t kDcSync0CycleTime = 0x09A0;
inline constexpr std::uint16_t kDcSync1CycleTime = 0x09A4;
/// First byte of process memory (mailboxes and process data buffers live above this).
inline constexpr std::uint16_t kProcessRam = 0x1000;

[[nodiscard]] constexpr std::uint16_t fmmu(unsigned n) {
    return static_cast<std::uint16_t>(kFmmu0 + 16 * n);
}
[[nodiscard]] constexpr std::uint16_t sm(unsigned n) {
    return static_cast<std::uint16_t>(kSm0 + 8 * n);
}
} // namespace reg

/// DL status (0x0110) bits (ETG.1000.4 §6.1.4, ET1100 datasheet register 0x0110): link and
/// loop state per port, which masters read for the topology (open ports with communication).
namespace dl_status {
inline constexpr std::uint16_t kPdiOperational = 1U << 0; ///< EEPROM loaded, PDI up
inline constexpr std::uint16_t kPdiWatchdogOk = 1U << 1;  ///< PDI watchdog not expired
/// Physical link on `port` (0..3).
[[nodiscard]] constexpr std::uint16_t link(unsigned port) {
    return static_cast<std::uint16_t>(1U << (4 + port));
}
/// Loop closed on `port` (the frame turns back there; 0 = open).
[[nodiscard]] constexpr std::uint16_t loop_closed(unsigned port) {
    return static_cast<std::uint16_t>(1U << (8 + 2 * port));
}
/// Communication established on `port`.
[[nodiscard]] constexpr std::uint16_t communication(unsigned port) {
    return static_cast<std::uint16_t>(1U << (9 + 2 * port));
}
} // namespace dl_status

/// 0x092C system time difference (ET1100 datasheet, register 0x092C): sign and magnitude, not
/// two's complement. Bits 30:0 the mean of |local copy of the system time - received system
/// time| (ns), bit 31 set when the local copy is smaller. Saturates at 2^31 - 1 ns.
namespace dc_difference {
[[nodiscard]] constexpr std::uint32_t encode(std::int64_t local_minus_received) {
    const bool behind = local_minus_received < 0;
    const std::uint64_t mag = behind ? 0ULL - static_cast<std::uint64_t>(local_minus_received)
                                     : static_cast<std::uint64_t>(local_minus_received);
    const std::uint32_t m = mag > 0x7FFFFFFFULL ? 0x7FFFFFFFU : static_cast<std::uint32_t>(mag);
    return behind ? (m | 0x80000000U) : m;
}
/// Local copy minus received time (ns): positive when the slave's clock is ahead.
[[nodiscard]] constexpr std::int32_t decode(std::uint32_t raw) {
    const auto m = static_cast<std::int32_t>(raw & 0x7FFFFFFFU);
    return (raw & 0x80000000U) != 0 ? -m : m;
}
} // namespace dc_difference

/// SII interface control/status (0x0502) bits.
namespace sii_ctl {
inline constexpr std::uint16_t kReadSize8 = 1U << 6; ///< 1: the ESC reads 8 bytes per access
inline constexpr std::uint16_t kRead = 1U << 8;
inline constexpr std::uint16_t kWrite = 1U << 9;
inline constexpr std::uint16_t kReload = 1U << 10;
inline constexpr std::uint16_t kChecksumError = 1U << 11;
inline constexpr std::uint16_t kDeviceInfoError = 1U << 12;
inline constexpr std::uint16_t kCommandError = 1U << 13;
inline constexpr std::uint16_t kWriteError = 1U << 14;
inline constexpr std::uint16_t kBusy = 1U << 15;
inline constexpr std::uint16_t kErrorMask = kChecksumError | kDeviceInfoError | kCommandError;
} // namespace sii_ctl

/// One sync manager channel (8 bytes at 0x0800 + 8n).
struct SyncManager {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;  ///< bits 1..0 mode (2 = mailbox, 0 = 3-buffer), bits 3..2 dir
    std::uint8_t status = 0;   ///< bit 3: mailbox full
    std::uint8_t activate = 0; ///< bit 0: enable
    std::uint8_t pdi_control = 0;

    static constexpr std::uint8_t kModeMailbox = 0x02;
    static constexpr std::uint8_t kDirWrite = 0x04; ///< ECAT writes (master → slave)
    static constexpr std::uint8_t kInterruptEcat = 0x08;
    static constexpr std::uint8_t kInterruptPdi = 0x10;
    static constexpr std::uint8_t kWatchdog = 0x40;
    static constexpr std::uint8_t kStatusMailboxFull = 0x08;
    /// Mailbox repeat (ETG.1000.4 §6.7.2): the master toggles the repeat request in the activate
    /// register (+6); the slave writes its last message into the buffer again and copies the
    /// toggle into the repeat acknowledge of the PDI control register (+7).
    static constexpr std::uint8_t kActivateRepeatRequest = 0x02;
    static constexpr std::uint8_t kPdiRepeatAck = 0x02;
    static constexpr std::uint8_t kActivateEnable = 0x01; ///< the master's own activate value
    /// The activate byte that asks for a repeat, from the byte just read: the repeat request
    /// toggled, everything else as the master configured it (enabled, no latch bits). Only the
    /// repeat bit is taken from the read, so a corrupted read cannot switch the SM off (a
    /// disabled SM1 reads as plain memory: the same message, working counter 1, every time).
    [[nodiscard]] static constexpr std::uint8_t repeat_request_after(std::uint8_t read) {
        return static_cast<std::uint8_t>(
            kActivateEnable | ((read & kActivateRepeatRequest) ^ kActivateRepeatRequest));
    }
    static constexpr std::uint16_t kActivateOffset = 6;
    static constexpr std::uint16_t kPdiControlOffset = 7;

    [[nodiscard]] bool enabled() const { return (activate & 0x01) != 0; }
    [[nodiscard]] bool is_mailbox() const { return (control & 0x03) == kModeMailbox; }
    [[nodiscard]] bool master_writes() const { return (control & 0x0C) == kDirWrite; }

    [[nodiscard]] std::array<std::uint8_t, 8> encode() const;
    static SyncManager decode(std::span<const std::uint8_t> bytes); ///< needs 8 bytes
};

/// One FMMU (16 bytes at 0x0600 + 16n): maps a logical range onto physical memory.
struct Fmmu {
    std::uint32_t logical_start = 0;
    std::uint16_t length = 0;
    std::uint8_t logical_start_bit = 0;
    std::uint8_t logical_end_bit = 7;
    std::uint16_t physical_start = 0;
    std::uint8_t physical_start_bit = 0;
    std::uint8_t type = 0; ///< bit 0 read (slave → master), bit 1 write (master → slave)
    std::uint8_t activate = 0;

    static constexpr std::uint8_t kRead = 0x01;
    static constexpr std::uint8_t kWrite = 0x02;

    [[nodiscard]] std::array<std::uint8_t, 16> encode() const;
    static Fmmu decode(std::span<const std::uint8_t> bytes); ///< needs 16 bytes
};

} // namespace codrive::ethercat
