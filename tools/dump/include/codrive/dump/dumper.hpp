// SPDX-License-Identifier: Apache-2.0
// The codrive-dump pipeline: records in, decoded lines (or JSON), pcap and statistics out.
#pragma once

#include <codrive/dump/decoder.hpp>
#include <codrive/dump/input.hpp>
#include <codrive/dump/line_format.hpp>
#include <codrive/dump/pcap.hpp>
#include <codrive/dump/stats.hpp>

#include <bitset>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

struct DumpOptions {
    LineOptions line;
    bool print = true;                 ///< per-frame lines (off for `-w` alone or `--top`)
    std::uint32_t only = kAllServices; ///< services printed (`--only`)
    std::bitset<kMaxNodeId + 1> nodes; ///< nodes printed (`--node`); none set = all
    bool stats = false;                ///< print the statistics table at the end
    bool report = false;               ///< keep the report's series, histograms and events
    std::uint32_t bitrate = 500000;    ///< for bus load
    DecoderOptions decoder;
};

/// Runs records through the decoder and writes the output in large chunks to `out`; problems
/// with the input (a bad line) go to `diag` in order with the output.
class Dumper {
public:
    using Sink = std::function<void(std::string_view)>;

    Dumper(DumpOptions options, Sink out, Sink diag);
    ~Dumper();

    [[nodiscard]] Decoder& decoder() { return decoder_; }
    [[nodiscard]] Stats& stats() { return stats_; }
    [[nodiscard]] const Stats& stats() const { return stats_; }
    [[nodiscard]] const DumpOptions& options() const { return options_; }
    /// Also writes every record to this pcap file.
    void set_pcap(std::unique_ptr<PcapWriter> writer) { pcap_ = std::move(writer); }

    void on_record(const TraceRecord& record);
    /// An input problem: "trace.log: line 12: bad data byte: '...'".
    void report(std::string_view message);
    /// Reports open transfers, prints statistics if asked, flushes.
    void finish();
    void flush();

private:
    [[nodiscard]] bool wanted(Service s, NodeId node) const;
    void emit_notes();
    void record_event(std::optional<std::int64_t> ts_ns, NodeId node, Service service,
                      Severity severity, std::string_view text);

    DumpOptions options_;
    Sink out_;
    Sink diag_;
    Stats stats_;
    Decoder decoder_;
    LineFormatter lines_;
    Decoded decoded_;
    std::vector<Note> notes_;
    fmt::memory_buffer buf_;
    std::unique_ptr<PcapWriter> pcap_;
    bool finished_ = false;
};

/// Counts from reading one input.
struct InputSummary {
    std::uint64_t frames = 0;
    std::uint64_t malformed = 0;
    bool fatal = false;
};

/// Reads a trace in any format open_trace_reader() recognises (candump log/screen, PEAK trc,
/// Vector asc, CSV, pcap/pcapng; detected from the content) into `dumper`. Each bad line or
/// record is reported through Dumper::report as "name:12: cause" (text) or "name: pcap record
/// 3: cause" and skipped;
/// a truncated or unreadable container ends the input with a report and `fatal`.
InputSummary dump_input(BufferedInput& input, std::string_view name, Dumper& dumper);

} // namespace codrive::dump
