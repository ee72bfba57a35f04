// SPDX-License-Identifier: Apache-2.0
// The HTML report page around the JSON data, with uPlot and the page script inlined.
#include <codrive/dump/report_assets.hpp>
#include <codrive/dump/report_html.hpp>

#include <string_view>

namespace codrive::dump {
namespace {

void html_text(std::string& out, std::string_view s) {
    for (char c : s) {
        switch (c) {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        default:
            out += c;
        }
    }
}

} // namespace

std::string_view report_uplot_version() {
    return assets::kUplotVersion;
}

std::string report_html(const Stats& stats, const ReportInfo& info) {
    const std::string data = report_json(stats, info);
    std::string out;
    out.reserve(data.size() + sizeof(assets::kUplotJs) + 16384);
    out += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>";
    out += "codrive-dump report: ";
    html_text(out, info.source);
    out += "</title>\n<style>\n";
    out += assets::kUplotCss;
    out += "\n</style>\n<style>\n";
    out += assets::kReportCss;
    out += "\n</style>\n</head>\n<body>\n<h1>CANopen trace report: ";
    html_text(out, info.source);
    out += "</h1>\n<p id=\"summary\"></p>\n"
           // Script errors are collected for the summary that tests read (#codrive-check).
           "<script>\nwindow.codriveErrors = [];\n"
           "window.addEventListener('error', function (e) { window.codriveErrors.push(String("
           "e.message)); });\n"
           "(function () { var ce = console.error; console.error = function () { "
           "window.codriveErrors.push(Array.prototype.join.call(arguments, ' ')); "
           "ce.apply(console, arguments); }; })();\n</script>\n"
           "<h2>Nodes</h2>\n<div class=\"wide\"><table id=\"nodes\"></table></div>\n"
           "<p class=\"note\">Rows are the nodes that sent something. Identity from 1018h uploads "
           "in the trace or an EDS; jitter is the standard deviation of the heartbeat "
           "interval; SDO times run from the request to the response that completes the "
           "transfer; SYNC→TPDO is the time from a SYNC to each TPDO of the node within the "
           "following SYNC period.</p>\n"
           "<h2>Bus load</h2>\n<div class=\"chart\" id=\"chart-load\"></div>\n"
           "<h2>Heartbeats</h2>\n<div class=\"chart\" id=\"chart-hb\"></div>\n"
           "<h2>SYNC</h2>\n<div class=\"chart\" id=\"chart-sync\"></div>\n"
           "<h2>SDO round trips</h2>\n<div class=\"chart\" id=\"chart-sdo\"></div>\n"
           "<h2>PDOs</h2>\n<div class=\"chart\" id=\"chart-pdo\"></div>\n"
           "<div class=\"chart\" id=\"chart-latency\"></div>\n"
           "<h2>EMCY and anomalies</h2>\n<div class=\"chart\" id=\"chart-events\"></div>\n"
           "<div id=\"events-box\"><table id=\"events\"></table></div>\n"
           "<p class=\"note\" id=\"events-more\"></p>\n"
           "<pre id=\"codrive-check\" hidden></pre>\n<script>\n";
    out += assets::kUplotJs;
    out += "\n</script>\n<script type=\"application/json\" id=\"codrive-data\">";
    out += data;
    out += "</script>\n<script>\n";
    out += assets::kReportJs;
    out += "\n</script>\n</body>\n</html>\n";
    return out;
}

} // namespace codrive::dump
