// SPDX-License-Identifier: Apache-2.0
// CAN traces exported as CSV (SavvyCAN, python-can, HMS/IXXAT, any export naming its columns).
#pragma once

#include <codrive/dump/text_reader.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace codrive::dump {

/// True if `line` is a CSV header this reader understands: ',' or ';' separated, with an id
/// column and a data column (or per-byte columns).
[[nodiscard]] bool looks_like_csv_header(std::string_view line);

/// Reads a CSV trace whose first line names the columns (case does not matter):
///  - time: a name containing `time`; seconds, unless the name says `ms` or `us`/`µs`, or is
///    SavvyCAN's `Time Stamp` (microseconds); seconds may be written `s.ms.µs.ns` with dots
///    between groups of three digits (`12.345.678.901`, HMS/IXXAT exports' `Time (abs)`);
///  - id: `id`, `arbitration_id`, `can id`, `identifier`, `id (hex)`, `message id` (hex, with or
///    without `0x`, a trailing `h` allowed);
///  - `extended`/`ext`/`ide`, `remote`/`rtr`, `error`/`is_error_frame`: `1`, `true`, `yes`,
///    `x` mean set (without an extended column, an id above 7FF or written with 8 digits is
///    29-bit);
///  - length: `dlc`, `len`, `length`, `data length`;
///  - data: one `data` column (hex bytes with or without spaces; base64 in python-can files,
///    recognised by their `arbitration_id` column) or one column per byte (`D1`..`D8`,
///    `D0`..`D7`, `Byte0`.., `Data0`..);
///  - `bus`/`channel`: the interface is named `can<value>` (else `csv`).
/// Other columns are ignored. A CAN FD length (more than 8 bytes) makes the frame CAN FD.
class CsvReader final : public TextTraceReader {
public:
    explicit CsvReader(BufferedInput& input) : TextTraceReader(input) {}

protected:
    LineStatus parse_line(std::string_view line, TraceRecord& out, std::string& why) override;

private:
    LineStatus parse_header(std::string_view line, std::string& why);
    enum class Role : std::uint8_t {
        Ignore,
        Time,
        Id,
        Extended,
        Remote,
        Error,
        Length,
        Data,
        Byte,
        Bus
    };
    bool header_done_ = false;
    char sep_ = ',';
    bool base64_ = false;
    bool ids_padded_to_8_ = false; ///< 8 id digits do not mean 29-bit (SavvyCAN's generic CSV)
    std::int64_t time_unit_ns_ = 1'000'000'000;
    std::vector<Role> roles_;
    std::string iface_;
};

} // namespace codrive::dump
