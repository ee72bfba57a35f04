// SPDX-License-Identifier: Apache-2.0
// Rate limit for event sentences: the first of a kind is passed on, repeats become one summary
// per interval ("node 3: TPDO1 (0x183) missing after SYNC ×412 in the last 1 s").
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/time.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive {

/// Keeps a flood of one kind of event (a TPDO missing after every SYNC, a heartbeat flapping)
/// from burying everything else. Each event has a key naming its kind and source, e.g.
/// "node 3: TPDO1 (0x183) missing after SYNC"; the key is also the start of the summary line.
///
/// - The first event of a key (or the first after a quiet interval) is passed on unchanged.
/// - Further events of that key within `interval` are counted, not passed on.
/// - When the interval ends, one summary is passed on if any were counted:
///   "<key> ×<count> in the last <interval>"; the next interval starts then.
///
/// It runs on the acyclic side (an event loop as ITimed, or driven by on_tick()). All storage is
/// taken at construction: offer() and on_tick() do not allocate while keys fit the reserved
/// length (longer keys are truncated in the summary, never lost). When more kinds are active
/// than `max_kinds`, an event of a new kind is passed on unchanged (no kind is ever silenced).
class EventRateLimiter final : public ITimed {
public:
    /// Receives each sentence to show.
    using Sink = std::function<void(std::string_view sentence)>;

    /// `interval` zero passes every event on unchanged.
    explicit EventRateLimiter(Sink sink, Duration interval = seconds(1), std::size_t max_kinds = 64,
                              std::size_t max_key_length = 120);

    /// One event: `key` names its kind and source, `sentence` is the full text.
    void offer(std::string_view key, std::string_view sentence, TimePoint now);
    /// Passes on the summaries of intervals that have ended by `now` and frees quiet kinds.
    void on_tick(TimePoint now) override;
    /// The end of the earliest running interval, or kNever.
    [[nodiscard]] TimePoint next_deadline() const override;
    /// Passes on every pending summary now (e.g. at shutdown), counting up to `now`.
    void flush(TimePoint now);

    /// Events counted but not passed on, since construction.
    [[nodiscard]] std::uint64_t suppressed_total() const { return suppressed_total_; }
    [[nodiscard]] Duration interval() const { return interval_; }

private:
    struct Kind {
        bool active = false;
        std::string key; ///< capacity reserved at construction
        TimePoint window_start{};
        std::uint64_t count = 0; ///< suppressed in the current window
    };
    Kind* find(std::string_view key);
    Kind* free_slot();
    void summarise(Kind& k, TimePoint now);

    Sink sink_;
    Duration interval_;
    std::size_t max_key_length_;
    std::vector<Kind> kinds_;
    std::string line_; ///< summary buffer, capacity reserved at construction
    std::uint64_t suppressed_total_ = 0;
};

} // namespace codrive
