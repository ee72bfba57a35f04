// SPDX-License-Identifier: Apache-2.0
// `codrive`: the command-line front end; subcommands live in cmd_*.cpp.
#include "command_registry.hpp"

#include <cstdio>

namespace codrive::cli {

std::vector<CommandInstaller>& commands() {
    static std::vector<CommandInstaller> list;
    return list;
}

bool register_command(CommandInstaller installer) {
    commands().push_back(std::move(installer));
    return true;
}

} // namespace codrive::cli

int main(int argc, char** argv) {
    CLI::App app{"codrive: CANopen and EtherCAT master for CiA 402 drives"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "codrive " CODRIVE_VERSION);
    int exit_code = codrive::cli::kExitOk;
    for (auto& install : codrive::cli::commands()) {
        install(app, exit_code);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : codrive::cli::kExitUsage;
    }
    return exit_code;
}
