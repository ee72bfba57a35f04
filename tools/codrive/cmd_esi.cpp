// SPDX-License-Identifier: Apache-2.0
// `codrive esi show|export`: print what an ESI XML file (ETG.2000) describes, or write a built-in
// profile's object dictionary as one.
#include "command_registry.hpp"
#include "device_export.hpp"

#include <codrive/ethercat/esi.hpp>

#include <fmt/format.h>

#include <memory>
#include <optional>

namespace codrive::cli {
namespace {

struct EsiShowArgs {
    std::string file;
    std::string index;
};

std::string type_text(const ethercat::EsiEntry& e) {
    return e.type ? fmt::format("{} ({})", e.type_name, to_string(*e.type)) : e.type_name;
}

std::string pdo_text(const ethercat::EsiEntry& e) {
    if (e.rx_mappable && e.tx_mappable) {
        return "T+R";
    }
    return e.tx_mappable ? "T" : (e.rx_mappable ? "R" : "-");
}

void print_pdos(const ethercat::EsiDevice& d, const std::vector<ethercat::EsiPdo>& pdos) {
    for (const auto& p : pdos) {
        std::string flags;
        if (p.sm) {
            flags += fmt::format(", SM{} by default", *p.sm);
        }
        if (p.fixed) {
            flags += ", fixed";
        }
        fmt::print("  {} {:04X}h {}{}\n", p.rx ? "RxPDO" : "TxPDO", p.index, p.name, flags);
        for (const auto& e : p.entries) {
            // An entry without a Name of its own is named by the dictionary.
            const ethercat::EsiEntry* od = d.entry(e.index, e.subindex);
            const std::string name = e.index == 0      ? std::string("(gap)")
                                     : !e.name.empty() ? e.name
                                     : od != nullptr   ? od->name
                                                       : std::string("(not in the dictionary)");
            fmt::print("    {:04X}:{:02X} {:>2} bit  {}\n", e.index, e.subindex, e.bit_len, name);
        }
    }
}

void print_device(const ethercat::EsiDevice& d) {
    fmt::print("device {}: {} objects, {} RxPDO, {} TxPDO\n", d.describe(), d.objects.size(),
               d.rx_pdos.size(), d.tx_pdos.size());
    for (const auto& sm : d.sync_managers) {
        fmt::print("  {:<7} start 0x{:04X}{}\n", sm.kind, sm.start_address,
                   sm.default_size != 0 ? fmt::format(" size {}", sm.default_size) : std::string());
    }
    fmt::print("  mailbox: {}\n",
               d.coe ? fmt::format("CoE (SDO info {}, PDO assign {}, PDO config {})",
                                   d.sdo_info ? "yes" : "no", d.pdo_assign ? "yes" : "no",
                                   d.pdo_config ? "yes" : "no")
                     : std::string("no CoE"));
    print_pdos(d, d.rx_pdos);
    print_pdos(d, d.tx_pdos);
}

// One object's entries, as `codrive eds show` prints them: index:sub, name, type, access, PDO,
// default (the ESI's DefaultData bytes, little endian as written).
int print_object(const ethercat::EsiFile& esi, std::uint16_t index) {
    bool found = false;
    for (const auto& d : esi.devices) {
        const ethercat::EsiObject* o = d.object(index);
        if (o == nullptr) {
            continue;
        }
        found = true;
        if (esi.devices.size() > 1) {
            fmt::print("{}:\n", d.describe());
        }
        fmt::print("{:04X}  {}  {}\n", o->index, o->name, o->type_name);
        for (const auto& e : o->entries) {
            fmt::print("{:04X}:{:02X}  {}  {}  {}  {}  {}\n", o->index, e.subindex, e.name,
                       type_text(e), to_string(e.access), pdo_text(e),
                       e.default_data ? *e.default_data : std::string("-"));
        }
    }
    if (!found) {
        fmt::print(stderr, "codrive esi show: {} has no object {:04X}h\n", esi.file, index);
        return kExitFailure;
    }
    return kExitOk;
}

int run_show(const EsiShowArgs& a) {
    std::optional<std::uint16_t> index;
    if (!a.index.empty()) {
        try {
            std::size_t used = 0;
            const unsigned long v = std::stoul(a.index, &used, 16);
            if (used != a.index.size() || v > 0xFFFF) {
                throw std::invalid_argument(a.index);
            }
            index = static_cast<std::uint16_t>(v);
        } catch (const std::exception&) {
            fmt::print(stderr, "codrive esi show: '{}' is not an index (like 1018 or 0x6040)\n",
                       a.index);
            return kExitUsage;
        }
    }
    const auto esi = ethercat::load_esi(a.file);
    if (!esi) {
        fmt::print(stderr, "codrive esi show: {}\n", esi.error());
        return kExitFailure;
    }
    if (index) {
        return print_object(*esi, *index);
    }
    fmt::print("{}: vendor 0x{:08X} ({}), {} device(s)\n", esi->file, esi->vendor_id,
               esi->vendor_name, esi->devices.size());
    for (const auto& d : esi->devices) {
        print_device(d);
    }
    return kExitOk;
}

void install_esi(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<EsiShowArgs>();
    CLI::App* esi =
        app.add_subcommand("esi", "Print and write EtherCAT slave information (ESI) files");
    esi->require_subcommand(1);
    CLI::App* show = esi->add_subcommand(
        "show", "Print the devices, sync managers and PDOs of an ESI file, or one object");
    show->add_option("file", args->file, "ESI XML file")->required();
    show->add_option("index", args->index, "only this object, hex (1018, 0x6040)");
    show->callback([args, &exit_code] { exit_code = run_show(*args); });
    install_export(*esi, true, exit_code);
}

CODRIVE_REGISTER_COMMAND(install_esi);

} // namespace
} // namespace codrive::cli
