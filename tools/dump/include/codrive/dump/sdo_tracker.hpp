// SPDX-License-Identifier: Apache-2.0
// Follows SDO conversations per node (CiA 301 §7.2.4): expedited, segmented and block transfers
// reassembled into one result, aborts, protocol errors and unanswered requests.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/dump/object_catalog.hpp>
#include <codrive/sdo/protocol.hpp>

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace codrive::dump {

/// What a transfer looked like on the wire.
enum class SdoMode : std::uint8_t { Expedited, Segmented, Block };

/// The outcome of one frame, for the decoder's bookkeeping (PDO learning, statistics).
struct SdoOutcome {
    enum class Kind : std::uint8_t { None, Completed, Aborted, ProtocolError };
    Kind kind = Kind::None;
    bool upload = false;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::span<const std::uint8_t> data; ///< completed: the value (first kKeepBytes bytes)
    std::uint32_t size = 0;             ///< completed: the full size
    std::int64_t duration_ns = 0;
    bool timed = false; ///< both ends of the transfer carry a timestamp: duration_ns is measured
};

/// A transfer that got no answer (reported as a timeout) or was left unfinished.
struct SdoStall {
    NodeId node = 0;
    std::int64_t ts_ns = 0; ///< when the timeout expired
    bool timed = true;      ///< ts_ns is a time: a frame of the transfer had a timestamp
    std::string text;
};

/// Per-node SDO conversation state. Memory is bounded: each node keeps at most kKeepBytes of a
/// transfer's data for display (sizes and CRCs cover all of it).
class SdoTracker {
public:
    static constexpr std::size_t kKeepBytes = 1024;

    SdoTracker(const ObjectCatalog& catalog, std::int64_t timeout_ns);

    /// Decodes one SDO frame of `node`, appending its text to `out` ("node 4 upload 1008:00 …").
    /// A frame without a timestamp (`timed` false) has no `ts_ns`: a transfer that starts or ends
    /// with one gets no duration, and its timeout counts from its last frame with a timestamp
    /// (with none, it is reported if still open at the end). `clock` names the clock the time
    /// is on (the decoder's per-interface clocks; times on different clocks are not compared).
    SdoOutcome on_frame(NodeId node, sdo::Sender sender, std::span<const std::uint8_t> payload,
                        std::int64_t ts_ns, fmt::memory_buffer& out, bool timed = true,
                        std::uint8_t clock = 0);

    /// Reports transfers idle for longer than the timeout at `now_ns` on `clock`.
    void check_timeouts(std::int64_t now_ns, std::vector<SdoStall>& stalls, std::uint8_t clock = 0);
    /// `clock` went back to `now_ns` (an appended capture, a clock set back): its open transfers
    /// get no duration, and one last heard of later than that waits for its timeout from
    /// `now_ns`.
    void restart_clocks(std::int64_t now_ns, std::uint8_t clock = 0);
    /// Reports every transfer still open (end of input).
    void finish(std::vector<SdoStall>& stalls);

private:
    enum class Op : std::uint8_t { None, Download, Upload, BlockDownload, BlockUpload };
    struct Channel {
        Op op = Op::None;
        std::uint16_t index = 0;
        std::uint8_t subindex = 0;
        bool expedited = false;
        bool client_spoke_last = false;
        bool toggle = false;
        bool size_known = false;
        bool crc = false;
        bool in_block = false; ///< block segments are flowing (sender depends on op)
        bool end_seen = false;
        bool confirmed = false;      ///< the server answered the initiate (segments may follow)
        bool short_response = false; ///< last server frame was too short (already reported)
        bool tail_pending = false;
        bool started_timed = false; ///< t0 is a time: the initiate carried a timestamp
        bool clocked = false;       ///< last is a time: a frame of the transfer had a timestamp
        std::uint8_t clock = 0;     ///< the clock of `last`
        std::uint8_t block_size = 0;
        std::uint8_t last_seq = 0;
        std::uint8_t tail_len = 0;
        std::uint32_t size = 0;
        std::uint32_t total = 0;
        std::uint32_t segments = 0;
        std::uint16_t crc_value = 0;
        std::int64_t t0 = 0;
        std::int64_t last = 0;
        std::vector<std::uint8_t> data; ///< first kKeepBytes bytes
        std::array<std::uint8_t, 127 * 7> sub_block{};
        std::array<std::uint8_t, 7> tail{};
        std::size_t sub_len = 0;
    };

    /// Opens a transfer; a transfer still open on the channel is abandoned and named in `out`.
    bool start(NodeId node, Channel& ch, Op op, const sdo::FrameInfo& fi, std::int64_t ts,
               fmt::memory_buffer& out);
    void add_data(Channel& ch, std::span<const std::uint8_t> bytes);
    SdoOutcome complete(NodeId node, Channel& ch, std::int64_t ts, SdoMode mode,
                        fmt::memory_buffer& out);
    void object_name(fmt::memory_buffer& out, NodeId node, std::uint16_t index,
                     std::uint8_t sub) const;
    void stall_text(NodeId node, const Channel& ch, std::string& text) const;
    /// The transfer's time can be measured now: it started with a timestamp on the clock of
    /// the timed frame being decoded.
    [[nodiscard]] bool measured(const Channel& ch) const {
        return ch.started_timed && frame_timed_;
    }
    /// Appends "<before>12.3 ms" when the transfer's time is measured().
    void put_elapsed(fmt::memory_buffer& out, const Channel& ch, std::int64_t ts,
                     std::string_view before) const;

    const ObjectCatalog& catalog_;
    std::int64_t timeout_ns_;
    std::array<Channel, kMaxNodeId + 1> channels_{};
    std::uint32_t open_ = 0;       ///< channels with op != None (skip the timeout scan when 0)
    bool frame_timed_ = true;      ///< the frame being decoded carries a timestamp
    std::uint8_t frame_clock_ = 0; ///< and the clock it is on
};

} // namespace codrive::dump
