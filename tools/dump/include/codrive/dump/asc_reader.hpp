// SPDX-License-Identifier: Apache-2.0
// Vector ASCII logging files (.asc, CANoe/CANalyzer and the tools that write the same format).
#pragma once

#include <codrive/dump/text_reader.hpp>

#include <cstdint>
#include <string>

namespace codrive::dump {

/// Reads a Vector ASC log. Header: `date <weekday> <month> <day> <time> [am|pm] <year>` gives the
/// start of the measurement (English or German month names; taken as UTC), `base hex|dec` the
/// number base of ids and data, `timestamps absolute|relative` whether each event's time is
/// since the start or since the previous event. Without a usable date the timestamps count from
/// the start of the measurement.
///
/// Events read: classic frames `<time> <ch> <id>[x] Rx|Tx d <dlc> <bytes>...` (a trailing `x`
/// marks a 29-bit id), remote frames `... Rx r [<dlc>]`, error frames `<time> <ch> ErrorFrame`,
/// and CAN FD events `<time> CANFD <ch> Rx|Tx <id>[x] [<name>] <brs> <esi> <dlc> <len> <bytes>...
/// <duration> <bitcount> <flags> ...` (flags without EDL 0x1000: a classic frame on an FD
/// channel; 0x10: remote). Other events (statistics, status, trigger blocks, comments) are
/// skipped. The interface is named `can<channel>`.
class AscReader final : public TextTraceReader {
public:
    explicit AscReader(BufferedInput& input) : TextTraceReader(input) {}

protected:
    LineStatus parse_line(std::string_view line, TraceRecord& out, std::string& why) override;

private:
    LineStatus parse_date(std::string_view rest, std::string& why);
    bool parse_id(std::string_view tok, Frame& f) const;
    bool parse_byte(std::string_view tok, std::uint8_t& b) const;
    LineStatus parse_fd(std::string_view rest, TraceRecord& out, std::string& why);
    /// Sets the record's time (the date plus `t_ns`, summed when relative); Error past 2255.
    LineStatus stamp(std::int64_t t_ns, TraceRecord& out, std::string& why);

    bool hex_ = true;
    bool relative_ = false;
    std::int64_t start_ns_ = 0;
    std::int64_t last_ns_ = 0;
    std::string iface_;
};

} // namespace codrive::dump
