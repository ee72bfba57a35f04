// SPDX-License-Identifier: Apache-2.0
// Per-node statistics and bus load for `--stats` / `--top`.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/dump/frame_bits.hpp>
#include <codrive/dump/timeline.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

/// Counters per node and for the whole bus, for `--stats`, `--top` and `--report`. Fixed size:
/// no growth with trace length.
class Stats {
public:
    /// Welford running mean and variance of a duration, with its extremes.
    struct Running {
        std::uint64_t n = 0;
        double mean_ns = 0;
        double m2 = 0;
        std::int64_t min_ns = 0;
        std::int64_t max_ns = 0;
        void add(std::int64_t ns);
        /// Sample standard deviation in ns (0 with fewer than two values).
        [[nodiscard]] double stddev_ns() const;
    };
    struct Node {
        bool seen = false;
        std::uint8_t nmt_state = 0xFF; ///< last heartbeat state byte, 0xFF = none
        std::uint64_t heartbeats = 0;
        std::int64_t last_hb_ns = 0;
        bool hb_measuring = false; ///< last_hb_ns holds a heartbeat to measure the next from
        Running hb;                ///< heartbeat intervals (a boot-up restarts the measurement)
        std::uint64_t emcy = 0;
        std::uint16_t last_emcy_code = 0;
        std::string last_emcy_text;
        std::uint64_t sdo_done = 0;
        std::uint64_t sdo_timed = 0; ///< of sdo_done, those with a measured duration
        std::uint64_t sdo_aborts = 0;
        std::uint64_t sdo_timeouts = 0;
        double sdo_rtt_sum_ns = 0; // double: out-of-order traces must not overflow a sum
        std::int64_t sdo_rtt_max_ns = 0;
        /// Time from the last SYNC to each TPDO of this node (CiA 301 §7.2.2.2: synchronous
        /// TPDOs follow the SYNC), counted while SYNCs are seen.
        Running sync_latency;
        /// Identity object 1018h sub-indices 1..4 seen in SDO traffic or an EDS (bit i-1 of
        /// `identity_known` set when `identity[i-1]` is known).
        std::array<std::uint32_t, 4> identity{};
        std::uint8_t identity_known = 0;
        std::string device_name; ///< 1008h, when uploaded in the trace
        std::uint64_t tpdo = 0;
        std::uint64_t rpdo = 0;
        /// PDOs per 100 ms slot of the last second (ring indexed by slot number), for `--top`.
        std::array<std::uint32_t, 10> tpdo_slots{};
        std::array<std::uint32_t, 10> rpdo_slots{};
        std::array<std::int64_t, 10> slot_ids{};
        // Node guarding (CiA 301 §7.2.8.3.2.1), kept apart from the heartbeat period.
        std::uint64_t guard_requests = 0;
        std::uint64_t guard_replies = 0;
        std::uint64_t guard_unanswered = 0; ///< a request followed by another request
        std::uint64_t guard_toggle_errors = 0;
        bool guard_pending = false;
        bool guard_toggle = false; ///< toggle bit of the last reply
    };

    /// A warning, error or EMCY for the report's timeline, with the decoded text.
    struct Event {
        std::optional<std::int64_t> ts_ns; ///< on the timeline; none for an untimed record
        NodeId node = 0;
        bool emcy = false;
        std::string_view severity; ///< a static name: "warning", "error", ...
        std::string_view service;  ///< a static name: "sdo", "emcy", ...
        std::string text;
    };
    /// What only the report needs: time buckets, histograms and the first events (fixed size).
    struct Detail {
        static constexpr std::size_t kMaxEvents = 2000;
        Timeline timeline;
        PeriodHistogram sync_period;
        std::array<LogHistogram, kMaxNodeId + 1> sdo_rtt{};
        std::array<LogHistogram, kMaxNodeId + 1> sync_latency{};
        std::vector<Event> events; ///< the first kMaxEvents, in trace order
        std::uint64_t events_total = 0;
    };

    explicit Stats(std::uint32_t bitrate = 500000) : bitrate_(bitrate) {}
    ~Stats();
    Stats(const Stats&) = delete;
    Stats& operator=(const Stats&) = delete;

    /// Also keeps the time series and histograms of `--report` (about 300 KiB, plus 16 KiB per node
    /// seen).
    void enable_report();
    /// The report's data; null unless enable_report() was called.
    [[nodiscard]] const Detail* detail() const { return detail_.get(); }

    /// Counts a frame; a frame without a timestamp (`timed` false: candump screen output without
    /// `-t`) is counted but says nothing about time, so with no timed frame at all the table
    /// shows no rates and no bus load instead of dividing by a zero duration.
    void on_frame(const Frame& f, std::int64_t ts_ns, bool timed = true);
    void on_heartbeat(NodeId node, std::uint8_t state, std::int64_t ts_ns);
    /// An interface's time went back to `ts_ns` (a second capture appended to the first, a clock
    /// step): the one-second load window restarts there. With `new_stretch` the time from there
    /// adds to the duration (the first interface to step); without, the interface joins the
    /// stretch another one opened.
    void on_time_step(std::int64_t ts_ns, bool new_stretch = true);
    /// A node guarding remote request to `node`.
    void on_guard_request(NodeId node);
    /// A node guarding reply: state byte without the toggle bit, and the toggle bit.
    void on_guard_reply(NodeId node, std::uint8_t state, bool toggle);
    void on_emcy(NodeId node, std::uint16_t code, std::string text);
    /// A completed transfer; its duration counts only when the trace is `timed` (a candump
    /// without -t has none, and 0 ms would be a figure nobody measured).
    void on_sdo_done(NodeId node, std::int64_t duration_ns, bool timed = true);
    void on_sdo_abort(NodeId node);
    void on_sdo_timeout(NodeId node);
    void on_pdo(NodeId node, bool tpdo, std::int64_t ts_ns = 0);
    /// A SYNC (080h) at `ts_ns`: its period, and the reference for SYNC→TPDO latencies.
    void on_sync(std::int64_t ts_ns);
    /// 1018h sub-index 1..4 of a node (from an upload in the trace or an EDS).
    void on_identity(NodeId node, std::uint8_t sub, std::uint32_t value);
    /// 1008h of a node (the first 64 bytes are kept).
    void on_device_name(NodeId node, std::string_view name);
    /// A warning, error or EMCY with its decoded text (kept for the report only). Without a time
    /// (a record that has no timestamp) it is listed, but in no bucket of the timeline.
    void on_event(std::optional<std::int64_t> ts_ns, NodeId node, bool emcy,
                  std::string_view severity, std::string_view service, std::string_view text);

    /// The table: one row per node that sent something, then the nodes that were addressed but
    /// never answered, totals and bus load (mean over the trace, peak over one-second windows).
    /// PDO rates are the mean over the trace; with `now_ns` (live `--top`) they are the rates of
    /// the last second before `now_ns`, so they fall to 0 when the PDOs stop.
    [[nodiscard]] std::string table(std::optional<std::int64_t> now_ns = std::nullopt) const;
    [[nodiscard]] const Node& node(NodeId n) const { return nodes_[n]; }
    [[nodiscard]] std::uint64_t frames() const { return frames_; }
    /// Mean bus load in percent over the trace so far.
    [[nodiscard]] double bus_load() const;
    [[nodiscard]] double peak_load() const { return peak_load_; }
    /// Peak load including the window still open, as the table prints it.
    [[nodiscard]] double peak_load_so_far() const;
    [[nodiscard]] std::uint32_t bitrate() const { return bitrate_; }
    [[nodiscard]] std::uint64_t error_frames() const { return error_frames_; }
    [[nodiscard]] std::uint64_t timed_frames() const { return timed_frames_; }
    [[nodiscard]] std::int64_t first_ns() const { return first_ns_; }
    /// The time the timed frames cover: last minus first, summed over the stretches between
    /// steps back (so two appended captures of 10 s make 20 s, not 10).
    [[nodiscard]] std::int64_t duration_ns() const;
    /// A trace time on the report's timeline, where the stretches follow one another (the
    /// second of two appended captures goes on after the first). The same time before any step.
    [[nodiscard]] std::int64_t on_timeline(std::int64_t ts_ns) const;
    /// The latest time on that timeline.
    [[nodiscard]] std::int64_t timeline_last_ns() const { return timeline_last_ns_; }
    /// SYNC intervals over the trace.
    [[nodiscard]] const Running& sync_period() const { return sync_period_; }
    [[nodiscard]] std::uint64_t syncs() const { return syncs_; }

private:
    /// Load of the one-second window still open, or 0 while it is under 100 ms.
    [[nodiscard]] double open_window_load() const;

    std::uint32_t bitrate_;
    std::array<Node, kMaxNodeId + 1> nodes_{};
    std::uint64_t frames_ = 0;
    std::uint64_t error_frames_ = 0;
    std::uint64_t timed_frames_ = 0;
    std::uint64_t bits_ = 0;
    std::int64_t first_ns_ = 0;
    std::int64_t stretch_first_ns_ = 0; ///< the stretch since the last step back
    std::int64_t stretch_last_ns_ = 0;
    std::int64_t earlier_stretches_ns_ = 0;
    std::int64_t timeline_offset_ns_ = 0; ///< on_timeline(ts) = ts + this
    std::int64_t timeline_last_ns_ = 0;
    std::int64_t window_start_ns_ = 0;
    std::uint64_t window_bits_ = 0;
    double peak_load_ = 0;
    std::uint64_t syncs_ = 0;
    std::int64_t last_sync_ns_ = 0;
    Running sync_period_;
    std::unique_ptr<Detail> detail_;
};

} // namespace codrive::dump
