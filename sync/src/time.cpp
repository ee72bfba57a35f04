// SPDX-License-Identifier: Apache-2.0
// TIME_OF_DAY codec, producer and consumer (CiA 301 §7.2.6).
#include <codrive/core/endian.hpp>
#include <codrive/sync/time.hpp>

#include <fmt/format.h>

namespace codrive::sync {

namespace {
using namespace std::chrono;
constexpr sys_days kEpoch1984 = sys_days{year{1984} / January / 1};
} // namespace

std::array<std::uint8_t, kTimeOfDayLen> encode(const TimeOfDay& t) {
    std::array<std::uint8_t, kTimeOfDayLen> out{};
    put_le<std::uint32_t>(out.data(), t.ms_after_midnight & 0x0FFF'FFFFU);
    put_le<std::uint16_t>(out.data() + 4, t.days_since_1984);
    return out;
}

Result<TimeOfDay> decode_time_of_day(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < kTimeOfDayLen) {
        return fail(CoreErrc::InvalidFrame);
    }
    TimeOfDay t;
    t.ms_after_midnight = get_le<std::uint32_t>(bytes.data()) & 0x0FFF'FFFFU;
    t.days_since_1984 = get_le<std::uint16_t>(bytes.data() + 4);
    if (t.ms_after_midnight >= kMsPerDay) {
        return fail(CoreErrc::InvalidFrame);
    }
    return t;
}

Result<TimeOfDay> to_time_of_day(system_clock::time_point t) {
    const auto ms = time_point_cast<milliseconds>(t);
    const auto day = floor<days>(ms);
    const auto since = (day - kEpoch1984).count();
    if (since < 0 || since > 0xFFFF) {
        return fail(CoreErrc::OutOfRange);
    }
    TimeOfDay out;
    out.days_since_1984 = static_cast<std::uint16_t>(since);
    out.ms_after_midnight = static_cast<std::uint32_t>((ms - day).count());
    return out;
}

system_clock::time_point to_system_time(const TimeOfDay& t) {
    return system_clock::time_point{kEpoch1984.time_since_epoch()} + days{t.days_since_1984} +
           milliseconds{t.ms_after_midnight};
}

std::string to_string(const TimeOfDay& t) {
    const sys_days day = kEpoch1984 + days{t.days_since_1984};
    const year_month_day ymd{day};
    const std::uint32_t ms = t.ms_after_midnight;
    return fmt::format("{:04}-{:02}-{:02} {:02}:{:02}:{:02}.{:03} UTC",
                       static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                       static_cast<unsigned>(ymd.day()), ms / 3'600'000U, ms / 60'000U % 60U,
                       ms / 1000U % 60U, ms % 1000U);
}

VoidResult TimeProducer::publish(const TimeOfDay& t) {
    const auto bytes = encode(t);
    auto r = bus_.send(Frame::make(cob_id_, bytes));
    if (r) {
        ++sent_;
    }
    return r;
}

VoidResult TimeProducer::publish(system_clock::time_point t) {
    auto tod = to_time_of_day(t);
    if (!tod) {
        return fail(tod.error());
    }
    return publish(*tod);
}

void TimeConsumer::on_frame(const Frame& frame, TimePoint now) {
    if (frame.id != cob_id_ || frame.rtr() || frame.extended() || frame.error()) {
        return;
    }
    auto t = decode_time_of_day(frame.payload());
    if (!t) {
        ++malformed_;
        return;
    }
    last_ = *t;
    last_rx_ = now;
    ++received_;
    if (handler_) {
        handler_(last_, now);
    }
}

Result<system_clock::time_point> TimeConsumer::network_time(TimePoint now) const {
    if (received_ == 0) {
        return fail(CoreErrc::NotPermitted);
    }
    return to_system_time(last_) + duration_cast<system_clock::duration>(now - last_rx_);
}

} // namespace codrive::sync
