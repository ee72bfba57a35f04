// SPDX-License-Identifier: Apache-2.0
// `codrive eds export` / `codrive esi export`: a profile's dictionary written as a vendor file.
#pragma once

#include "command_registry.hpp"

#include <string>

namespace codrive::cli {

/// Options of both export subcommands.
struct ExportArgs {
    std::string profile;
    unsigned axes = 0; ///< 0: the devices/ default for the profile (AKD2G 2, others 1)
    std::string output;
};

/// Adds `export` to `parent` ("eds" or "esi"); `esi` selects the XML writer.
void install_export(CLI::App& parent, bool esi, int& exit_code);

} // namespace codrive::cli
