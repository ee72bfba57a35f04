// SPDX-License-Identifier: Apache-2.0
// `codrive ecat foe read|write`: files over FoE (file access over EtherCAT).
#pragma once

#include <CLI/CLI.hpp>

namespace codrive::cli {

/// Adds `foe read` and `foe write` under the `ecat` subcommand.
void install_ecat_foe(CLI::App& ecat, int& exit_code);

} // namespace codrive::cli
