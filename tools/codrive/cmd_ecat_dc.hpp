// SPDX-License-Identifier: Apache-2.0
// `codrive ecat dc`: distributed clocks status and drift over time.
#pragma once

#include <CLI/CLI.hpp>

namespace codrive::cli {

/// Adds `dc` under the `ecat` subcommand.
void install_ecat_dc(CLI::App& ecat, int& exit_code);

} // namespace codrive::cli
