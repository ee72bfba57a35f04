// SPDX-License-Identifier: Apache-2.0
// `codrive esi export`: a built-in profile's object dictionary as an ESI XML file (ETG.2000).
#include "command_registry.hpp"
#include "device_export.hpp"

namespace codrive::cli {
namespace {

void install_esi(CLI::App& app, int& exit_code) {
    CLI::App* esi = app.add_subcommand("esi", "Write EtherCAT slave information (ESI) files");
    esi->require_subcommand(1);
    install_export(*esi, true, exit_code);
}

CODRIVE_REGISTER_COMMAND(install_esi);

} // namespace
} // namespace codrive::cli
