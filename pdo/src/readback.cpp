// SPDX-License-Identifier: Apache-2.0
// Reading back PDO communication and mapping parameters, and the table rendering.
#include <codrive/pdo/readback.hpp>

#include <fmt/format.h>

namespace codrive::pdo {
namespace {

std::uint64_t as_uint(const sdo::Bytes& b) {
    return get_le_n(b.data(), b.size());
}

bool is_missing(const sdo::SdoError& e) {
    const auto code = e.abort_code();
    return code && (*code == static_cast<std::uint32_t>(SdoAbort::NoObject) ||
                    *code == static_cast<std::uint32_t>(SdoAbort::NoSubindex));
}

} // namespace

const PdoConfig* NodePdoConfiguration::find(PdoDir dir, unsigned number) const {
    for (const auto& p : pdos) {
        if (p.dir == dir && p.number == number) {
            return &p;
        }
    }
    return nullptr;
}

std::string NodePdoConfiguration::to_string(const ObjectDictionary* od) const {
    std::string out = fmt::format("node {} PDO configuration\n", node);
    out += fmt::format("{:<7}{:<12}{:<7}{:<28}{:<9}{:<8}{:<7}{}\n", "PDO", "COB-ID", "valid",
                       "transmission", "inhibit", "timer", "bytes", "mapping");
    for (const auto& p : pdos) {
        std::string map;
        for (const auto& e : p.mapping) {
            if (!map.empty()) {
                map += ' ';
            }
            map += pdo::to_string(e);
            if (od != nullptr) {
                const std::string n = od->name_of(e.index, e.subindex);
                if (!n.empty()) {
                    map += fmt::format(" ({})", n);
                }
            }
        }
        if (map.empty()) {
            map.push_back('-');
        }
        const bool tpdo = p.dir == PdoDir::Tpdo;
        const std::string cob =
            fmt::format("0x{:X}{}{}", p.comm.can_id, p.comm.extended ? " ext" : "",
                        tpdo && p.comm.rtr_allowed ? " rtr" : "");
        out +=
            fmt::format("{:<7}{:<12}{:<7}{:<28}{:<9}{:<8}{:<7}{}\n", p.name(), cob,
                        p.enabled ? "yes" : "no", describe_transmission(p.comm.transmission_type),
                        tpdo ? fmt::format("{} us", p.comm.inhibit_time * 100U) : std::string("-"),
                        (tpdo || p.comm.event_timer != 0) ? fmt::format("{} ms", p.comm.event_timer)
                                                          : std::string("-"),
                        p.byte_length(), map);
    }
    for (const auto& n : notes) {
        out += "note: " + n + "\n";
    }
    return out;
}

PdoReader::PdoReader(sdo::SdoClient& client)
    : client_(client), alive_(std::make_shared<bool>(true)) {}

PdoReader::~PdoReader() {
    *alive_ = false;
}

bool PdoReader::read(unsigned rpdos, unsigned tpdos, Done done) {
    if (running_) {
        return false;
    }
    result_ = {};
    result_.node = client_.config().node;
    steps_.clear();
    for (unsigned n = 1; n <= rpdos; ++n) {
        queue_pdo(PdoDir::Rpdo, n);
    }
    for (unsigned n = 1; n <= tpdos; ++n) {
        queue_pdo(PdoDir::Tpdo, n);
    }
    running_ = true;
    done_ = std::move(done);
    next();
    return true;
}

void PdoReader::queue_pdo(PdoDir dir, unsigned number) {
    const std::uint16_t comm = comm_index(dir, number);
    const std::uint16_t map = map_index(dir, number);
    // The COB-ID read decides whether the PDO exists; the other steps find it by number.
    steps_.push_back({comm, comm_sub::kCobId, true, [this, dir, number](const auto& r) {
                          if (!r) {
                              // No communication object: the PDO does not exist. Drop its
                              // remaining steps (they carry the same comm/map indexes).
                              const std::uint16_t c = comm_index(dir, number);
                              const std::uint16_t m = map_index(dir, number);
                              std::erase_if(steps_, [c, m](const Step& s) {
                                  return s.index == c || s.index == m;
                              });
                              return;
                          }
                          PdoConfig p;
                          p.dir = dir;
                          p.number = number;
                          const auto f = decode_cob_id(static_cast<std::uint32_t>(as_uint(*r)));
                          p.comm.can_id = f.can_id;
                          p.comm.extended = f.extended;
                          p.comm.rtr_allowed = !f.no_rtr;
                          p.enabled = !f.invalid;
                          p.comm.transmission_type = 0;
                          result_.pdos.push_back(std::move(p));
                      }});
    auto current = [this]() -> PdoConfig& { return result_.pdos.back(); };
    auto optional_sub = [this, dir, number, comm](std::uint8_t sub, auto apply) {
        steps_.push_back({comm, sub, true, [this, dir, number, sub, apply](const auto& r) {
                              if (!r) {
                                  result_.notes.push_back(fmt::format("{} has no sub-index {:02X}h",
                                                                      pdo_name(dir, number), sub));
                                  return;
                              }
                              apply(result_.pdos.back(), as_uint(*r));
                          }});
    };
    steps_.push_back({comm, comm_sub::kTransmissionType, false, [current](const auto& r) {
                          current().comm.transmission_type = static_cast<std::uint8_t>(as_uint(*r));
                      }});
    if (dir == PdoDir::Tpdo) {
        optional_sub(comm_sub::kInhibitTime, [](PdoConfig& p, std::uint64_t v) {
            p.comm.inhibit_time = static_cast<std::uint16_t>(v);
        });
        optional_sub(comm_sub::kEventTimer, [](PdoConfig& p, std::uint64_t v) {
            p.comm.event_timer = static_cast<std::uint16_t>(v);
        });
        optional_sub(comm_sub::kSyncStart, [](PdoConfig& p, std::uint64_t v) {
            p.comm.sync_start = static_cast<std::uint8_t>(v);
        });
    }
    steps_.push_back(
        {map, 0, false, [this, map, current](const auto& r) {
             const auto count = static_cast<unsigned>(as_uint(*r));
             // Entries are read right after the count, before the next PDO.
             for (unsigned i = count; i >= 1; --i) {
                 steps_.push_front(
                     {map, static_cast<std::uint8_t>(i), false, [current](const auto& e) {
                          current().mapping.push_back(
                              MappingEntry::from_raw(static_cast<std::uint32_t>(as_uint(*e))));
                      }});
             }
             if (count == 0 && !current().mapping.empty()) {
                 current().mapping.clear();
             }
         }});
}

void PdoReader::next() {
    if (steps_.empty()) {
        finish(std::move(result_));
        return;
    }
    std::weak_ptr<bool> alive = alive_;
    const Step& s = steps_.front();
    client_.upload(s.index, s.subindex, [this, alive](sdo::SdoResult<sdo::Bytes> r) {
        if (alive.expired()) {
            return;
        }
        Step step = std::move(steps_.front());
        steps_.pop_front();
        if (!r && !(step.optional && is_missing(r.error()))) {
            finish(pdo_fail(PdoErrc::SdoFailed,
                            fmt::format("node {}: reading the PDO configuration failed: {}",
                                        client_.config().node, r.error().to_string())));
            return;
        }
        step.handle(r);
        next();
    });
}

void PdoReader::finish(PdoResult<NodePdoConfiguration> r) {
    running_ = false;
    steps_.clear();
    auto done = std::move(done_);
    done(std::move(r));
}

} // namespace codrive::pdo
