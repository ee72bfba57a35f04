// SPDX-License-Identifier: Apache-2.0
// `codrive ecat foe read|write`: read a file from a slave or write one to it over FoE
// (ETG.1000.6 §5.7), e.g. the AKD2G's *.akd parameter file (manual §2.3.3.4), with progress on
// stderr and the failure as one sentence.
#include "cmd_ecat_foe.hpp"

#include "command_registry.hpp"
#include "ecat_session.hpp"
#include "sdo_progress.hpp"

#include <codrive/core/value.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

namespace codrive::cli {
namespace {

using namespace codrive::ethercat;

struct FoeCliOptions {
    std::string iface;
    unsigned position = 0;
    std::string name;  ///< the file's name on the slave
    std::string local; ///< write: the file to send; read: where to put it ("" = stdout)
    std::string password = "0";
    unsigned timeout_ms = 1000;
};

/// Opens the segment, brings the slave to PRE-OP (FoE needs the mailbox) and fills `options`;
/// prints the problem and returns the exit code otherwise.
struct FoeSession {
    EcatSession session;
    std::size_t slave = 0;
};

int open_for_foe(const FoeCliOptions& o, std::optional<FoeSession>& out, FoeOptions& options) {
    const auto password = parse_uint(o.password);
    if (!password || *password > 0xFFFFFFFFU) {
        fmt::print(stderr, "codrive: bad --password '{}' (a 32-bit number)\n", o.password);
        return kExitUsage;
    }
    if (o.timeout_ms == 0) {
        fmt::print(stderr, "codrive: --timeout must be at least 1 ms\n");
        return kExitUsage;
    }
    options.password = static_cast<std::uint32_t>(*password);
    auto s = open_segment(o.iface);
    if (!s) {
        return kExitNoBus;
    }
    s->master->config().mailbox_timeout = std::chrono::milliseconds(o.timeout_ms);
    const auto slave = slave_for_coe(*s->master, o.position, 0);
    if (!slave) {
        return kExitFailure;
    }
    out = FoeSession{std::move(*s), *slave};
    return kExitOk;
}

std::string rate(std::size_t bytes, TimePoint start) {
    const double secs = std::chrono::duration<double>(SteadyClock::now() - start).count();
    return fmt::format("{:.2f} s, {:.1f} kB/s", secs,
                       secs > 0 ? static_cast<double>(bytes) / 1000.0 / secs : 0.0);
}

int run_write(const FoeCliOptions& o) {
    std::ifstream in(o.local, std::ios::binary);
    if (!in) {
        fmt::print(stderr, "codrive: cannot read {}\n", o.local);
        return kExitUsage;
    }
    const std::vector<std::uint8_t> data((std::istreambuf_iterator<char>(in)), {});
    const std::string name =
        o.name.empty() ? std::filesystem::path(o.local).filename().string() : o.name;
    std::optional<FoeSession> s;
    FoeOptions options;
    if (const int rc = open_for_foe(o, s, options); rc != kExitOk) {
        return rc;
    }
    SdoProgressBar bar;
    options.progress = [&bar](std::size_t done, std::optional<std::size_t> total) {
        bar.update(done, total);
    };
    const TimePoint start = SteadyClock::now();
    auto w = s->session.master->foe_write(s->slave, name, data, options);
    bar.finish();
    if (!w) {
        fmt::print(stderr, "codrive: {}\n", s->session.master->last_error());
        return kExitFailure;
    }
    fmt::print(stderr, "wrote {} bytes to {} as '{}' ({})\n", data.size(),
               s->session.master->slave_label(s->slave), name, rate(data.size(), start));
    return kExitOk;
}

int run_read(const FoeCliOptions& o) {
    std::optional<FoeSession> s;
    FoeOptions options;
    if (const int rc = open_for_foe(o, s, options); rc != kExitOk) {
        return rc;
    }
    SdoProgressBar bar;
    options.progress = [&bar](std::size_t done, std::optional<std::size_t> total) {
        bar.update(done, total);
    };
    const TimePoint start = SteadyClock::now();
    auto data = s->session.master->foe_read(s->slave, o.name, options);
    bar.finish();
    if (!data) {
        fmt::print(stderr, "codrive: {}\n", s->session.master->last_error());
        return kExitFailure;
    }
    if (o.local.empty()) {
        std::fwrite(data->data(), 1, data->size(), stdout);
        std::fflush(stdout);
    } else {
        std::ofstream out(o.local, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data->data()),
                  static_cast<std::streamsize>(data->size()));
        if (!out) {
            fmt::print(stderr, "codrive: cannot write {}\n", o.local);
            return kExitFailure;
        }
    }
    fmt::print(stderr, "read {} bytes of '{}' from {} ({})\n", data->size(), o.name,
               s->session.master->slave_label(s->slave), rate(data->size(), start));
    return kExitOk;
}

} // namespace

void install_ecat_foe(CLI::App& ecat, int& exit_code) {
    auto* foe = ecat.add_subcommand("foe", "FoE: read or write a file on a slave");
    foe->require_subcommand(1);
    auto opts = std::make_shared<FoeCliOptions>();
    auto* read = foe->add_subcommand("read", "read the file NAME from the slave");
    auto* write = foe->add_subcommand("write", "write the local FILE to the slave");
    for (auto* c : {read, write}) {
        c->add_option("--ethercat", opts->iface, "network interface")->required();
        c->add_option("-n,--position", opts->position, "slave position (0 = first)")->required();
        c->add_option("--password", opts->password, "FoE password (32-bit number, default 0)");
        c->add_option("--timeout", opts->timeout_ms,
                      "mailbox timeout per FoE step in ms (default 1000)");
    }
    read->add_option("name", opts->name, "the file's name on the slave")->required();
    read->add_option("-o,--output", opts->local, "write the file here (default: stdout)");
    write->add_option("file", opts->local, "the local file to send")->required();
    write->add_option("--as", opts->name, "the file's name on the slave (default: FILE's name)");
    read->callback([opts, &exit_code] { exit_code = run_read(*opts); });
    write->callback([opts, &exit_code] { exit_code = run_write(*opts); });
}

} // namespace codrive::cli
