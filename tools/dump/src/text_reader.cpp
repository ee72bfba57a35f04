// SPDX-License-Identifier: Apache-2.0
// The line loop of the text trace readers.
#include <codrive/dump/text_reader.hpp>

#include <fmt/format.h>

namespace codrive::dump {

ReadStatus TextTraceReader::next(TraceRecord& record) {
    if (frames_ == 0 && failed_before_frames_ >= kUnreadableLinesToStop) {
        return ReadStatus::Fatal; // stopped: error() still says why
    }
    std::string_view line;
    bool too_long = false;
    std::string why;
    while (input_.next_line(line, too_long)) {
        ++line_no_;
        if (too_long) {
            error_ = fmt::format("{}: longer than {} bytes, skipped", line_no_, input_.capacity());
            return ReadStatus::Malformed;
        }
        if (line_no_ == 1 && line.size() >= 3 && line.substr(0, 3) == "\xEF\xBB\xBF") {
            line.remove_prefix(3); // a UTF-8 byte-order mark (Windows tools write one)
        }
        switch (parse_line(line, record, why)) {
        case LineStatus::Frame:
            ++frames_;
            return ReadStatus::Frame;
        case LineStatus::Skip:
            continue;
        case LineStatus::Error: {
            // Shown printable only: a binary file read as text must not garble the terminal.
            std::string shown;
            for (char c : line.substr(0, 80)) {
                shown += (c >= 0x20 && c < 0x7F) ? c : '?';
            }
            if (frames_ == 0 && ++failed_before_frames_ == kUnreadableLinesToStop) {
                error_ = fmt::format(
                    "{}: no trace format codrive-dump reads: none of the first {} lines that "
                    "are not comments could be read, so reading stops (this one: {}: '{}'); "
                    "docs/codrive-dump.md lists the formats",
                    line_no_, kUnreadableLinesToStop, why, shown);
                return ReadStatus::Fatal;
            }
            error_ = fmt::format("{}: {}: '{}'", line_no_, why, shown);
            return ReadStatus::Malformed;
        }
        }
    }
    if (!input_.read_error().empty()) {
        error_ = fmt::format("{}: read error: {}", line_no_, input_.read_error());
        return ReadStatus::Fatal;
    }
    return ReadStatus::End;
}

} // namespace codrive::dump
