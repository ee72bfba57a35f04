// SPDX-License-Identifier: Apache-2.0
// Per-node statistics and bus load for `--stats` / `--top`.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/frame.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace codrive::dump {

/// Bits a frame occupies on the bus in the worst case of bit stuffing, including the 3-bit
/// interframe space: classic 11-bit 47 + 8n + ⌊(34 + 8n − 1)/4⌋, 29-bit 67 + 8n + ⌊(54 + 8n −
/// 1)/4⌋ (Davis et al., "Controller Area Network (CAN) schedulability analysis", 2007). CAN FD
/// frames are counted at the arbitration rate (an upper bound).
[[nodiscard]] std::uint32_t frame_bits_worst_case(const Frame& f);

/// Counters per node and for the whole bus. Fixed size: no growth with trace length.
class Stats {
public:
    struct Node {
        bool seen = false;
        std::uint8_t nmt_state = 0xFF; ///< last heartbeat state byte, 0xFF = none
        std::uint64_t heartbeats = 0;
        std::int64_t last_hb_ns = 0;
        // Welford running mean / variance of the heartbeat interval.
        std::uint64_t hb_intervals = 0;
        double hb_mean_ns = 0;
        double hb_m2 = 0;
        std::int64_t hb_min_ns = 0;
        std::int64_t hb_max_ns = 0;
        std::uint64_t emcy = 0;
        std::uint16_t last_emcy_code = 0;
        std::string last_emcy_text;
        std::uint64_t sdo_done = 0;
        std::uint64_t sdo_aborts = 0;
        std::uint64_t sdo_timeouts = 0;
        double sdo_rtt_sum_ns = 0; // double: out-of-order traces must not overflow a sum
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

    explicit Stats(std::uint32_t bitrate = 500000) : bitrate_(bitrate) {}

    /// Counts a frame; a frame without a timestamp (`timed` false: candump screen output without
    /// `-t`) is counted but says nothing about time, so with no timed frame at all the table
    /// shows no rates and no bus load instead of dividing by a zero duration.
    void on_frame(const Frame& f, std::int64_t ts_ns, bool timed = true);
    void on_heartbeat(NodeId node, std::uint8_t state, std::int64_t ts_ns);
    /// A node guarding remote request to `node`.
    void on_guard_request(NodeId node);
    /// A node guarding reply: state byte without the toggle bit, and the toggle bit.
    void on_guard_reply(NodeId node, std::uint8_t state, bool toggle);
    void on_emcy(NodeId node, std::uint16_t code, std::string text);
    void on_sdo_done(NodeId node, std::int64_t duration_ns);
    void on_sdo_abort(NodeId node);
    void on_sdo_timeout(NodeId node);
    void on_pdo(NodeId node, bool tpdo, std::int64_t ts_ns = 0);

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

private:
    std::uint32_t bitrate_;
    std::array<Node, kMaxNodeId + 1> nodes_{};
    std::uint64_t frames_ = 0;
    std::uint64_t error_frames_ = 0;
    std::uint64_t timed_frames_ = 0;
    std::uint64_t bits_ = 0;
    std::int64_t first_ns_ = 0;
    std::int64_t last_ns_ = 0;
    std::int64_t window_start_ns_ = 0;
    std::uint64_t window_bits_ = 0;
    double peak_load_ = 0;
};

} // namespace codrive::dump
