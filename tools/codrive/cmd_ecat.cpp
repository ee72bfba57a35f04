// SPDX-License-Identifier: Apache-2.0
// `codrive ecat`: EtherCAT segment scan, CoE SDO read/write and state requests over a raw socket.
#include "cmd_ecat_dc.hpp"
#include "cmd_ecat_foe.hpp"
#include "command_registry.hpp"
#include "ecat_session.hpp"

#include <codrive/core/data_type.hpp>
#include <codrive/core/value.hpp>
#include <codrive/ethercat/esi.hpp>

#include <fmt/format.h>

#include <memory>

namespace codrive::cli {
namespace {

using namespace codrive::ethercat;

struct EcatOptions {
    std::string iface;
    unsigned position = 0;
    std::string index;
    std::string subindex = "0";
    std::string value;
    std::string type;
    std::string state;
    std::string esi; ///< --esi: names and types of the objects from this ESI file
    bool complete_access = false;
};

/// With --esi: the ESI entry of INDEX:SUB on the device the slave's SII identity matches. Sets
/// `refused` (after printing the sentence) when the file cannot be read or describes another
/// device; nullptr without --esi or when the dictionary has no such entry.
struct EsiLookup {
    std::optional<SlaveEsi> esi;
    const ethercat::EsiEntry* entry = nullptr;
    bool refused = false;
};

EsiLookup esi_entry(const EcatOptions& o, const Master& m, std::uint16_t index, std::uint8_t sub) {
    EsiLookup out;
    if (o.esi.empty()) {
        return out;
    }
    out.esi = slave_esi(o.esi, m, o.position);
    if (!out.esi) {
        out.refused = true;
        return out;
    }
    const ethercat::EsiDevice* d = out.esi->device;
    out.entry = d->entry(index, sub);
    if (out.entry == nullptr) {
        fmt::print(stderr, "codrive: {} has no object 0x{:04X}:{:02X} for {}\n", o.esi, index, sub,
                   d->describe());
    } else if (!out.entry->type) {
        fmt::print(stderr, "codrive: {}: 0x{:04X}:{:02X} is of type {}, not a base type\n", o.esi,
                   index, sub, out.entry->type_name);
    }
    return out;
}

int run_scan(const EcatOptions& o) {
    auto s = open_segment(o.iface);
    if (!s) {
        return kExitNoBus;
    }
    for (const auto& sl : s->master->slaves()) {
        fmt::print(
            "slave {} @0x{:04X}: {} vendor 0x{:08X} product 0x{:08X} revision 0x{:08X} "
            "serial {} mailbox {}/{}{} DC {} state {}\n",
            sl.position, sl.station_address, sl.display_name(), sl.sii.vendor_id,
            sl.sii.product_code, sl.sii.revision, sl.sii.serial, sl.sii.rx_mailbox_size,
            sl.sii.tx_mailbox_size,
            fmt::format("{}{}", sl.sii.has_coe() ? " CoE" : "", sl.sii.has_foe() ? " FoE" : ""),
            sl.has_dc ? "yes" : "no", to_string(sl.state));
    }
    return kExitOk;
}

std::optional<std::pair<std::uint16_t, std::uint8_t>> parse_object(const EcatOptions& o) {
    const auto index = parse_uint(o.index);
    const auto sub = parse_uint(o.subindex);
    if (!index || *index > 0xFFFF || !sub || *sub > 0xFF) {
        fmt::print(stderr, "codrive: bad object '{}:{}' (use e.g. 0x1018 1)\n", o.index,
                   o.subindex);
        return std::nullopt;
    }
    return std::make_pair(static_cast<std::uint16_t>(*index), static_cast<std::uint8_t>(*sub));
}

/// `codrive ecat` numbers slaves from 0 (as `-n` here counts them).
bool to_preop(Master& m, std::size_t slave) {
    return slave_for_coe(m, static_cast<unsigned>(slave), 0).has_value();
}

int run_sdo_read(const EcatOptions& o) {
    const auto obj = parse_object(o);
    std::optional<DataType> type;
    if (!o.type.empty() && !(type = data_type_from_name(o.type))) {
        fmt::print(stderr, "codrive: unknown type '{}'\n", o.type);
        return kExitUsage;
    }
    if (!obj) {
        return kExitUsage;
    }
    auto s = open_segment(o.iface);
    if (!s) {
        return kExitNoBus;
    }
    if (!to_preop(*s->master, o.position)) {
        return kExitFailure;
    }
    const EsiLookup esi = esi_entry(o, *s->master, obj->first, obj->second);
    if (esi.refused) {
        return kExitFailure;
    }
    auto data = s->master->sdo_upload(o.position, obj->first, obj->second, o.complete_access);
    if (!data) {
        fmt::print(stderr, "codrive: {}\n", s->master->last_error());
        return kExitFailure;
    }
    if (!type && esi.entry != nullptr && esi.entry->type) {
        // Typed and named from the ESI (ETG.2000 Object Name/Type).
        fmt::print("{}: {}\n", esi.entry->name, Value(*esi.entry->type, *data).to_string());
    } else if (type) {
        fmt::print("{}\n", Value(*type, *data).to_string());
    } else if (!data->empty() && data->size() <= 4) {
        const auto v = get_le_n(data->data(), data->size());
        fmt::print("0x{:0{}X} ({})\n", v, data->size() * 2, v);
    } else {
        fmt::print("{}\n", hex_bytes(*data));
    }
    return kExitOk;
}

int run_sdo_write(const EcatOptions& o) {
    const auto obj = parse_object(o);
    if (!obj) {
        return kExitUsage;
    }
    std::optional<DataType> type;
    if (!o.type.empty() && !(type = data_type_from_name(o.type))) {
        fmt::print(stderr, "codrive: unknown type '{}'\n", o.type);
        return kExitUsage;
    }
    if (!type && o.esi.empty()) {
        type = DataType::Unsigned32;
    }
    if (type && !Value::parse(*type, o.value)) { // a usage error before the segment is opened
        fmt::print(stderr, "codrive: cannot read '{}' as {}\n", o.value, to_string(*type));
        return kExitUsage;
    }
    auto s = open_segment(o.iface);
    if (!s) {
        return kExitNoBus;
    }
    if (!to_preop(*s->master, o.position)) {
        return kExitFailure;
    }
    const EsiLookup esi = esi_entry(o, *s->master, obj->first, obj->second);
    if (esi.refused) {
        return kExitFailure;
    }
    if (!type) { // the ESI's type, else UNSIGNED32
        type = esi.entry != nullptr && esi.entry->type ? *esi.entry->type : DataType::Unsigned32;
    }
    auto value = Value::parse(*type, o.value);
    if (!value) {
        fmt::print(stderr, "codrive: cannot read '{}' as {}\n", o.value, to_string(*type));
        return kExitUsage;
    }
    if (!s->master->sdo_download(o.position, obj->first, obj->second, value->bytes(),
                                 o.complete_access)) {
        fmt::print(stderr, "codrive: {}\n", s->master->last_error());
        return kExitFailure;
    }
    return kExitOk;
}

int run_state(const EcatOptions& o) {
    const auto target = al_state_from_string(o.state);
    if (!target) {
        fmt::print(stderr, "codrive: unknown state '{}' (use init, preop, safeop, op)\n", o.state);
        return kExitUsage;
    }
    auto s = open_segment(o.iface);
    if (!s) {
        return kExitNoBus;
    }
    if (!s->master->set_state_all(*target)) {
        fmt::print(stderr, "codrive: {}\n", s->master->last_error());
        return kExitFailure;
    }
    fmt::print("{} slave(s) in {}\n", s->master->slaves().size(), to_string(*target));
    return kExitOk;
}

void install_ecat(CLI::App& app, int& exit_code) {
    auto* ecat =
        app.add_subcommand("ecat", "EtherCAT: scan, CoE SDO access, state requests, FoE files, DC");
    ecat->require_subcommand(1);
    auto opts = std::make_shared<EcatOptions>();
    auto* scan = ecat->add_subcommand("scan", "list the slaves with identity, mailbox, DC, state");
    scan->add_option("--ethercat", opts->iface, "network interface")->required();
    scan->callback([opts, &exit_code] { exit_code = run_scan(*opts); });

    auto* sdo = ecat->add_subcommand("sdo", "CoE SDO access");
    sdo->require_subcommand(1);
    auto* read = sdo->add_subcommand("read", "SDO upload: read INDEX SUBINDEX");
    auto* write = sdo->add_subcommand("write", "SDO download: write INDEX SUBINDEX VALUE");
    for (auto* c : {read, write}) {
        c->add_option("--ethercat", opts->iface, "network interface")->required();
        c->add_option("-n,--position", opts->position, "slave position (0 = first)")->required();
        c->add_option("index", opts->index, "object index, e.g. 0x1018")->required();
        c->add_option("subindex", opts->subindex, "sub-index");
        c->add_option("-t,--type", opts->type, "data type: u8, u16, u32, i32, str, ...");
        c->add_flag("--complete-access", opts->complete_access, "CoE complete access");
        c->add_option("--esi", opts->esi,
                      "ESI file: the object's name and type (the slave's identity must match)");
    }
    write->add_option("value", opts->value, "value to write")->required();
    read->callback([opts, &exit_code] { exit_code = run_sdo_read(*opts); });
    write->callback([opts, &exit_code] { exit_code = run_sdo_write(*opts); });

    auto* state = ecat->add_subcommand("state", "request an EtherCAT state for every slave");
    state->add_option("--ethercat", opts->iface, "network interface")->required();
    state->add_option("state", opts->state, "init, preop, safeop or op")->required();
    state->callback([opts, &exit_code] { exit_code = run_state(*opts); });

    install_ecat_foe(*ecat, exit_code);
    install_ecat_dc(*ecat, exit_code);
}

} // namespace

CODRIVE_REGISTER_COMMAND(install_ecat);

} // namespace codrive::cli
