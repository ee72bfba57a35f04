// SPDX-License-Identifier: Apache-2.0
// Node-ID / bit-rate commissioning: write the drive's objects, then save (commissioning.hpp).
#include <codrive/drives/commissioning.hpp>
#include <codrive/drives/persistence.hpp>

#include <fmt/format.h>

#include <memory>

namespace codrive::drives {

std::string bit_rate_names(const Profile& p) {
    std::string out;
    for (const BitRateCode& b : p.commissioning.bit_rates) {
        out += fmt::format("{}{}", out.empty() ? "" : ", ", b.kbit);
    }
    return out;
}

void commission_node(DriveTransport& t, const Profile& p, unsigned node_id,
                     std::optional<unsigned> bit_rate_kbit, DriveTransport::WriteDone done) {
    const Commissioning& c = p.commissioning;
    if (c.node_id_object == 0 || (bit_rate_kbit && c.bit_rate_object == 0)) {
        done(drive_fail(DriveErrc::NotSupported,
                        fmt::format("{} ({}): the profile knows no {} object: set it on the drive "
                                    "itself (see its manual)",
                                    t.name(), p.title,
                                    c.node_id_object == 0 ? "node-ID" : "bit-rate")));
        return;
    }
    if (node_id < 1 || node_id > 127) {
        done(drive_fail(DriveErrc::InvalidArgument,
                        fmt::format("{}: node-ID {} is outside 1..127", t.name(), node_id)));
        return;
    }
    std::optional<std::uint8_t> code;
    if (bit_rate_kbit) {
        code = c.code_for(*bit_rate_kbit);
        if (!code) {
            done(drive_fail(DriveErrc::InvalidArgument,
                            fmt::format("{} ({}): {} kbit/s is not supported (it takes: {})",
                                        t.name(), p.title, *bit_rate_kbit, bit_rate_names(p))));
            return;
        }
    }
    auto shared = std::make_shared<DriveTransport::WriteDone>(std::move(done));
    const std::uint16_t rate_object = c.bit_rate_object;
    // Node-ID, then bit rate, then "save": each step only after the previous one succeeded.
    auto save = [&t, &p, shared]() {
        store_parameters(t, p, "all", [shared](DriveVoid r) { (*shared)(std::move(r)); });
    };
    t.write_as<std::uint8_t>(c.node_id_object, 0, static_cast<std::uint8_t>(node_id),
                             [&t, shared, code, rate_object, save](DriveVoid r) {
                                 if (!r) {
                                     (*shared)(std::move(r));
                                     return;
                                 }
                                 if (!code) {
                                     save();
                                     return;
                                 }
                                 t.write_as<std::uint8_t>(rate_object, 0, *code,
                                                          [shared, save](DriveVoid w) {
                                                              if (!w) {
                                                                  (*shared)(std::move(w));
                                                                  return;
                                                              }
                                                              save();
                                                          });
                             });
}

} // namespace codrive::drives
