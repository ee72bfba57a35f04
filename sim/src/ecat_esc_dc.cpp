// SPDX-License-Identifier: Apache-2.0
// The simulated ESC's DC registers (ETG.1000.4 §9.1, ET1100 datasheet 0x0900..0x0935): receive
// time latches, system time, the distributed reference time as drift control input, SYNC0 state.
#include <codrive/sim/ecat/esc_slave.hpp>

#include <codrive/core/endian.hpp>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

std::uint64_t EscSlave::local_time(TimePoint now) const {
    return dc_clock_.local_time(now);
}

std::uint64_t EscSlave::system_time(TimePoint now) const {
    return local_time(now) + get_le<std::uint64_t>(mem_.data() + reg::kDcSystemTimeOffset) +
           static_cast<std::uint64_t>(dc_clock_.correction(now));
}

std::int32_t EscSlave::system_time_difference() const {
    return dc_difference::decode(get_le<std::uint32_t>(mem_.data() + reg::kDcSystemTimeDifference));
}

bool EscSlave::sync0_active() const {
    return (mem_[reg::kDcActivation] & 0x03) == 0x03 &&
           get_le<std::uint32_t>(mem_.data() + reg::kDcSync0CycleTime) != 0;
}

void EscSlave::refresh_dc(TimePoint now) {
    put_le<std::uint64_t>(mem_.data() + reg::kDcSystemTime, system_time(now));
}

void EscSlave::on_system_time_write(std::span<const std::uint8_t> data, TimePoint now) {
    // Drift control input: the reference clock's system time distributed by ARMW/FRMW
    // (ETG.1000.4 §9.1.3), plus this slave's propagation delay (0x0928), against its own copy.
    // A 4-byte write carries the low 32 bits (32-bit system time, ETG.1000.4 §9.1.1).
    const auto delay = get_le<std::uint32_t>(mem_.data() + reg::kDcSystemTimeDelay);
    const std::uint64_t own = system_time(now);
    std::int64_t error = 0;
    if (data.size() == 8) {
        error = static_cast<std::int64_t>(own - (get_le<std::uint64_t>(data.data()) + delay));
    } else {
        error = static_cast<std::int32_t>(static_cast<std::uint32_t>(own) -
                                          (get_le<std::uint32_t>(data.data()) + delay));
    }
    const std::int64_t mean =
        dc_clock_.on_difference(now, error, mem_[reg::kDcSystemTimeDifferenceFilterDepth] & 0x0FU);
    put_le<std::uint32_t>(mem_.data() + reg::kDcSystemTimeDifference, dc_difference::encode(mean));
}

void EscSlave::latch_receive_times(const ChainContext& ctx) {
    const std::uint64_t t = local_time(ctx.now);
    const auto pos = static_cast<std::int64_t>(ctx.position);
    const auto n = static_cast<std::int64_t>(ctx.chain_length);
    const std::uint64_t port0 = t + static_cast<std::uint64_t>(pos * kDcHopNs);
    const std::uint64_t port1 = t + static_cast<std::uint64_t>((2 * n - 1 - pos) * kDcHopNs);
    put_le<std::uint32_t>(mem_.data() + reg::kDcReceiveTimePort0,
                          static_cast<std::uint32_t>(port0));
    put_le<std::uint32_t>(mem_.data() + reg::kDcReceiveTimePort0 + 4,
                          static_cast<std::uint32_t>(port1));
    put_le<std::uint64_t>(mem_.data() + reg::kDcReceiveTimeLocal, port0);
}

} // namespace codrive::sim::ecat
