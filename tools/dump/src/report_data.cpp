// SPDX-License-Identifier: Apache-2.0
// The report's data as JSON, built from the statistics codrive-dump keeps for --stats.
#include <codrive/dump/report_data.hpp>

#include <codrive/dump/line_format.hpp>
#include <codrive/nmt/state.hpp>

#include <fmt/compile.h>
#include <fmt/format.h>

#include <cmath>
#include <iterator>

namespace codrive::dump {
namespace {

class Json {
public:
    void raw(std::string_view s) { b_.append(s.data(), s.data() + s.size()); }
    void key(std::string_view k) {
        sep();
        append_json_string(b_, k);
        b_.push_back(':');
        fresh_ = true;
    }
    void open(char c) {
        sep();
        b_.push_back(c);
        fresh_ = true;
    }
    void close(char c) {
        b_.push_back(c);
        fresh_ = false;
    }
    void str(std::string_view s) {
        sep();
        append_json_string(b_, s);
    }
    void num(double v) {
        sep();
        if (!std::isfinite(v)) {
            raw("null");
        } else if (v == std::trunc(v) && std::fabs(v) < 1e6 && !std::signbit(v)) {
            // Most values of a series are whole (counts, empty buckets): below 10^6 "{:.6g}"
            // prints them exactly as an integer does, and integers print several times faster.
            digits(static_cast<std::uint64_t>(v));
        } else {
            fmt::format_to(std::back_inserter(b_), FMT_COMPILE("{:.6g}"), v);
        }
    }
    void uint(std::uint64_t v) {
        sep();
        digits(v);
    }
    void null() {
        sep();
        raw("null");
    }
    void boolean(bool v) {
        sep();
        raw(v ? "true" : "false");
    }
    [[nodiscard]] std::string text() const {
        // "</" only occurs inside strings, where "<\/" means the same.
        std::string out;
        out.reserve(b_.size());
        for (std::size_t i = 0; i < b_.size(); ++i) {
            out.push_back(b_[i]);
            if (b_[i] == '<' && i + 1 < b_.size() && b_[i + 1] == '/') {
                out.push_back('\\');
            }
        }
        return out;
    }

private:
    void digits(std::uint64_t v) {
        const fmt::format_int text(v);
        b_.append(text.data(), text.data() + text.size());
    }
    void sep() {
        if (!fresh_) {
            b_.push_back(',');
        }
        fresh_ = false;
    }
    fmt::memory_buffer b_;
    bool fresh_ = true;
};

double ms(double ns) {
    return ns / 1e6;
}

void running(Json& j, std::string_view name, const Stats::Running& r, double unit_ns) {
    j.key(name);
    j.open('{');
    j.key("n");
    j.uint(r.n);
    if (r.n > 0) {
        j.key("mean");
        j.num(r.mean_ns / unit_ns);
        j.key("jitter");
        j.num(r.stddev_ns() / unit_ns);
        j.key("min");
        j.num(static_cast<double>(r.min_ns) / unit_ns);
        j.key("max");
        j.num(static_cast<double>(r.max_ns) / unit_ns);
    }
    j.close('}');
}

void log_histogram(Json& j, std::string_view name, const LogHistogram& h) {
    j.key(name);
    j.open('{');
    j.key("counts");
    j.open('[');
    for (auto c : h.counts()) {
        j.uint(c);
    }
    j.close(']');
    j.key("below");
    j.uint(h.below());
    j.key("above");
    j.uint(h.above());
    j.close('}');
}

// Per-bucket series of one node; nullptr-like gaps are JSON null.
template <typename F>
void series(Json& j, std::string_view name, const Timeline& t, F value) {
    j.key(name);
    j.open('[');
    for (std::size_t i = 0; i < t.used(); ++i) {
        const double v = value(i);
        if (std::isnan(v)) {
            j.null();
        } else {
            j.num(v);
        }
    }
    j.close(']');
}

// The duration a bucket covers: the whole width, except the last one, which ends with the trace.
double bucket_seconds(const Stats& s, const Timeline& t, std::size_t i) {
    const double width = static_cast<double>(t.width_ns()) / 1e9;
    if (i + 1 < t.used()) {
        return width;
    }
    const auto start = t.start_ns() + static_cast<std::int64_t>(i) * t.width_ns();
    return std::min(width, static_cast<double>(s.timeline_last_ns() - start) / 1e9);
}

void node_row(Json& j, const Stats& s, NodeId id, const Stats::Detail* d) {
    const auto& n = s.node(id);
    j.open('{');
    j.key("id");
    j.uint(id);
    j.key("state");
    if (n.nmt_state == 0xFF) {
        j.null();
    } else {
        const auto st = nmt::state_from_byte(n.nmt_state);
        j.str(st ? nmt::to_string(*st) : std::string_view("invalid"));
    }
    j.key("identity");
    j.open('[');
    for (unsigned i = 0; i < 4; ++i) {
        if ((n.identity_known & (1U << i)) != 0) {
            j.uint(n.identity[i]);
        } else {
            j.null();
        }
    }
    j.close(']');
    j.key("name");
    j.str(n.device_name);
    running(j, "hb", n.hb, 1e6);
    j.key("guard");
    j.open('[');
    j.uint(n.guard_requests);
    j.uint(n.guard_replies);
    j.uint(n.guard_unanswered);
    j.uint(n.guard_toggle_errors);
    j.close(']');
    j.key("emcy");
    j.uint(n.emcy);
    j.key("last_emcy");
    j.str(n.last_emcy_code != 0 ? fmt::format("0x{:04X} {}", n.last_emcy_code, n.last_emcy_text)
                                : std::string());
    j.key("sdo");
    j.open('{');
    j.key("done");
    j.uint(n.sdo_done);
    j.key("aborts");
    j.uint(n.sdo_aborts);
    j.key("timeouts");
    j.uint(n.sdo_timeouts);
    j.key("mean_ms");
    n.sdo_timed > 0 ? j.num(ms(n.sdo_rtt_sum_ns / static_cast<double>(n.sdo_timed))) : j.null();
    j.key("max_ms");
    n.sdo_timed > 0 ? j.num(ms(static_cast<double>(n.sdo_rtt_max_ns))) : j.null();
    j.close('}');
    const double secs = static_cast<double>(s.duration_ns()) / 1e9;
    j.key("tpdo");
    j.uint(n.tpdo);
    j.key("rpdo");
    j.uint(n.rpdo);
    j.key("tpdo_rate");
    secs > 0 && s.timed_frames() > 0 ? j.num(static_cast<double>(n.tpdo) / secs) : j.null();
    j.key("rpdo_rate");
    secs > 0 && s.timed_frames() > 0 ? j.num(static_cast<double>(n.rpdo) / secs) : j.null();
    running(j, "latency", n.sync_latency, 1e3);
    if (d != nullptr) {
        log_histogram(j, "sdo_hist", d->sdo_rtt[id]);
        log_histogram(j, "latency_hist", d->sync_latency[id]);
        const auto& t = d->timeline;
        const bool pdos = n.tpdo + n.rpdo > 0;
        const auto rate = [&](std::size_t i, bool tpdo) {
            const auto& b = t.node(id, i);
            const double secs_i = bucket_seconds(s, t, i);
            return secs_i > 0 ? static_cast<double>(tpdo ? b.tpdo : b.rpdo) / secs_i : NAN;
        };
        if (pdos) {
            series(j, "tpdo_series", t, [&](std::size_t i) { return rate(i, true); });
            series(j, "rpdo_series", t, [&](std::size_t i) { return rate(i, false); });
        }
        if (n.hb.n > 0) {
            series(j, "hb_series", t, [&](std::size_t i) {
                const auto& b = t.node(id, i);
                return b.hb > 0 ? ms(b.hb_sum_ns / b.hb) : NAN;
            });
        }
    }
    j.close('}');
}

} // namespace

std::string report_json(const Stats& s, const ReportInfo& info) {
    Json j;
    const Stats::Detail* d = s.detail();
    j.open('{');
    j.key("source");
    j.str(info.source);
    j.key("generator");
    j.str(info.generator);
    j.key("bitrate");
    j.uint(s.bitrate());
    j.key("frames");
    j.uint(s.frames());
    j.key("error_frames");
    j.uint(s.error_frames());
    j.key("timed");
    j.boolean(s.timed_frames() > 0);
    j.key("start_s");
    j.num(static_cast<double>(s.first_ns()) / 1e9);
    j.key("duration_s");
    j.num(static_cast<double>(s.duration_ns()) / 1e9);
    j.key("load_mean");
    j.num(s.bus_load());
    j.key("load_peak_1s");
    j.num(s.peak_load_so_far());
    running(j, "sync", s.sync_period(), 1e3);
    if (d != nullptr) {
        const auto& t = d->timeline;
        j.key("bucket_s");
        j.num(static_cast<double>(t.width_ns()) / 1e9);
        j.key("timeline_start_s");
        j.num(static_cast<double>(t.start_ns()) / 1e9);
        series(j, "t", t, [&](std::size_t i) {
            return static_cast<double>(static_cast<std::int64_t>(i) * t.width_ns() + t.start_ns() -
                                       s.first_ns()) /
                   1e9;
        });
        series(j, "load", t, [&](std::size_t i) {
            const double secs = bucket_seconds(s, t, i);
            // A last bucket of under a quarter width says little: left out.
            if (secs < static_cast<double>(t.width_ns()) / 4e9 || s.bitrate() == 0) {
                return static_cast<double>(NAN);
            }
            return 100.0 * static_cast<double>(t.bus(i).bits) / (s.bitrate() * secs);
        });
        series(j, "emcy", t, [&](std::size_t i) { return static_cast<double>(t.bus(i).emcy); });
        series(j, "anomalies", t,
               [&](std::size_t i) { return static_cast<double>(t.bus(i).anomalies); });
        j.key("log_bins_us");
        j.open('[');
        for (std::size_t i = 0; i < LogHistogram::kBins; ++i) {
            j.num(std::sqrt(LogHistogram::edge_ns(i) * LogHistogram::edge_ns(i + 1)) / 1e3);
        }
        j.close(']');
        j.key("sync_hist");
        j.open('{');
        j.key("bin_us");
        j.num(d->sync_period.bin_ns() / 1e3);
        j.key("counts");
        j.open('[');
        for (auto c : d->sync_period.counts()) {
            j.uint(c);
        }
        j.close(']');
        j.key("above");
        j.uint(d->sync_period.above());
        j.close('}');
        j.key("events_total");
        j.uint(d->events_total);
        j.key("events");
        j.open('[');
        for (const auto& e : d->events) {
            j.open('{');
            j.key("t");
            e.ts_ns ? j.num(static_cast<double>(*e.ts_ns - s.first_ns()) / 1e9) : j.null();
            j.key("node");
            j.uint(e.node);
            j.key("emcy");
            j.boolean(e.emcy);
            j.key("severity");
            j.str(e.severity);
            j.key("service");
            j.str(e.service);
            j.key("text");
            j.str(e.text);
            j.close('}');
        }
        j.close(']');
    }
    j.key("nodes");
    j.open('[');
    for (NodeId id = 1; id <= kMaxNodeId; ++id) {
        if (s.node(id).seen) {
            node_row(j, s, id, d);
        }
    }
    j.close(']');
    j.close('}');
    return j.text();
}

} // namespace codrive::dump
