// SPDX-License-Identifier: Apache-2.0
// Per-node statistics and bus load.
#include <codrive/dump/stats.hpp>

#include <codrive/dump/record.hpp>
#include <codrive/nmt/state.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

namespace codrive::dump {
namespace {

// a + b for a, b >= 0, held at INT64_MAX (a trace of stretches longer than that is a fuzzer's).
std::int64_t add_saturated(std::int64_t a, std::int64_t b) {
    return b > std::numeric_limits<std::int64_t>::max() - a
               ? std::numeric_limits<std::int64_t>::max()
               : a + b;
}

} // namespace

void Stats::Running::add(std::int64_t ns) {
    ++n;
    const double x = static_cast<double>(ns);
    const double delta = x - mean_ns;
    mean_ns += delta / static_cast<double>(n);
    m2 += delta * (x - mean_ns);
    min_ns = n == 1 ? ns : std::min(min_ns, ns);
    max_ns = n == 1 ? ns : std::max(max_ns, ns);
}

double Stats::Running::stddev_ns() const {
    return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0;
}

Stats::~Stats() = default;

void Stats::enable_report() {
    if (!detail_) {
        detail_ = std::make_unique<Detail>();
        detail_->events.reserve(Detail::kMaxEvents);
    }
}

void Stats::on_frame(const Frame& f, std::int64_t ts, bool timed) {
    ++frames_;
    if (f.error()) {
        ++error_frames_;
    }
    if (!timed) {
        return;
    }
    if (timed_frames_++ == 0) {
        first_ns_ = ts;
        stretch_first_ns_ = ts;
        stretch_last_ns_ = ts;
        window_start_ns_ = ts;
        timeline_last_ns_ = ts;
    }
    if (f.error()) {
        return;
    }
    const auto bits = frame_bits_exact(f);
    bits_ += bits;
    stretch_first_ns_ = std::min(stretch_first_ns_, ts);
    stretch_last_ns_ = std::max(stretch_last_ns_, ts);
    timeline_last_ns_ = std::max(timeline_last_ns_, on_timeline(ts));
    if (detail_) {
        auto& b = detail_->timeline.bus(detail_->timeline.bucket(on_timeline(ts)));
        b.bits += bits;
        ++b.frames;
    }
    constexpr std::int64_t kWindow = 1'000'000'000;
    if (ts < window_start_ns_ - kWindow) {
        return; // another interface's backlog, a window or more behind: in the mean, not the peak
    }
    if (ts - window_start_ns_ >= kWindow) {
        const double load = 100.0 * static_cast<double>(window_bits_) / bitrate_;
        peak_load_ = std::max(peak_load_, load);
        window_start_ns_ += ((ts - window_start_ns_) / kWindow) * kWindow;
        window_bits_ = 0;
    }
    window_bits_ += bits;
}

void Stats::on_time_step(std::int64_t ts, bool new_stretch) {
    if (timed_frames_ == 0) {
        return;
    }
    peak_load_ = std::max(peak_load_, open_window_load()); // the window the step cuts short
    window_start_ns_ = ts;
    window_bits_ = 0;
    if (!new_stretch) {
        return;
    }
    earlier_stretches_ns_ =
        add_saturated(earlier_stretches_ns_, stretch_last_ns_ - stretch_first_ns_);
    // The new stretch goes on where the last one ended on the report's timeline.
    if (__builtin_sub_overflow(on_timeline(stretch_last_ns_), ts, &timeline_offset_ns_)) {
        timeline_offset_ns_ = 0; // not a time a reader gives
    }
    stretch_first_ns_ = ts;
    stretch_last_ns_ = ts;
}

std::int64_t Stats::duration_ns() const {
    return add_saturated(earlier_stretches_ns_, stretch_last_ns_ - stretch_first_ns_);
}

std::int64_t Stats::on_timeline(std::int64_t ts) const {
    std::int64_t t = 0;
    if (__builtin_add_overflow(ts, timeline_offset_ns_, &t)) {
        return timeline_offset_ns_ > 0 ? kMaxTraceTimeNs : 0;
    }
    return std::clamp<std::int64_t>(t, 0, kMaxTraceTimeNs);
}

void Stats::on_heartbeat(NodeId node, std::uint8_t state, std::int64_t ts) {
    Node& n = nodes_[node];
    n.seen = true;
    n.nmt_state = state;
    if (state == 0) {
        n.hb_measuring = false; // a boot-up restarts the period measurement
        ++n.heartbeats;
        return;
    }
    if (n.hb_measuring && ts > n.last_hb_ns) {
        const auto d = ts - n.last_hb_ns;
        n.hb.add(d);
        if (detail_) {
            auto& b = detail_->timeline.node(node, detail_->timeline.bucket(on_timeline(ts)));
            ++b.hb;
            b.hb_sum_ns += static_cast<double>(d);
            b.hb_max_ns = std::max(b.hb_max_ns, d);
        }
    }
    n.last_hb_ns = ts;
    n.hb_measuring = true; // also at t = 0 of a relative trace
    ++n.heartbeats;
}

void Stats::on_guard_request(NodeId node) {
    Node& n = nodes_[node];
    n.seen = true;
    ++n.guard_requests;
    if (n.guard_pending) {
        ++n.guard_unanswered;
    }
    n.guard_pending = true;
}

void Stats::on_guard_reply(NodeId node, std::uint8_t state, bool toggle) {
    Node& n = nodes_[node];
    n.seen = true;
    n.nmt_state = state;
    n.guard_pending = false;
    // The toggle bit alternates from reply to reply (CiA 301 §7.2.8.3.2.1); the first reply seen
    // may be anywhere in the sequence, so it is not checked.
    if (n.guard_replies > 0 && toggle == n.guard_toggle) {
        ++n.guard_toggle_errors;
    }
    n.guard_toggle = toggle;
    ++n.guard_replies;
}

void Stats::on_emcy(NodeId node, std::uint16_t code, std::string text) {
    Node& n = nodes_[node];
    n.seen = true;
    ++n.emcy;
    if (code == 0) {
        // "Error reset": keep the last error, noting that it has been cleared.
        if (!n.last_emcy_text.empty() && n.last_emcy_code != 0 &&
            !n.last_emcy_text.ends_with(" (reset)")) {
            n.last_emcy_text += " (reset)";
        }
        return;
    }
    n.last_emcy_code = code;
    n.last_emcy_text = std::move(text);
}

void Stats::on_sdo_done(NodeId node, std::int64_t d, bool timed) {
    nodes_[node].seen = true;
    ++nodes_[node].sdo_done;
    if (!timed) {
        return;
    }
    ++nodes_[node].sdo_timed;
    nodes_[node].sdo_rtt_sum_ns += static_cast<double>(std::max<std::int64_t>(d, 0));
    nodes_[node].sdo_rtt_max_ns = std::max(nodes_[node].sdo_rtt_max_ns, d);
    if (detail_) {
        detail_->sdo_rtt[node].add(static_cast<double>(d));
    }
}
void Stats::on_sdo_abort(NodeId node) {
    nodes_[node].seen = true;
    ++nodes_[node].sdo_aborts;
}
void Stats::on_sdo_timeout(NodeId node) {
    // Not `seen`: a scan addresses all 127 ids and most never answer; they are summarised in
    // one line, not listed as rows.
    ++nodes_[node].sdo_timeouts;
}

namespace {
constexpr std::int64_t kSlotNs = 100'000'000; // 10 slots = the 1 s window of `--top` rates
constexpr std::size_t kSlots = 10;
} // namespace

void Stats::on_pdo(NodeId node, bool tpdo, std::int64_t ts_ns) {
    Node& n = nodes_[node];
    n.seen = true;
    ++(tpdo ? n.tpdo : n.rpdo);
    const std::int64_t slot = ts_ns / kSlotNs;
    constexpr auto kN = static_cast<std::int64_t>(kSlots);
    const auto i = static_cast<std::size_t>(((slot % kN) + kN) % kN); // a trace may start < 0
    if (n.slot_ids[i] != slot) {
        n.slot_ids[i] = slot;
        n.tpdo_slots[i] = 0;
        n.rpdo_slots[i] = 0;
    }
    ++(tpdo ? n.tpdo_slots[i] : n.rpdo_slots[i]);
    // A TPDO belongs to the SYNC before it if it comes within one SYNC period (twice the mean,
    // for jitter); with SYNC gone silent, latencies would only measure the silence.
    const auto lat = ts_ns - last_sync_ns_;
    const bool synced =
        tpdo && syncs_ > 0 && lat >= 0 &&
        (sync_period_.n == 0 || static_cast<double>(lat) < 2 * sync_period_.mean_ns);
    if (synced) {
        n.sync_latency.add(lat);
    }
    if (detail_) {
        auto& b = detail_->timeline.node(node, detail_->timeline.bucket(on_timeline(ts_ns)));
        ++(tpdo ? b.tpdo : b.rpdo);
        if (synced) {
            detail_->sync_latency[node].add(static_cast<double>(lat));
        }
    }
}

void Stats::on_sync(std::int64_t ts) {
    if (syncs_ > 0 && ts > last_sync_ns_) {
        sync_period_.add(ts - last_sync_ns_);
        if (detail_) {
            detail_->sync_period.add(ts - last_sync_ns_);
        }
    }
    ++syncs_;
    last_sync_ns_ = ts;
    if (detail_) {
        ++detail_->timeline.bus(detail_->timeline.bucket(on_timeline(ts))).sync;
    }
}

void Stats::on_identity(NodeId node, std::uint8_t sub, std::uint32_t value) {
    if (sub >= 1 && sub <= 4) {
        nodes_[node].identity[sub - 1U] = value;
        nodes_[node].identity_known =
            static_cast<std::uint8_t>(nodes_[node].identity_known | (1U << (sub - 1U)));
    }
}

void Stats::on_device_name(NodeId node, std::string_view name) {
    nodes_[node].device_name.assign(name.substr(0, 64));
}

void Stats::on_event(std::optional<std::int64_t> ts, NodeId node, bool emcy,
                     std::string_view severity, std::string_view service, std::string_view text) {
    if (!detail_) {
        return;
    }
    std::optional<std::int64_t> at;
    if (ts) {
        at = on_timeline(*ts);
        auto& b = detail_->timeline.bus(detail_->timeline.bucket(*at));
        ++(emcy ? b.emcy : b.anomalies);
    }
    if (detail_->events_total++ < Detail::kMaxEvents) {
        detail_->events.push_back(Event{at, node, emcy, severity, service, std::string(text)});
    }
}

namespace {

// PDOs in the 1 s before now_ns (the 10 slots ending with the current one).
double recent_rate(const std::array<std::uint32_t, kSlots>& counts,
                   const std::array<std::int64_t, kSlots>& ids, std::int64_t now_ns) {
    const std::int64_t now_slot = now_ns / kSlotNs;
    std::uint64_t sum = 0;
    for (std::size_t i = 0; i < kSlots; ++i) {
        if (ids[i] > now_slot - static_cast<std::int64_t>(kSlots) && ids[i] <= now_slot) {
            sum += counts[i];
        }
    }
    return static_cast<double>(sum); // per 1 s window
}

// "2, 5..127": node ids as ranges.
std::string ranges(const std::vector<unsigned>& ids) {
    std::string out;
    for (std::size_t i = 0; i < ids.size();) {
        std::size_t j = i;
        while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) {
            ++j;
        }
        out += out.empty() ? "" : ", ";
        out += j == i ? fmt::format("{}", ids[i]) : fmt::format("{}..{}", ids[i], ids[j]);
        i = j + 1;
    }
    return out;
}

} // namespace

double Stats::bus_load() const {
    const auto span = duration_ns();
    if (span <= 0 || bitrate_ == 0) {
        return 0;
    }
    return 100.0 * static_cast<double>(bits_) /
           (static_cast<double>(bitrate_) * 1e-9 * static_cast<double>(span));
}

double Stats::open_window_load() const {
    // The window still open counts if it is long enough to say something.
    const auto open_ns = stretch_last_ns_ - window_start_ns_;
    if (open_ns < 100'000'000 || bitrate_ == 0) {
        return 0;
    }
    return 100.0 * static_cast<double>(window_bits_) /
           (static_cast<double>(bitrate_) * 1e-9 * static_cast<double>(open_ns));
}

double Stats::peak_load_so_far() const {
    double peak = std::max(peak_load_, open_window_load());
    if (static_cast<double>(duration_ns()) / 1e9 < 1.0) {
        peak = std::max(peak, bus_load());
    }
    return peak;
}

std::string Stats::table(std::optional<std::int64_t> now_ns) const {
    fmt::memory_buffer b;
    auto it = std::back_inserter(b);
    const double secs = static_cast<double>(duration_ns()) / 1e9;
    fmt::format_to(it,
                   "{:>4}  {:<15}  {:>9}  {:>8}  {:>5}  {:>5}  {:>6}  {:>8}  {:>8}  {:>8}  {}\n",
                   "node", "NMT state", "HB period", "HB jit.", "EMCY", "SDO", "ab/to", "SDO mean",
                   "TPDO/s", "RPDO/s", "last EMCY");
    for (std::size_t i = 1; i < nodes_.size(); ++i) {
        const Node& n = nodes_[i];
        if (!n.seen) {
            continue;
        }
        std::string_view state = "-";
        if (n.nmt_state != 0xFF) {
            const auto s = nmt::state_from_byte(n.nmt_state);
            state = s ? nmt::to_string(*s) : std::string_view("invalid");
        }
        const std::string period = n.hb.n > 0 ? fmt::format("{:.1f} ms", n.hb.mean_ns / 1e6) : "-";
        const std::string jitter =
            n.hb.n > 1 ? fmt::format("{:.2f} ms", n.hb.stddev_ns() / 1e6) : "-";
        const std::string rtt =
            n.sdo_timed > 0 ? fmt::format("{:.1f} ms",
                                          n.sdo_rtt_sum_ns / static_cast<double>(n.sdo_timed) / 1e6)
                            : "-";
        const auto rate = [&](std::uint64_t c, const std::array<std::uint32_t, kSlots>& slots) {
            if (now_ns) {
                return fmt::format("{:.1f}", recent_rate(slots, n.slot_ids, *now_ns));
            }
            if (timed_frames_ == 0) {
                return std::string("-"); // no timestamps: a count is not a rate
            }
            return secs > 0 ? fmt::format("{:.1f}", static_cast<double>(c) / secs)
                            : std::string("-");
        };
        const std::string last =
            n.last_emcy_code != 0 ? fmt::format("0x{:04X} {}", n.last_emcy_code, n.last_emcy_text)
                                  : std::string();
        fmt::format_to(
            it, "{:>4}  {:<15}  {:>9}  {:>8}  {:>5}  {:>5}  {:>6}  {:>8}  {:>8}  {:>8}  {}\n", i,
            state, period, jitter, n.emcy, n.sdo_done, n.sdo_aborts + n.sdo_timeouts, rtt,
            rate(n.tpdo, n.tpdo_slots), rate(n.rpdo, n.rpdo_slots), last);
        while (b.size() > 1 && b[b.size() - 2] == ' ') { // no trailing blanks without a last EMCY
            b[b.size() - 2] = '\n';
            b.resize(b.size() - 1);
        }
    }
    std::vector<unsigned> silent;
    for (unsigned i = 1; i < nodes_.size(); ++i) {
        if (!nodes_[i].seen && nodes_[i].sdo_timeouts > 0) {
            silent.push_back(i);
        }
    }
    if (!silent.empty()) {
        fmt::format_to(it, "no answer to SDO requests from {} node{}: {}\n", silent.size(),
                       silent.size() == 1 ? "" : "s", ranges(silent));
    }
    if (now_ns) {
        fmt::format_to(it, "PDO rates: last 1 s\n");
    }
    for (std::size_t i = 1; i < nodes_.size(); ++i) {
        const Node& n = nodes_[i];
        if (n.guard_requests > 0 || n.guard_replies > 0) {
            fmt::format_to(it,
                           "node {} guarding: {} requests, {} replies, {} unanswered, {} toggle "
                           "errors\n",
                           i, n.guard_requests, n.guard_replies, n.guard_unanswered,
                           n.guard_toggle_errors);
        }
    }
    const double peak = peak_load_so_far();
    if (timed_frames_ == 0) {
        fmt::format_to(it,
                       "{} frames ({} error frames) without timestamps: no PDO rates and no bus "
                       "load (record with candump -t a, or give a trace with timestamps)\n",
                       frames_, error_frames_);
        return {b.data(), b.size()};
    }
    fmt::format_to(it,
                   "{} frames ({} error frames) in {:.3f} s; bus load at {} kbit/s: {:.1f} % mean, "
                   "{:.1f} % peak (1 s windows, exact bit stuffing)\n",
                   frames_, error_frames_, secs, bitrate_ / 1000, bus_load(), peak);
    return {b.data(), b.size()};
}

} // namespace codrive::dump
