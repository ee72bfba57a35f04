// SPDX-License-Identifier: Apache-2.0
// EventRateLimiter: first event of a kind passed on, repeats summarised once per interval.
#include <codrive/core/event_rate_limiter.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace codrive {

EventRateLimiter::EventRateLimiter(Sink sink, Duration interval, std::size_t max_kinds,
                                   std::size_t max_key_length)
    : sink_(std::move(sink)), interval_(interval), max_key_length_(max_key_length),
      kinds_(max_kinds) {
    for (auto& k : kinds_) {
        k.key.reserve(max_key_length_);
    }
    line_.reserve(max_key_length_ + 64);
}

EventRateLimiter::Kind* EventRateLimiter::find(std::string_view key) {
    for (auto& k : kinds_) {
        if (k.active && k.key == key) {
            return &k;
        }
    }
    return nullptr;
}

EventRateLimiter::Kind* EventRateLimiter::free_slot() {
    for (auto& k : kinds_) {
        if (!k.active) {
            return &k;
        }
    }
    return nullptr;
}

void EventRateLimiter::summarise(Kind& k, TimePoint now) {
    if (k.count > 0 && sink_) {
        // The time the count covers, in seconds to one decimal: "in the last 1 s", "2.5 s".
        const double s = std::round(to_ms(now - k.window_start) / 100.0) / 10.0;
        line_.clear();
        fmt::format_to(std::back_inserter(line_), "{} \u00d7{} in the last {:g} s", k.key, k.count,
                       s);
        sink_(line_);
    }
    k.count = 0;
    k.window_start = now;
}

void EventRateLimiter::offer(std::string_view key, std::string_view sentence, TimePoint now) {
    if (interval_ <= Duration::zero()) {
        if (sink_) {
            sink_(sentence);
        }
        return;
    }
    key = key.substr(0, std::min(key.size(), max_key_length_));
    Kind* k = find(key);
    if (k == nullptr) {
        k = free_slot();
        if (k != nullptr) {
            k->active = true;
            k->key.assign(key.data(), key.size());
            k->window_start = now;
            k->count = 0;
        }
        if (sink_) {
            sink_(sentence);
        }
        return;
    }
    if (now - k->window_start >= interval_) {
        // The window ended before on_tick() saw it: close it first.
        const bool flooding = k->count > 0;
        summarise(*k, now);
        if (!flooding) {
            if (sink_) {
                sink_(sentence); // quiet for a whole interval: this one is news again
            }
            return;
        }
    }
    ++k->count;
    ++suppressed_total_;
}

void EventRateLimiter::on_tick(TimePoint now) {
    for (auto& k : kinds_) {
        if (!k.active || now - k.window_start < interval_) {
            continue;
        }
        if (k.count > 0) {
            summarise(k, now);
        } else {
            k.active = false; // quiet for a whole interval: the next one is passed on
        }
    }
}

TimePoint EventRateLimiter::next_deadline() const {
    TimePoint earliest = kNever;
    for (const auto& k : kinds_) {
        if (k.active) {
            earliest = std::min(earliest, k.window_start + interval_);
        }
    }
    return earliest;
}

void EventRateLimiter::flush(TimePoint now) {
    for (auto& k : kinds_) {
        if (k.active) {
            summarise(k, now);
            k.active = false;
        }
    }
}

} // namespace codrive
