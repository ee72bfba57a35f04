// SPDX-License-Identifier: Apache-2.0
// `codrive sdo read|write|serve`: SDO access from the command line (CiA 301 §7.2.4), over CAN or
// over EtherCAT CoE (`--ethercat IFACE`, `-n` = slave position from 1).
#include "cli_common.hpp"
#include "command_registry.hpp"
#include "ecat_session.hpp"
#include "sdo_cli_format.hpp"
#include "sdo_progress.hpp"
#include "sdo_serve.hpp"

#include <codrive/sdo/blocking.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <iterator>
#include <memory>

namespace codrive::cli {
namespace {

struct SdoOptions {
    std::string iface;
    std::string ethercat; ///< EtherCAT interface instead of a CAN one
    std::string node;
    std::string object;
    std::string type;
    std::string value;
    std::string file;
    std::string output;
    std::string eds;
    bool block = false;
    unsigned timeout_ms = 1000;
};

struct Prepared {
    NodeId node = 0;
    Multiplexer mux;
    std::optional<SdoValueType> type;
    std::unique_ptr<sdo::BlockingSdo> sdo;
    sdo::TransferOptions transfer;
};

/// Parses node, object, type and timeout; prints the problem and returns false.
bool parse_args(const SdoOptions& o, Prepared& p) {
    const auto node = parse_node(o.node);
    if (!node) {
        return false;
    }
    p.node = static_cast<NodeId>(*node);
    const auto mux = parse_multiplexer(o.object);
    if (!mux) {
        fmt::print(stderr,
                   "codrive: '{}' is not an object address: use INDEX:SUB in hex, e.g. 0x1018:1 "
                   "or 1018:01\n",
                   o.object);
        return false;
    }
    p.mux = *mux;
    if (!o.type.empty()) {
        p.type = parse_value_type(o.type);
        if (!p.type) {
            fmt::print(stderr,
                       "codrive: unknown type '{}' (use u8 u16 u32 u64 i8 i16 i32 i64 f32 f64 str "
                       "hex domain)\n",
                       o.type);
            return false;
        }
    }
    if (o.timeout_ms == 0) {
        fmt::print(stderr, "codrive: --timeout must be at least 1 ms\n");
        return false;
    }
    return true;
}

/// Parses the common arguments and opens the bus; prints the problem and returns nullopt.
std::optional<Prepared> prepare(const SdoOptions& o, int& exit_code, SdoProgressBar& bar) {
    Prepared p;
    exit_code = kExitUsage;
    if (!parse_args(o, p)) {
        return std::nullopt;
    }
    auto sdo = sdo::BlockingSdo::open(o.iface);
    if (!sdo) {
        fmt::print(stderr, "codrive: {}\n", describe_can_open_error(o.iface, sdo.error()));
        exit_code = kExitNoBus;
        return std::nullopt;
    }
    p.sdo = std::move(*sdo);
    // Ctrl-C or SIGTERM during a transfer aborts it on the node too (abort 0x08000000), so a
    // long segmented or block transfer does not stay open there until its timeout.
    catch_stop_signals();
    p.sdo->set_interrupt([]() -> std::optional<std::string> {
        if (const int sig = stop_signal(); sig != 0) {
            return fmt::format("interrupted by {}", signal_name(sig));
        }
        return std::nullopt;
    });
    p.transfer.mode = o.block ? sdo::Mode::Block : sdo::Mode::Auto;
    p.transfer.timeout = std::chrono::milliseconds(o.timeout_ms);
    p.transfer.progress = [&bar](std::size_t done, std::optional<std::size_t> total) {
        bar.update(done, total);
    };
    exit_code = kExitOk;
    return p;
}

int report(const sdo::SdoError& e, SdoProgressBar& bar) {
    bar.finish();
    fmt::print(stderr, "codrive: {}\n", e.to_string());
    return stop_requested() ? 128 + stop_signal() : kExitFailure; // 130 / 143 when interrupted
}

/// Prints read bytes as --type asks (raw for domain); `who` names the node or slave.
int print_read(const std::optional<SdoValueType>& type, const std::string& who,
               const Multiplexer& mux, std::span<const std::uint8_t> bytes) {
    if (!type) {
        fmt::print("{}\n", format_untyped(bytes));
        return kExitOk;
    }
    auto text = format_value(*type, bytes);
    if (!text) {
        fmt::print(stderr, "codrive: {}: 0x{:04X}:{:02X}: {}\n", who, mux.index, mux.subindex,
                   text.error());
        return kExitFailure;
    }
    if (*type == SdoValueType::Domain) {
        std::fwrite(text->data(), 1, text->size(), stdout);
    } else {
        fmt::print("{}\n", *text);
    }
    return kExitOk;
}

/// The EtherCAT session of --ethercat with the slave selected by -n (a position from 1) in
/// PRE-OP; prints the problem and returns nullopt.
struct CoeTarget {
    EcatSession session;
    std::size_t slave = 0;
};
std::optional<CoeTarget> open_coe(const SdoOptions& o, Prepared& p, int& exit_code) {
    exit_code = kExitUsage;
    if (!parse_args(o, p)) {
        return std::nullopt;
    }
    if (o.block) {
        fmt::print(stderr, "codrive: --block is a CANopen SDO transfer; CoE chooses expedited, "
                           "normal or segmented by itself\n");
        return std::nullopt;
    }
    exit_code = kExitNoBus;
    auto s = open_segment(o.ethercat, 1);
    if (!s) {
        return std::nullopt;
    }
    exit_code = kExitFailure;
    s->master->config().mailbox_timeout = std::chrono::milliseconds(o.timeout_ms);
    const auto slave = slave_for_coe(*s->master, p.node, 1);
    if (!slave) {
        return std::nullopt;
    }
    exit_code = kExitOk;
    return CoeTarget{std::move(*s), *slave};
}

int run_read_coe(const SdoOptions& o) {
    Prepared p;
    int rc = kExitOk;
    auto t = open_coe(o, p, rc);
    if (!t) {
        return rc;
    }
    ethercat::Master& m = *t->session.master;
    auto data = m.sdo_upload(t->slave, p.mux.index, p.mux.subindex);
    if (!data) {
        fmt::print(stderr, "codrive: {}\n", m.last_error());
        return kExitFailure;
    }
    if (!o.output.empty()) {
        std::ofstream f(o.output, std::ios::binary);
        f.write(reinterpret_cast<const char*>(data->data()),
                static_cast<std::streamsize>(data->size()));
        if (!f) {
            fmt::print(stderr, "codrive: writing {} failed\n", o.output);
            return kExitFailure;
        }
        return kExitOk;
    }
    return print_read(p.type, m.slave_label(t->slave), p.mux, *data);
}

int run_write_coe(const SdoOptions& o) {
    Prepared p;
    int rc = kExitOk;
    auto t = open_coe(o, p, rc);
    if (!t) {
        return rc;
    }
    std::vector<std::uint8_t> bytes;
    if (!o.file.empty()) {
        std::ifstream f(o.file, std::ios::binary);
        if (!f) {
            fmt::print(stderr, "codrive: cannot read {}\n", o.file);
            return kExitUsage;
        }
        bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    } else {
        auto b = encode_value(*p.type, o.value);
        if (!b) {
            fmt::print(stderr, "codrive: {}\n", b.error());
            return kExitUsage;
        }
        bytes = std::move(*b);
    }
    ethercat::Master& m = *t->session.master;
    if (!m.sdo_download(t->slave, p.mux.index, p.mux.subindex, bytes)) {
        fmt::print(stderr, "codrive: {}\n", m.last_error());
        return kExitFailure;
    }
    return kExitOk;
}

/// -i or --ethercat, one of them.
bool has_wire(const SdoOptions& o) {
    if (o.iface.empty() && o.ethercat.empty()) {
        fmt::print(stderr, "codrive: sdo needs -i IFACE (CAN) or --ethercat IFACE\n");
        return false;
    }
    return true;
}

int run_read(const SdoOptions& o) {
    if (!has_wire(o)) {
        return kExitUsage;
    }
    if (!o.ethercat.empty()) {
        return run_read_coe(o);
    }
    int rc = kExitOk;
    SdoProgressBar bar;
    auto p = prepare(o, rc, bar);
    if (!p) {
        return rc;
    }
    if (!o.output.empty()) {
        std::FILE* f = std::fopen(o.output.c_str(), "wb");
        if (f == nullptr) {
            fmt::print(stderr, "codrive: cannot create {}: {}\n", o.output, std::strerror(errno));
            return kExitUsage;
        }
        auto r =
            p->sdo->upload(p->node, p->mux.index, p->mux.subindex, sdo::file_sink(f), p->transfer);
        const bool closed = std::fclose(f) == 0;
        if (!r) {
            return report(r.error(), bar);
        }
        bar.finish();
        if (!closed) {
            fmt::print(stderr, "codrive: writing {} failed: {}\n", o.output, std::strerror(errno));
            return kExitFailure;
        }
        return kExitOk;
    }
    auto r = p->sdo->upload(p->node, p->mux.index, p->mux.subindex, p->transfer);
    if (!r) {
        return report(r.error(), bar);
    }
    bar.finish();
    return print_read(p->type, fmt::format("node {}", p->node), p->mux, *r);
}

int run_write(const SdoOptions& o) {
    if (!has_wire(o)) {
        return kExitUsage;
    }
    if (o.file.empty() == o.value.empty()) {
        fmt::print(stderr, "codrive: sdo write needs either VALUE (with --type) or --file FILE\n");
        return kExitUsage;
    }
    if (!o.value.empty() && o.type.empty()) {
        fmt::print(stderr, "codrive: sdo write VALUE needs --type T (u8 u16 u32 u64 i8 i16 i32 "
                           "i64 f32 f64 str hex domain)\n");
        return kExitUsage;
    }
    if (!o.ethercat.empty()) {
        return run_write_coe(o);
    }
    int rc = kExitOk;
    SdoProgressBar bar;
    auto p = prepare(o, rc, bar);
    if (!p) {
        return rc;
    }
    sdo::DownloadSource source;
    if (!o.file.empty()) {
        auto s = sdo::file_source(o.file);
        if (!s) {
            fmt::print(stderr, "codrive: cannot read {}: {}\n", o.file, s.error().message());
            return kExitUsage;
        }
        source = std::move(*s);
    } else {
        auto bytes = encode_value(*p->type, o.value);
        if (!bytes) {
            fmt::print(stderr, "codrive: {}\n", bytes.error());
            return kExitUsage;
        }
        source = sdo::bytes_source(std::move(*bytes));
    }
    auto r =
        p->sdo->download(p->node, p->mux.index, p->mux.subindex, std::move(source), p->transfer);
    if (!r) {
        return report(r.error(), bar);
    }
    bar.finish();
    return kExitOk;
}

int run_serve(const SdoOptions& o) {
    if (!o.ethercat.empty()) {
        fmt::print(stderr, "codrive: sdo serve answers on CAN only (-i IFACE); the simulated "
                           "EtherCAT slaves are codrive-ecat-sim\n");
        return kExitUsage;
    }
    if (!has_wire(o)) {
        return kExitUsage;
    }
    const auto node = parse_node(o.node);
    if (!node) {
        return kExitUsage;
    }
    return run_sdo_serve(o.iface, static_cast<NodeId>(*node), o.eds);
}

constexpr const char* kInterruptFooter =
    "Ctrl-C (SIGINT) or SIGTERM during a CAN transfer: the node is sent SDO abort 0x08000000 and "
    "the command exits 130 / 143.";

void add_common(CLI::App* cmd, SdoOptions& o) {
    auto* can = cmd->add_option("-i,--iface", o.iface, "CAN interface");
    auto* ecat = cmd->add_option("--ethercat", o.ethercat,
                                 "EtherCAT: network interface of the segment (CoE SDO)");
    can->excludes(ecat);
    cmd->add_option("-n,--node", o.node, "Node id 1..127 (EtherCAT: slave position from 1)")
        ->required();
}

void install_sdo(CLI::App& app, int& exit_code) {
    auto opts = std::make_shared<SdoOptions>();
    auto* sdo = app.add_subcommand("sdo", "Read or write objects by SDO, or serve a dictionary");
    sdo->require_subcommand(1);

    auto* read = sdo->add_subcommand("read", "Upload INDEX:SUB from a node and print it");
    add_common(read, *opts);
    read->add_option("object", opts->object, "INDEX:SUB in hex, e.g. 0x1018:1")->required();
    read->add_option("--type", opts->type,
                     "u8 u16 u32 u64 i8 i16 i32 i64 f32 f64 str hex domain (default: hex bytes)");
    read->add_flag("--block", opts->block, "Use an SDO block upload");
    read->add_option("--timeout", opts->timeout_ms, "Response timeout in ms (default 1000)");
    read->add_option("-o,--output", opts->output, "Write the raw bytes to FILE");
    read->footer(kInterruptFooter);
    read->callback([opts, &exit_code] { exit_code = run_read(*opts); });

    auto* write = sdo->add_subcommand("write", "Download a value or a file to INDEX:SUB");
    add_common(write, *opts);
    write->add_option("object", opts->object, "INDEX:SUB in hex, e.g. 0x2000:0")->required();
    write->add_option("value", opts->value, "The value, in the form --type asks for");
    write->add_option("--type", opts->type, "u8 u16 u32 u64 i8 i16 i32 i64 f32 f64 str hex domain");
    write->add_option("--file", opts->file, "Download the contents of FILE");
    write->add_flag("--block", opts->block, "Use an SDO block download");
    write->add_option("--timeout", opts->timeout_ms, "Response timeout in ms (default 1000)");
    write->footer(kInterruptFooter);
    write->callback([opts, &exit_code] { exit_code = run_write(*opts); });

    auto* serve = sdo->add_subcommand(
        "serve", "Run an SDO server for NODE with a small built-in dictionary (or --eds FILE)");
    add_common(serve, *opts);
    serve->add_option("--eds", opts->eds, "Serve the dictionary of this EDS/DCF file");
    serve->callback([opts, &exit_code] { exit_code = run_serve(*opts); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_sdo;
CODRIVE_REGISTER_COMMAND(install_sdo);
