// SPDX-License-Identifier: Apache-2.0
// Registration of `codrive` subcommands: each cmd_*.cpp registers itself at static-init time.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace codrive::cli {

/// Exit codes shared by every subcommand.
enum ExitCode : int {
    kExitOk = 0,
    kExitFailure = 1, ///< the operation failed (abort, timeout, refused)
    kExitUsage = 2,   ///< bad arguments
    kExitNoBus = 3,   ///< the interface could not be opened
};

/// A subcommand installer: adds its CLI11 subcommand to the app and sets its callback. The
/// callback stores its exit code in `exit_code`.
using CommandInstaller = std::function<void(CLI::App& app, int& exit_code)>;

/// Registers an installer; returns true so it can initialise a static.
bool register_command(CommandInstaller installer);
std::vector<CommandInstaller>& commands();

} // namespace codrive::cli

/// In a cmd_*.cpp: CODRIVE_REGISTER_COMMAND(install_sdo);
#define CODRIVE_REGISTER_COMMAND(fn)                                                               \
    [[maybe_unused]] static const bool codrive_registered_##fn =                                   \
        ::codrive::cli::register_command(fn)
