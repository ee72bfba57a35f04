// SPDX-License-Identifier: Apache-2.0
// Helpers for `codrive` subcommands that talk EtherCAT (`--ethercat IFACE`): open the segment
// with a readable error, pick a slave by its position, bring it to PRE-OP for CoE.
#pragma once

#include <codrive/ethercat/esi.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/raw_socket_link.hpp>

#include <memory>
#include <optional>
#include <string>

namespace codrive::cli {

/// A raw socket on the segment's interface and a master that has scanned it.
struct EcatSession {
    std::unique_ptr<ethercat::RawSocketLink> link;
    std::unique_ptr<ethercat::Master> master;
};

/// Opens `iface` and scans the segment (every slave is reset to INIT, addresses 0x1001..).
/// `label_base` numbers the slaves in messages (1 where -n counts from 1). On failure prints
/// one sentence to stderr ("codrive: cannot open a raw EtherCAT socket on ecm0: ... needs
/// CAP_NET_RAW") and returns nullopt.
std::optional<EcatSession> open_segment(const std::string& iface, unsigned label_base = 0);

/// The 0-based index of the slave at `position` (counted from `base`), in PRE-OP (CoE needs the
/// mailbox); prints the problem and returns nullopt.
std::optional<std::size_t> slave_for_coe(ethercat::Master& master, unsigned position,
                                         unsigned base);

/// A vendor's ESI file and its device that describes one slave.
struct SlaveEsi {
    ethercat::EsiFile file;
    const ethercat::EsiDevice* device = nullptr; ///< in `file`
};

/// `--esi PATH` for the slave at index `slave`: the file read and its device matched against the
/// slave's SII identity (vendor, product; the exact revision first). Prints the sentence and
/// returns nullopt when the file cannot be read or describes another device.
std::optional<SlaveEsi> slave_esi(const std::string& path, const ethercat::Master& master,
                                  std::size_t slave);

/// The segment as a table: position (from `base`), station address, vendor, product,
/// revision, name, AL state.
std::string format_slave_table(const ethercat::Master& master, unsigned base);

} // namespace codrive::cli
