// SPDX-License-Identifier: Apache-2.0
// The codrive-dump pipeline.
#include <codrive/dump/dumper.hpp>

#include <codrive/dump/trace_format.hpp>

namespace codrive::dump {
namespace {
constexpr std::size_t kFlushAt = 256 * 1024;
}

Dumper::Dumper(DumpOptions options, Sink out, Sink diag)
    : options_(std::move(options)), out_(std::move(out)), diag_(std::move(diag)),
      stats_(options_.bitrate), decoder_(options_.decoder, &stats_), lines_(options_.line) {
    if (options_.report) {
        stats_.enable_report();
    }
}

Dumper::~Dumper() {
    flush();
}

bool Dumper::wanted(Service s, NodeId node) const {
    if ((options_.only & (1U << static_cast<unsigned>(s))) == 0) {
        return false;
    }
    if (options_.nodes.none()) {
        return true;
    }
    // NMT commands to all nodes (node 0) concern every node.
    return (node == 0 && s == Service::Nmt) || (node <= kMaxNodeId && options_.nodes.test(node));
}

// Warnings, errors and EMCYs go to the report's timeline with their decoded text.
void Dumper::record_event(std::optional<std::int64_t> ts_ns, NodeId node, Service service,
                          Severity severity, std::string_view text) {
    if (options_.report && (severity >= Severity::Warning || service == Service::Emcy)) {
        stats_.on_event(ts_ns, node, service == Service::Emcy, to_string(severity),
                        to_string(service), text);
    }
}

void Dumper::emit_notes() {
    for (const auto& n : notes_) {
        record_event(n.timed ? std::optional(n.ts_ns) : std::nullopt, n.node, n.service, n.severity,
                     n.text);
        // A step in time is shown whatever --only and --node keep: it explains the times and
        // timeouts of every service after it.
        if (options_.print && (wanted(n.service, n.node) || n.event == "time step")) {
            lines_.note(buf_, n);
        }
    }
    notes_.clear();
}

void Dumper::on_record(const TraceRecord& r) {
    decoder_.decode(r, decoded_, notes_);
    if (!notes_.empty()) {
        emit_notes(); // they happened before this frame
    }
    record_event(decoded_.timed ? std::optional(r.ts_ns) : std::nullopt, decoded_.node,
                 decoded_.service, decoded_.severity,
                 std::string_view(decoded_.text.data(), decoded_.text.size()));
    if (pcap_) {
        pcap_->write(r);
    }
    if (options_.print && wanted(decoded_.service, decoded_.node)) {
        lines_.frame(buf_, r, decoded_);
        if (buf_.size() >= kFlushAt) {
            flush();
        }
    }
}

void Dumper::report(std::string_view message) {
    flush();
    if (diag_) {
        diag_(message);
    }
}

void Dumper::finish() {
    if (finished_) {
        return;
    }
    finished_ = true;
    decoder_.finish(notes_);
    emit_notes();
    if (options_.stats) {
        const auto t = stats_.table();
        if (options_.print) {
            buf_.push_back('\n');
        }
        buf_.append(t.data(), t.data() + t.size());
    }
    flush();
    if (pcap_) {
        if (auto r = pcap_->flush(); !r) {
            report("cannot write the pcap file: " + r.error().message());
        }
    }
}

void Dumper::flush() {
    if (buf_.size() != 0 && out_) {
        out_(std::string_view(buf_.data(), buf_.size()));
    }
    buf_.clear();
}

namespace {

// A read error the reader did not name itself (a binary reader sees only a short file; a cut
// gzip stream reads as one): one more line with the cause. True if there was one.
bool report_read_error(const BufferedInput& input, std::string_view name, std::string_view said,
                       Dumper& dumper) {
    const auto& err = input.read_error();
    if (err.empty() || said.find(err) != std::string_view::npos) {
        return !err.empty();
    }
    dumper.report(fmt::format("{}: read error: {}", name, err));
    return true;
}

} // namespace

InputSummary dump_input(BufferedInput& input, std::string_view name, Dumper& dumper) {
    InputSummary sum;
    const auto n = input.ensure(kCompressionMagicBytes);
    if (const auto tool = other_compression(input.data(), n); !tool.empty()) {
        dumper.report(fmt::format(
            "{}: the file is {}-compressed; codrive-dump inflates gzip only: "
            "decompress it first ({})",
            name, tool, tool == "zip" ? std::string("unzip") : fmt::format("{} -d", tool)));
        sum.fatal = true;
        return sum;
    }
    auto source = open_trace_reader(input);
    // Text readers name the line ("trace.trc:12: ..."), container readers the record.
    const std::string_view sep = source->line_numbered() ? ":" : ": ";
    TraceRecord rec;
    for (;;) {
        switch (source->next(rec)) {
        case ReadStatus::Frame:
            ++sum.frames;
            dumper.on_record(rec);
            continue;
        case ReadStatus::Malformed:
            ++sum.malformed;
            dumper.report(fmt::format("{}{}{}", name, sep, source->error()));
            continue;
        case ReadStatus::Fatal:
            sum.fatal = true;
            dumper.report(fmt::format("{}{}{}", name, sep, source->error()));
            report_read_error(input, name, source->error(), dumper);
            return sum;
        case ReadStatus::End:
            sum.fatal = report_read_error(input, name, {}, dumper);
            return sum;
        }
    }
}

} // namespace codrive::dump
