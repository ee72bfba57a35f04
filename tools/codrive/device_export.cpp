// SPDX-License-Identifier: Apache-2.0
// `codrive eds export` / `codrive esi export`: a profile's dictionary written as a vendor file.
#include "device_export.hpp"

#include <codrive/devices/device_files.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <memory>

namespace codrive::cli {

namespace {

int run_export(const ExportArgs& a, bool esi) {
    const char* what = esi ? "esi" : "eds";
    const drives::Profile* p = drives::find_profile(a.profile);
    if (p == nullptr) {
        fmt::print(stderr,
                   "codrive {} export: unknown profile `{}` (known: akd2g, ds-bvs, fio, "
                   "generic)\n",
                   what, a.profile);
        return kExitUsage;
    }
    const devices::DeviceFile* f = devices::device_file(p->name);
    unsigned axes = a.axes != 0 ? a.axes : (f != nullptr ? f->axes : 1U);
    if (axes > p->max_axes) {
        fmt::print(stderr, "codrive {} export: profile `{}` has at most {} {}, not {}\n", what,
                   p->name, p->max_axes, p->max_axes == 1 ? "axis" : "axes", axes);
        return kExitUsage;
    }
    const std::string_view vendor = f != nullptr ? f->vendor_name : std::string_view{};
    const std::string text =
        esi ? devices::export_esi(*p, axes, vendor) : devices::export_eds(*p, axes, vendor);
    if (a.output.empty() || a.output == "-") {
        fmt::print("{}", text);
        return kExitOk;
    }
    std::ofstream out(a.output, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
        fmt::print(stderr, "codrive {} export: cannot write {}\n", what, a.output);
        return kExitFailure;
    }
    return kExitOk;
}

} // namespace

void install_export(CLI::App& parent, bool esi, int& exit_code) {
    auto args = std::make_shared<ExportArgs>();
    CLI::App* cmd = parent.add_subcommand(
        "export", esi ? "Write a built-in profile's object dictionary as an ESI XML file "
                        "(ETG.2000)"
                      : "Write a built-in profile's object dictionary as an EDS file (CiA 306)");
    cmd->add_option("--profile", args->profile, "akd2g, ds-bvs, fio or generic")->required();
    cmd->add_option("--axes", args->axes, "axes of the device (default: AKD2G 2, others 1)")
        ->check(CLI::Range(1, 8));
    cmd->add_option("-o,--output", args->output, "file to write (default: standard output)");
    cmd->callback([args, esi, &exit_code] { exit_code = run_export(*args, esi); });
}

} // namespace codrive::cli
