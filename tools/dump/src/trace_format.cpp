// SPDX-License-Identifier: Apache-2.0
// Trace format detection by content and the reader for each format.
#include <codrive/dump/trace_format.hpp>

#include <codrive/dump/asc_reader.hpp>
#include <codrive/dump/blf_reader.hpp>
#include <codrive/dump/csv_reader.hpp>
#include <codrive/dump/log_parser.hpp>
#include <codrive/dump/pcap.hpp>
#include <codrive/dump/text_scan.hpp>
#include <codrive/dump/trc_reader.hpp>

namespace codrive::dump {
namespace {

// An ASC event line: "<seconds.fraction> <channel> <id> Rx|Tx ..." or "<time> CANFD ...".
bool looks_like_asc_event(std::string_view line) {
    scan::Cursor c(line);
    const auto t = c.token();
    std::int64_t ns = 0;
    if (t.find('.') == std::string_view::npos || !scan::parse_seconds(t, ns)) {
        return false;
    }
    const auto ch = c.token();
    if (ch == "CANFD") {
        return true;
    }
    std::int64_t channel = 0;
    if (!scan::parse_digits(ch, channel)) {
        return false;
    }
    const auto id = c.token();
    const auto dir = c.token();
    return id == "ErrorFrame" || dir == "Rx" || dir == "Tx";
}

// True once the buffered bytes decide the format: a pcap magic number, a BLF signature, or a
// complete line that is neither blank nor a '#' comment.
bool decisive(const std::uint8_t* p, std::size_t n) {
    if (looks_like_pcap(p, n) || looks_like_blf(p, n)) {
        return true;
    }
    std::string_view text(reinterpret_cast<const char*>(p), n);
    for (auto nl = text.find('\n'); nl != std::string_view::npos; nl = text.find('\n')) {
        scan::Cursor c(text.substr(0, nl));
        c.skip_space();
        const auto rest = c.rest();
        if (!rest.empty() && rest != "\r" && rest.front() != '#') {
            return true;
        }
        text.remove_prefix(nl + 1);
    }
    return false;
}

} // namespace

std::string_view to_string(TraceFormat f) {
    switch (f) {
    case TraceFormat::Candump:
        return "candump";
    case TraceFormat::Pcap:
        return "pcap";
    case TraceFormat::PeakTrc:
        return "PEAK trc";
    case TraceFormat::VectorAsc:
        return "Vector asc";
    case TraceFormat::Csv:
        return "CSV";
    case TraceFormat::VectorBlf:
        return "Vector blf";
    }
    return "unknown";
}

TraceFormat detect_trace_format(const std::uint8_t* p, std::size_t n) {
    if (looks_like_pcap(p, n)) {
        return TraceFormat::Pcap;
    }
    if (looks_like_blf(p, n)) {
        return TraceFormat::VectorBlf;
    }
    std::string_view text(reinterpret_cast<const char*>(p), n);
    if (text.substr(0, 3) == "\xEF\xBB\xBF") {
        text.remove_prefix(3);
    }
    // The first non-blank line decides, except candump comments ('#'), which are passed over.
    for (int i = 0; i < 50 && !text.empty(); ++i) {
        const auto nl = text.find('\n');
        auto line = text.substr(0, nl);
        text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1);
        }
        scan::Cursor c(line);
        c.skip_space();
        const auto rest = c.rest();
        if (rest.empty() || rest.front() == '#') {
            continue;
        }
        if (rest.front() == ';') {
            return TraceFormat::PeakTrc;
        }
        if (rest.substr(0, 5) == "date " || rest.substr(0, 9) == "base hex " ||
            rest.substr(0, 9) == "base dec " || rest.substr(0, 10) == "// version" ||
            scan::istarts_with(rest, "begin triggerblock") || looks_like_asc_event(rest)) {
            return TraceFormat::VectorAsc;
        }
        if (looks_like_csv_header(rest)) {
            return TraceFormat::Csv;
        }
        return TraceFormat::Candump;
    }
    return TraceFormat::Candump;
}

std::unique_ptr<ITraceSource> open_trace_reader(BufferedInput& input, TraceFormat* detected) {
    // Read only as far as the first telling line: on a pipe (`candump -L can0 | codrive-dump -r
    // -`) waiting for a fixed amount would hold back the first lines.
    const std::size_t look = std::min<std::size_t>(input.capacity(), 64 * 1024);
    input.ensure(4);
    while (!input.at_eof() && input.available() < look &&
           !decisive(input.data(), input.available())) {
        input.ensure(input.available() + 1);
    }
    const auto format = detect_trace_format(input.data(), input.available());
    if (detected != nullptr) {
        *detected = format;
    }
    return make_trace_reader(format, input);
}

std::unique_ptr<ITraceSource> make_trace_reader(TraceFormat format, BufferedInput& input) {
    switch (format) {
    case TraceFormat::Pcap:
        return std::make_unique<PcapReader>(input);
    case TraceFormat::PeakTrc:
        return std::make_unique<TrcReader>(input);
    case TraceFormat::VectorAsc:
        return std::make_unique<AscReader>(input);
    case TraceFormat::Csv:
        return std::make_unique<CsvReader>(input);
    case TraceFormat::VectorBlf:
        return std::make_unique<BlfReader>(input);
    case TraceFormat::Candump:
        break;
    }
    return std::make_unique<LogReader>(input);
}

} // namespace codrive::dump
