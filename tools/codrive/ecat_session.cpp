// SPDX-License-Identifier: Apache-2.0
// EtherCAT session helpers shared by `codrive ecat`, `scan`, `sdo` and `drive --ethercat`.
#include "ecat_session.hpp"

#include <fmt/format.h>

namespace codrive::cli {

using namespace codrive::ethercat;

std::optional<EcatSession> open_segment(const std::string& iface, unsigned label_base) {
    auto link = RawSocketLink::open(iface);
    if (!link) {
        fmt::print(stderr, "codrive: {}\n",
                   RawSocketLink::describe_open_error(iface, link.error()));
        return std::nullopt;
    }
    EcatSession s;
    s.link = std::move(*link);
    MasterConfig config;
    config.slave_label_base = label_base;
    s.master = std::make_unique<Master>(*s.link, RealClock::instance(), config);
    if (!s.master->scan()) {
        fmt::print(stderr, "codrive: {}\n", s.master->last_error());
        return std::nullopt;
    }
    return s;
}

std::optional<std::size_t> slave_for_coe(Master& master, unsigned position, unsigned base) {
    const std::size_t count = master.slaves().size();
    if (position < base || position - base >= count) {
        fmt::print(stderr,
                   "codrive: there is no slave at position {} ({} found, numbered from {})\n",
                   position, count, base);
        return std::nullopt;
    }
    const std::size_t slave = position - base;
    if (master.slaves()[slave].state == AlState::Init &&
        !master.request_state(slave, AlState::PreOp)) {
        fmt::print(stderr, "codrive: {}\n", master.last_error());
        return std::nullopt;
    }
    return slave;
}

std::string format_slave_table(const Master& master, unsigned base) {
    std::string out = fmt::format("{:>3}  {:<7} {:<10} {:<10} {:<10} {:<20} {}\n", "pos", "station",
                                  "vendor", "product", "revision", "name", "state");
    for (const auto& sl : master.slaves()) {
        // What the previous master left behind is what a field engineer needs first: the
        // state and a pending AL error, in words (the scan itself resets every slave to INIT).
        std::string found;
        if (sl.found_state != AlState::None &&
            (sl.found_state != AlState::Init || sl.found_error)) {
            found = fmt::format(" (found in {}{})", to_string(sl.found_state),
                                sl.found_error ? fmt::format(" + error 0x{:04X} {}", sl.found_code,
                                                             al_status_code_describe(sl.found_code))
                                               : std::string());
        }
        out += fmt::format("{:>3}  0x{:04X}  0x{:08X} 0x{:08X} 0x{:08X} {:<20} {}{}\n",
                           sl.position + base, sl.station_address, sl.sii.vendor_id,
                           sl.sii.product_code, sl.sii.revision, sl.display_name(),
                           to_string(sl.state), found);
    }
    return out;
}

std::optional<SlaveEsi> slave_esi(const std::string& path, const Master& master,
                                  std::size_t slave) {
    auto esi = ethercat::load_esi(path);
    if (!esi) {
        fmt::print(stderr, "codrive: {}\n", esi.error());
        return std::nullopt;
    }
    std::optional<SlaveEsi> out(std::in_place);
    out->file = std::move(*esi); // `device` points into the file from here on
    const auto& sii = master.slaves().at(slave).sii;
    out->device = out->file.match(sii.vendor_id, sii.product_code, sii.revision);
    if (out->device == nullptr) {
        fmt::print(stderr, "codrive: {}: {}\n", master.slave_label(slave),
                   out->file.mismatch(sii.vendor_id, sii.product_code, sii.revision));
        return std::nullopt;
    }
    return out;
}

} // namespace codrive::cli
