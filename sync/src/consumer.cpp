// SPDX-License-Identifier: Apache-2.0
// SYNC consumer: counter and period monitoring (CiA 301 §7.2.5, 1006h/1019h).
#include <codrive/sync/consumer.hpp>

#include <cmath>
#include <fmt/format.h>

namespace codrive::sync {

namespace {
std::string ms_text(Duration d) {
    const double ms = to_ms(d);
    if (std::abs(ms - std::round(ms)) < 1e-6) {
        return fmt::format("{} ms", std::llround(ms));
    }
    return fmt::format("{:.3g} ms", ms);
}
} // namespace

std::string_view to_string(SyncEventKind k) {
    switch (k) {
    case SyncEventKind::Missing:
        return "SYNC missing";
    case SyncEventKind::Recovered:
        return "SYNC recovered";
    case SyncEventKind::CounterJump:
        return "SYNC counter jump";
    case SyncEventKind::LengthError:
        return "SYNC length error";
    }
    return "unknown";
}

VoidResult SyncConsumer::configure(const SyncConsumerConfig& config) {
    if (config.cob_id > Frame::kStdMask || config.cycle_period.count() < 0 ||
        config.counter_overflow == 1 || config.counter_overflow > 240 ||
        !(config.timeout_factor >= 1.0)) {
        return fail(CoreErrc::InvalidArgument);
    }
    config_ = config;
    timeout_ = Duration{static_cast<Duration::rep>(
        std::llround(static_cast<double>(config.cycle_period.count()) * config.timeout_factor))};
    deadline_ = kNever;
    have_last_ = false;
    missing_ = false;
    last_counter_ = 0;
    last_interval_ = Duration{0};
    return {};
}

std::string SyncConsumer::prefix() const {
    return config_.node != 0 ? fmt::format("node {}: ", config_.node) : std::string{};
}

void SyncConsumer::on_frame(const Frame& frame, TimePoint now) {
    if (frame.id != config_.cob_id || frame.rtr() || frame.extended() || frame.error()) {
        return;
    }
    const std::uint8_t expected_len = config_.counter_overflow != 0 ? 1 : 0;
    if (frame.len != expected_len) {
        ++length_errors_;
        emit(SyncEventKind::LengthError, now,
             fmt::format("{}SYNC with {} data bytes, expected {} (1019h = {})", prefix(), frame.len,
                         expected_len, config_.counter_overflow));
        return;
    }
    ++received_;
    std::uint8_t counter = 0;
    if (expected_len == 1) {
        counter = frame.data[0];
        if (have_last_ && last_counter_ != 0) {
            const auto expected = static_cast<std::uint8_t>(
                last_counter_ >= config_.counter_overflow ? 1 : last_counter_ + 1);
            if (counter != expected) {
                ++counter_jumps_;
                emit(SyncEventKind::CounterJump, now,
                     fmt::format("{}SYNC counter {} after {}, expected {}", prefix(), counter,
                                 last_counter_, expected),
                     counter, expected);
            }
        }
        last_counter_ = counter;
    }
    if (have_last_) {
        last_interval_ = now - last_;
    }
    last_ = now;
    have_last_ = true;
    if (timeout_.count() > 0) {
        deadline_ = now + timeout_;
    }
    if (missing_) {
        missing_ = false;
        emit(SyncEventKind::Recovered, now, fmt::format("{}SYNC received again", prefix()));
    }
    if (hook_) {
        hook_(SyncReception{counter, now, received_});
    }
}

void SyncConsumer::on_tick(TimePoint now) {
    if (deadline_ == kNever || now < deadline_ || missing_) {
        return;
    }
    missing_ = true;
    deadline_ = kNever;
    emit(SyncEventKind::Missing, now,
         fmt::format("{}SYNC missing: none for {} (communication cycle period {})", prefix(),
                     ms_text(now - last_), ms_text(config_.cycle_period)));
}

void SyncConsumer::emit(SyncEventKind kind, TimePoint now, std::string text, std::uint8_t counter,
                        std::uint8_t expected) {
    if (handler_) {
        handler_(SyncEvent{kind, now, counter, expected, std::move(text)});
    }
}

} // namespace codrive::sync
