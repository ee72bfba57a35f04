// SPDX-License-Identifier: Apache-2.0
// EtherCAT session helpers shared by `codrive ecat`, `scan`, `sdo` and `drive --ethercat`.
#include "ecat_session.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string_view>
#include <vector>

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

std::string no_inputs_cause(const ethercat::ProcessDataStats& at_op,
                            const ethercat::ProcessDataStats& now, unsigned cycle_us) {
    // Each cyclic frame came back in time (cycles: with the expected working counter, bringing
    // the inputs in, or not), or its wait ended without it (lost_frames; late_frames of them
    // were read by a later wait), or on a receive error, or it could not be sent.
    const std::uint64_t inputs = now.input_frames - at_op.input_frames;
    const std::uint64_t wkc = now.wkc_errors - at_op.wkc_errors;
    const std::uint64_t lost = now.lost_frames - at_op.lost_frames;
    const std::uint64_t late = std::min(lost, now.late_frames - at_op.late_frames);
    const std::uint64_t failed = now.receive_errors - at_op.receive_errors;
    const std::uint64_t unsent = now.send_errors - at_op.send_errors;
    const std::uint64_t frames = (now.cycles - at_op.cycles) + lost + failed + unsent;
    if (frames == 0 || inputs * 2 >= frames) {
        return {}; // most frames brought the inputs in: the cause is elsewhere
    }
    std::vector<std::string> fates;
    const auto fate = [&fates](std::uint64_t n, std::string_view what) {
        if (n != 0) {
            fates.push_back(fmt::format("{} {}", n, what));
        }
    };
    fate(late, fmt::format("came back after their {} µs cycle", cycle_us));
    fate(lost - late, "did not come back");
    fate(wkc, "came back with a working counter other than expected");
    fate(failed, "were given up on a receive error");
    fate(unsent, "could not be sent");
    std::string out = inputs == 0
                          ? fmt::format(": none of the {} cyclic frames", frames)
                          : fmt::format(": only {} of the {} cyclic frames", inputs, frames);
    out += fmt::format(" since OP brought the inputs in ({})", fmt::join(fates, ", "));
    if (late != 0) {
        out += fmt::format("; the frames take longer than the {} µs cycle to come back (a "
                           "loaded host or a long segment): a longer --cycle gives them time",
                           cycle_us);
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
