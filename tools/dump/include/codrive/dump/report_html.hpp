// SPDX-License-Identifier: Apache-2.0
// `codrive-dump --report`: one self-contained HTML page (uPlot inlined) from the statistics.
#pragma once

#include <codrive/dump/report_data.hpp>

#include <string>

namespace codrive::dump {

/// The page: uPlot's script and style (inlined at build time), the data of report_json(), and
/// the script that draws the charts and tables. No external URL: it opens offline. Part of
/// `codrive_dump_report`, built when CODRIVE_DUMP_REPORT is on.
[[nodiscard]] std::string report_html(const Stats& stats, const ReportInfo& info);

/// The uPlot version inlined ("1.6.32").
[[nodiscard]] std::string_view report_uplot_version();

} // namespace codrive::dump
