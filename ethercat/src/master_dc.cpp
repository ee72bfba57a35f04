// SPDX-License-Identifier: Apache-2.0
// Master distributed clocks: propagation delays, system time offsets, static and continuous drift
// compensation and SYNC0 activation (ETG.1000.4 §9.1, ET1100 datasheet §9 "Distributed Clocks").
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/registers.hpp>

#include <fmt/format.h>

namespace codrive::ethercat {

VoidResult Master::configure_dc() {
    dc_reference_.reset();
    std::vector<std::size_t> dc;
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        if (slaves_[i].has_dc) {
            dc.push_back(i);
        }
    }
    if (dc.empty()) {
        return {};
    }
    // A broadcast write to 0x0900 latches the port receive times in every slave.
    const std::uint64_t master_time = master_time_ns();
    std::array<Datagram, 1> latch{Datagram::physical(Command::Bwr, 0, reg::kDcReceiveTimePort0, 4)};
    if (auto e = exchange(latch); !e) {
        return e;
    }
    std::vector<Datagram> reads;
    for (std::size_t i : dc) {
        reads.push_back(Datagram::physical(Command::Fprd, slaves_[i].station_address,
                                           reg::kDcReceiveTimePort0, 8));
        reads.push_back(Datagram::physical(Command::Fprd, slaves_[i].station_address,
                                           reg::kDcReceiveTimeLocal, 8));
    }
    if (auto e = exchange(reads); !e) {
        return e;
    }
    const std::size_t ref = dc.front();
    const auto port_times = [&](std::size_t k) {
        const auto t0 = get_le<std::uint32_t>(reads[2 * k].data.data());
        const auto t1 = get_le<std::uint32_t>(reads[2 * k].data.data() + 4);
        return static_cast<std::int64_t>(static_cast<std::uint32_t>(t1 - t0));
    };
    const std::int64_t ref_loop = port_times(0);
    for (std::size_t k = 0; k < dc.size(); ++k) {
        if (reads[2 * k].wkc != 1 || reads[2 * k + 1].wkc != 1) {
            return set_error(
                make_error_code(EcatErrc::WorkingCounter),
                fmt::format("{}: reading the DC receive times failed", slave_label(dc[k])));
        }
        // Line topology: the frame needs (loop time of the reference - own loop time) / 2 to
        // get from the reference to this slave.
        const std::int64_t delay =
            k == 0 ? 0 : std::max<std::int64_t>(0, (ref_loop - port_times(k)) / 2);
        const auto local = get_le<std::uint64_t>(reads[2 * k + 1].data.data());
        const std::uint64_t offset = master_time + static_cast<std::uint64_t>(delay) - local;
        std::array<std::uint8_t, 12> b{};
        put_le<std::uint64_t>(b.data(), offset);
        put_le<std::uint32_t>(b.data() + 8, static_cast<std::uint32_t>(delay));
        if (auto w = write_registers(dc[k], reg::kDcSystemTimeOffset, b); !w) {
            return w;
        }
    }
    dc_reference_ = ref;
    // Static drift compensation: the reference clock's time distributed in a burst of frames
    // (ETG.1000.4 §9.1.3 recommends many; the slaves' control loops start settling with them).
    // The cyclic frame then goes on distributing it every cycle (dc_time_add()).
    for (int i = 0; i < 16; ++i) {
        if (auto e = distribute_system_time(); !e) {
            return e;
        }
    }
    return {};
}

namespace {
/// The drift compensation datagram (ETG.1000.4 §9.1.3, ETG.1020 distributed clocks): FRMW to
/// the reference clock's configured address on 0x0910, 64 bits. The reference clock puts its
/// system time into it, every DC slave behind it takes it as the input of its drift control
/// (and reports the mean difference in 0x092C).
constexpr Command kDcTimeCommand = Command::Frmw;
constexpr std::size_t kDcTimeSize = 8;
} // namespace

VoidResult Master::distribute_system_time() {
    if (!dc_reference_) {
        return set_error(make_error_code(EcatErrc::NotConfigured),
                         "distributed clocks are not configured (no reference clock)");
    }
    std::array<Datagram, 1> d{Datagram::physical(
        kDcTimeCommand, slaves_[*dc_reference_].station_address, reg::kDcSystemTime, kDcTimeSize)};
    return exchange(d);
}

void Master::dc_time_add() {
    // Right behind the LRW, in the same frame: no extra exchange, and the datagram's buffer is
    // reused from frame to frame (add_datagram keeps its capacity), so nothing is allocated.
    if (!dc_reference_ || !config_.continuous_drift_compensation ||
        frame_room() < kDatagramOverhead + kDcTimeSize) {
        return;
    }
    add_datagram(kDcTimeCommand, slaves_[*dc_reference_].station_address, reg::kDcSystemTime,
                 kDcTimeSize);
    ++stats_.dc_time_distributions;
}

Result<std::uint64_t> Master::read_system_time(std::size_t slave) {
    return read_register<std::uint64_t>(slave, reg::kDcSystemTime);
}

VoidResult Master::configure_sync0(std::size_t slave, Duration cycle, Duration shift) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    if (!slaves_[slave].has_dc) {
        return set_error(make_error_code(CoreErrc::NotSupported),
                         fmt::format("{}: the slave has no distributed clock", slave_label(slave)));
    }
    if (auto w = write_register<std::uint8_t>(slave, reg::kDcActivation, 0); !w) {
        return w;
    }
    auto now = read_system_time(slave);
    if (!now) {
        return fail(now.error());
    }
    const auto cyc = static_cast<std::uint64_t>(cycle.count());
    if (cyc == 0) {
        return set_error(make_error_code(CoreErrc::InvalidArgument), "SYNC0 cycle time is zero");
    }
    const std::uint64_t start =
        ((*now + 10'000'000) / cyc + 1) * cyc + static_cast<std::uint64_t>(shift.count());
    if (auto w = write_register<std::uint64_t>(slave, reg::kDcSyncStartTime, start); !w) {
        return w;
    }
    if (auto w = write_register<std::uint32_t>(slave, reg::kDcSync0CycleTime,
                                               static_cast<std::uint32_t>(cyc));
        !w) {
        return w;
    }
    return write_register<std::uint8_t>(slave, reg::kDcActivation, 0x03);
}

Result<std::vector<DcSlaveStatus>> Master::dc_status() {
    std::vector<std::size_t> dc;
    std::vector<Datagram> reads;
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        if (slaves_[i].has_dc) {
            dc.push_back(i);
            reads.push_back(Datagram::physical(Command::Fprd, slaves_[i].station_address,
                                               reg::kDcSystemTime, 8));
            reads.push_back(Datagram::physical(Command::Fprd, slaves_[i].station_address,
                                               reg::kDcSystemTimeDelay, 8));
        }
    }
    std::vector<DcSlaveStatus> out;
    if (dc.empty()) {
        return out;
    }
    if (auto e = exchange(reads); !e) {
        return fail(e.error());
    }
    const auto ref_time = get_le<std::uint64_t>(reads[0].data.data());
    for (std::size_t k = 0; k < dc.size(); ++k) {
        DcSlaveStatus s;
        s.position = static_cast<std::uint16_t>(dc[k]);
        s.system_time = get_le<std::uint64_t>(reads[2 * k].data.data());
        s.delay = get_le<std::uint32_t>(reads[2 * k + 1].data.data());
        s.difference =
            dc_difference::decode(get_le<std::uint32_t>(reads[2 * k + 1].data.data() + 4));
        s.offset_to_reference = static_cast<std::int64_t>(s.system_time - ref_time) -
                                static_cast<std::int64_t>(s.delay);
        out.push_back(s);
    }
    return out;
}

} // namespace codrive::ethercat
