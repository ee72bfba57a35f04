// SPDX-License-Identifier: Apache-2.0
// codrive-dump: a candump-style CANopen analyser for live interfaces and capture files.
#include <codrive/core/cob_id.hpp>
#include <codrive/core/eds.hpp>
#include <codrive/core/value.hpp>
#include <codrive/dump/drive_profiles.hpp>
#include <codrive/dump/dumper.hpp>
#include <codrive/dump/live.hpp>
#ifdef CODRIVE_DUMP_HAS_REPORT
#include <codrive/dump/report_html.hpp>
#endif

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace {

using namespace codrive;
using namespace codrive::dump;

std::atomic<bool> g_stop{false};

void on_signal(int /*sig*/) {
    g_stop.store(true);
}

void write_all(int fd, std::string_view s) {
    while (!s.empty()) {
        const ssize_t n = ::write(fd, s.data(), s.size());
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return; // EPIPE (e.g. piped into head): nothing more to do
        }
        s.remove_prefix(static_cast<std::size_t>(n));
    }
}

void diag(std::string_view s) {
    std::string line = "codrive-dump: ";
    line += s;
    line += '\n';
    write_all(2, line);
}

bool split_node_arg(const std::string& arg, NodeId& node, std::string& rest) {
    const auto eq = arg.find('=');
    if (eq == std::string::npos) {
        return false;
    }
    const auto n = parse_uint(arg.substr(0, eq));
    if (!n || !valid_node_id(static_cast<unsigned>(*n))) {
        return false;
    }
    node = static_cast<NodeId>(*n);
    rest = arg.substr(eq + 1);
    return !rest.empty();
}

// Writes the HTML report to a file opened before the trace was read; false after telling why.
bool write_report(std::FILE* file, const std::string& path, const Dumper& dumper,
                  const std::string& source) {
#ifdef CODRIVE_DUMP_HAS_REPORT
    const std::string html =
        report_html(dumper.stats(), ReportInfo{source, "codrive-dump " CODRIVE_VERSION});
    const bool ok = std::fwrite(html.data(), 1, html.size(), file) == html.size();
    if (std::fclose(file) != 0 || !ok) {
        diag(fmt::format("--report: cannot write {}: {}", path, std::strerror(errno)));
        return false;
    }
    diag(fmt::format("report written to {} ({} bytes)", path, html.size()));
    return true;
#else
    (void)file;
    (void)path;
    (void)dumper;
    (void)source;
    return false;
#endif
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"codrive-dump: decode CANopen traffic live from SocketCAN interfaces or from "
                 "trace files (candump, PEAK trc, Vector asc and blf, CSV, pcap/pcapng)"};
    app.set_version_flag("--version", "codrive-dump " CODRIVE_VERSION);
    std::vector<std::string> ifaces;
    std::string read_file;
    std::string write_file;
    bool print_too = false;
    std::string time_mode = "a";
    std::string color = "auto";
    bool json = false;
    std::string only;
    std::vector<unsigned> nodes;
    std::vector<std::string> eds_args;
    std::vector<std::string> profile_args;
    bool stats = false;
    bool top = false;
    bool quiet = false;
    std::uint32_t bitrate = 500000;
    unsigned sdo_timeout_ms = 1000;
    std::uint64_t count = 0;
    std::string report_file;

    app.add_option("interfaces", ifaces,
                   "SocketCAN interfaces to capture, with optional candump filters "
                   "(vcan0,0x580:0x780), or 'any'");
    app.add_option("-r,--read", read_file,
                   "Read a trace file: candump log/screen, PEAK .trc, Vector .asc and .blf, "
                   "CSV, pcap/pcapng, each also gzip-compressed, recognised by content ('-' for "
                   "stdin)");
    app.add_option("-w,--write", write_file,
                   "Write the frames to a pcap file, pcapng if the name ends in .pcapng "
                   "(SocketCAN link type) for Wireshark; printing stops unless --print");
    app.add_flag("--print", print_too, "Print decoded lines even when writing a pcap file");
    app.add_option("-t,--time", time_mode, "Timestamps: a absolute, d delta, z from zero, n none")
        ->capture_default_str();
    app.add_option("--color", color, "Colours: auto, always, never")->capture_default_str();
    app.add_flag("--json", json, "Write one JSON object per frame");
    app.add_option("--only", only,
                   "Print only these services: nmt,sync,time,emcy,hb,sdo,pdo,"
                   "lss,other,error");
    app.add_option("--node", nodes, "Print only frames of these nodes (repeatable)");
    app.add_option("--eds", eds_args,
                   "NODE=FILE: object names, types and PDO mappings of a "
                   "node from its EDS or DCF (repeatable)");
    app.add_option("--profile", profile_args, "NODE=NAME: use a drive profile for a node");
    app.add_flag("--stats", stats, "Print a per-node statistics table at the end");
    app.add_flag("-q,--quiet", quiet, "No per-frame lines: with --stats only the table at the end");
    app.add_option("--report", report_file,
                   "Write an HTML report at the end: bus load, heartbeats, SYNC, SDO and PDO "
                   "timing, EMCY/anomaly timeline, node table (one self-contained file)");
    app.add_flag("--top", top, "Live: show the statistics table, refreshed every second");
    app.add_option("--bitrate", bitrate, "Bit rate for the bus load figure")
        ->capture_default_str()
        ->check(CLI::Range(1U, 1'000'000'000U));
    app.add_option("--sdo-timeout", sdo_timeout_ms,
                   "Report SDO requests unanswered after this many ms")
        ->capture_default_str();
    app.add_option("-n,--count", count, "Live: stop after this many frames");
    CLI11_PARSE(app, argc, argv);

    DumpOptions opts;
    if (time_mode == "a") {
        opts.line.time = TimeMode::Absolute;
    } else if (time_mode == "d") {
        opts.line.time = TimeMode::Delta;
    } else if (time_mode == "z") {
        opts.line.time = TimeMode::Zero;
    } else if (time_mode == "n") {
        opts.line.time = TimeMode::None;
    } else {
        diag(fmt::format("-t must be a, d, z or n, not '{}'", time_mode));
        return 2;
    }
    if (color == "always") {
        opts.line.color = true;
    } else if (color == "auto") {
        opts.line.color = ::isatty(1) != 0 && !json;
    } else if (color != "never") {
        diag(fmt::format("--color must be auto, always or never, not '{}'", color));
        return 2;
    }
    opts.line.json = json;
    if (!only.empty()) {
        std::string bad;
        const auto mask = parse_service_list(only, bad);
        if (!mask) {
            diag(fmt::format("--only: unknown service '{}' (use nmt,sync,time,emcy,hb,sdo,pdo,"
                             "lss,other,error)",
                             bad));
            return 2;
        }
        opts.only = *mask;
    }
    for (unsigned n : nodes) {
        if (!valid_node_id(n)) {
            diag(fmt::format("--node {}: a node id is 1..127", n));
            return 2;
        }
        opts.nodes.set(n);
    }
    opts.stats = stats || top;
    opts.bitrate = bitrate;
    opts.decoder.sdo_timeout_ns = static_cast<std::int64_t>(sdo_timeout_ms) * 1'000'000;
    opts.print = (write_file.empty() || print_too) && !top && !quiet;
    if (read_file.empty() == ifaces.empty()) {
        diag("give either interfaces to capture or -r FILE");
        return 2;
    }
    opts.report = !report_file.empty();
    std::FILE* report_out = nullptr;
    if (opts.report) {
#ifndef CODRIVE_DUMP_HAS_REPORT
        diag("--report: this codrive-dump was built without the HTML report (configured with "
             "CODRIVE_DUMP_REPORT=OFF, or npm was not found: see docs/codrive-dump.md)");
        return 2;
#endif
        // Opened now, so a path that cannot be written fails before a long trace is read.
        report_out = std::fopen(report_file.c_str(), "wb");
        if (report_out == nullptr) {
            diag(fmt::format("--report: cannot write {}: {}", report_file, std::strerror(errno)));
            return 2;
        }
    }

    Dumper dumper(
        opts, [](std::string_view s) { write_all(1, s); }, diag);
    ProfileRegistry profiles;
    register_drive_profiles(profiles);
    dumper.decoder().set_profiles(&profiles);
    for (const auto& arg : eds_args) {
        NodeId node = 0;
        std::string path;
        if (!split_node_arg(arg, node, path)) {
            diag(fmt::format("--eds '{}': expected NODE=FILE with NODE 1..127", arg));
            return 2;
        }
        auto desc = load_eds(path, node);
        if (!desc) {
            diag(fmt::format("--eds {}: cannot read {}: {}", node, path, desc.error().message()));
            return 2;
        }
        for (const auto& f : desc->findings) {
            if (f.severity == EdsSeverity::Error) {
                diag(format_finding(f));
            }
        }
        dumper.decoder().set_description(node,
                                         std::make_shared<DeviceDescription>(std::move(*desc)));
    }
    for (const auto& arg : profile_args) {
        NodeId node = 0;
        std::string name;
        if (!split_node_arg(arg, node, name)) {
            diag(fmt::format("--profile '{}': expected NODE=NAME with NODE 1..127", arg));
            return 2;
        }
        const auto* p = profiles.find(name);
        if (p == nullptr) {
            std::string names;
            for (const auto& known : profiles.all()) {
                names +=
                    names.empty() ? std::string(known->name()) : ", " + std::string(known->name());
            }
            diag(fmt::format("--profile {}: no profile named '{}' (known: {})", node, name, names));
            return 2;
        }
        dumper.decoder().set_profile(node, p);
    }
    if (!write_file.empty()) {
        auto w = PcapWriter::open(write_file);
        if (!w) {
            diag(fmt::format("cannot write {}: {}", write_file, w.error().message()));
            return 2;
        }
        dumper.set_pcap(std::move(*w));
    }
    std::signal(SIGPIPE, SIG_IGN);

    if (!read_file.empty()) {
        auto in = BufferedInput::open(read_file);
        if (!in) {
            diag(fmt::format("cannot read {}: {}", read_file, in.error().message()));
            return 2;
        }
        const auto sum = dump_input(**in, read_file == "-" ? "stdin" : read_file, dumper);
        dumper.finish();
        if (sum.malformed > 0) {
            diag(fmt::format("{}: {} of {} entries could not be parsed and were skipped", read_file,
                             sum.malformed, sum.malformed + sum.frames));
        }
        if (report_out != nullptr && !write_report(report_out, report_file, dumper,
                                                   read_file == "-" ? "stdin" : read_file)) {
            return 2;
        }
        return sum.fatal ? 1 : 0;
    }

    std::vector<LiveSpec> specs;
    for (const auto& arg : ifaces) {
        std::string err;
        auto spec = parse_live_spec(arg, err);
        if (!spec) {
            diag(err);
            return 2;
        }
        if (spec->iface == "any") {
            for (const auto& name : list_can_interfaces()) {
                LiveSpec s = *spec;
                s.iface = name;
                specs.push_back(std::move(s));
            }
            if (specs.empty()) {
                diag("any: this host has no CAN interfaces");
                return 2;
            }
        } else {
            specs.push_back(std::move(*spec));
        }
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    LiveOptions lo;
    lo.top = top;
    lo.count = count;
    lo.stop = &g_stop;
    lo.screen = [](std::string_view s) { write_all(1, s); };
    lo.clear_screen = ::isatty(1) != 0;
    lo.ready = [&] {
        std::string names;
        for (const auto& s : specs) {
            names += names.empty() ? s.iface : ", " + s.iface;
        }
        diag(fmt::format("listening on {}", names));
    };
    std::string err;
    if (auto r = run_live(specs, dumper, lo, err); !r) {
        diag(err);
        return 2;
    }
    dumper.finish();
    if (report_out != nullptr) {
        std::string names;
        for (const auto& sp : specs) {
            names += names.empty() ? sp.iface : ", " + sp.iface;
        }
        if (!write_report(report_out, report_file, dumper, names)) {
            return 2;
        }
    }
    return 0;
}
