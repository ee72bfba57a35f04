// SPDX-License-Identifier: Apache-2.0
// The data of `codrive-dump --report` as JSON: what the HTML page charts and tabulates.
#pragma once

#include <codrive/dump/stats.hpp>

#include <string>

namespace codrive::dump {

/// Where the data came from, for the page's heading.
struct ReportInfo {
    std::string source;    ///< the trace file or the interfaces
    std::string generator; ///< "codrive-dump 0.1.0"
};

/// The report's data as one JSON object (the layout is documented in docs/codrive-dump.md,
/// "HTML report"): bus load per time bucket, per-node rows (identity, NMT state, heartbeat,
/// EMCY, SDO, PDO rates, SYNC→TPDO latency) with their series and histograms, the SYNC period
/// histogram and the first events. Needs Stats::enable_report() before the trace; without it
/// the series are empty. `</` never appears in the text, so it can sit inside a `<script>`.
[[nodiscard]] std::string report_json(const Stats& stats, const ReportInfo& info);

} // namespace codrive::dump
