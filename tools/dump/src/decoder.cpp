// SPDX-License-Identifier: Apache-2.0
// Frame-by-frame CANopen decoding with conversation state.
#include <codrive/dump/decoder.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/dump/text_append.hpp>
#include <codrive/emcy/error_codes.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/nmt/command.hpp>
#include <codrive/nmt/state.hpp>
#include <codrive/sync/time.hpp>

#include <algorithm>
#include <iterator>

namespace codrive::dump {
namespace {

constexpr std::string_view kServiceNames[] = {"nmt", "sync", "time", "emcy",  "hb",
                                              "sdo", "pdo",  "lss",  "other", "error"};

} // namespace

std::string_view to_string(Service s) {
    return kServiceNames[static_cast<std::size_t>(s)];
}

std::string_view to_string(Severity s) {
    static constexpr std::string_view kNames[] = {"info", "notice", "warning", "error"};
    return kNames[static_cast<std::size_t>(s)];
}

std::optional<std::uint32_t> parse_service_list(std::string_view list, std::string& bad) {
    std::uint32_t mask = 0;
    while (!list.empty()) {
        const auto comma = list.find(',');
        const auto word = list.substr(0, comma);
        list = comma == std::string_view::npos ? std::string_view{} : list.substr(comma + 1);
        if (word.empty()) {
            continue;
        }
        bool found = false;
        for (std::size_t i = 0; i < std::size(kServiceNames); ++i) {
            if (word == kServiceNames[i] || (word == "heartbeat" && i == 4)) {
                mask |= 1U << i;
                found = true;
            }
        }
        if (!found) {
            bad = std::string(word);
            return std::nullopt;
        }
    }
    return mask;
}

Decoder::Decoder(DecoderOptions options, Stats* stats)
    : options_(options), stats_(stats), sdo_(catalog_, options.sdo_timeout_ns), pdo_(catalog_) {}

void Decoder::set_description(NodeId node, std::shared_ptr<const DeviceDescription> desc) {
    if (!valid_node_id(node) || !desc) {
        return;
    }
    pdo_.learn_from_description(node, *desc);
    if (desc->device_info.vendor_number != 0) {
        learn_identity(node, 1, desc->device_info.vendor_number);
        learn_identity(node, 2, desc->device_info.product_number);
    }
    catalog_.set_description(node, std::move(desc));
}

void Decoder::set_profile(NodeId node, const IDumpProfile* profile) {
    if (valid_node_id(node)) {
        nodes_[node].profile = profile;
        nodes_[node].profile_pinned = true;
    }
}

void Decoder::learn_identity(NodeId node, std::uint8_t sub, std::uint32_t value) {
    NodeState& n = nodes_[node];
    (sub == 1 ? n.vendor : n.product) = value;
    if (stats_ != nullptr) {
        stats_->on_identity(node, sub, value);
    }
    if (!n.profile_pinned && registry_ != nullptr && n.vendor && n.product) {
        n.profile = registry_->match(*n.vendor, *n.product);
    }
}

void Decoder::collect_stalls(std::vector<SdoStall>& stalls, std::vector<Note>& notes,
                             std::string_view event) {
    for (auto& s : stalls) {
        Note n;
        n.ts_ns = s.ts_ns;
        n.timed = s.timed;
        n.service = Service::Sdo;
        n.node = s.node;
        n.severity = Severity::Error;
        n.event = event;
        n.text = std::move(s.text);
        if (stats_ != nullptr) {
            stats_->on_sdo_timeout(s.node);
        }
        notes.push_back(std::move(n));
    }
    stalls.clear();
}

// An interface's time going back by more than a second is another capture appended to the
// first (relative times starting again at 0) or a clock set back. Left alone, it would stop SDO
// timeouts and the one-second load window until the time caught up again. The first interface
// to step opens a new stretch of time (the duration adds up the stretches); the others join it
// when they step, so two appended two-interface captures are two stretches, not four.
void Decoder::follow_time(std::string_view iface, std::int64_t ts, std::vector<Note>& notes) {
    constexpr std::int64_t kStepBackNs = 1'000'000'000;
    auto clock = std::find_if(clocks_.begin(), clocks_.end(),
                              [&](const InterfaceClock& c) { return c.iface == iface; });
    if (clock == clocks_.end()) {
        if (clocks_.size() < kMaxClocks) {
            clock_ = static_cast<std::uint8_t>(clocks_.size());
            clocks_.push_back({std::string(iface), ts, 0, stretch_});
            return;
        }
        clock = clocks_.end() - 1;
    }
    clock_ = static_cast<std::uint8_t>(clock - clocks_.begin());
    const std::int64_t latest = clock->latest_ns;
    if (ts >= latest) {
        clock->latest_ns = ts;
        return;
    }
    if (latest - ts <= kStepBackNs) { // both times are in 0..kMaxTraceTimeNs
        return;
    }
    clock->latest_ns = ts;
    clock->next_check_ns = ts;
    const bool new_stretch = clock->stretch == stretch_;
    if (new_stretch) {
        ++stretch_;
    }
    clock->stretch = stretch_;
    Note n;
    n.ts_ns = ts;
    n.service = Service::Other;
    n.severity = Severity::Warning;
    n.event = "time step";
    n.text = fmt::format("{}time goes back {:.3f} s (an appended capture or a clock step): SDO "
                         "timeouts and the bus load go on from the new time",
                         iface.empty() ? std::string() : fmt::format("{}: ", iface),
                         static_cast<double>(latest - ts) / 1e9);
    notes.push_back(std::move(n));
    sdo_.restart_clocks(ts, clock_);
    if (stats_ != nullptr) {
        stats_->on_time_step(ts, new_stretch);
    }
}

void Decoder::finish(std::vector<Note>& notes) {
    sdo_.finish(stalls_);
    collect_stalls(stalls_, notes, "unfinished");
}

void Decoder::decode(const TraceRecord& r, Decoded& out, std::vector<Note>& notes) {
    const Frame& f = r.frame;
    out.text.clear();
    out.node = 0;
    out.severity = Severity::Info;
    out.service = Service::Other;
    timed_ = r.has_ts && r.ts_ns >= 0 && r.ts_ns <= kMaxTraceTimeNs;
    out.timed = timed_;
    const std::int64_t ts = timed_ ? r.ts_ns : 0;
    if (timed_) {
        follow_time(r.iface, ts, notes);
    }
    if (stats_ != nullptr) {
        stats_->on_frame(f, ts, timed_);
    }
    if (timed_ && ts >= clocks_[clock_].next_check_ns) {
        sdo_.check_timeouts(ts, stalls_, clock_);
        collect_stalls(stalls_, notes, "timeout");
        clocks_[clock_].next_check_ns = ts + 10'000'000; // scan at most every 10 ms of its time
    }
    if (f.error()) {
        out.service = Service::Error;
        out.severity = Severity::Warning;
        text::put(out.text, "error frame:");
        bool first = true;
        for (const auto& e : decode_error_frame(f)) {
            text::put(out.text, first ? " " : "; ");
            first = false;
            text::put(out.text, to_string(e));
        }
        return;
    }
    if (f.extended() || f.fd()) {
        return; // CANopen (CiA 301) uses classic 11-bit frames; nothing to decode
    }
    const auto info = classify_cob_id(f.id);
    if (f.rtr() && decode_stray_remote(info, out)) {
        return;
    }
    switch (info.type) {
    case CobType::Nmt:
        decode_nmt(f, out);
        return;
    case CobType::Sync:
        decode_sync(f, out);
        if (stats_ != nullptr && timed_ && out.severity == Severity::Info) {
            stats_->on_sync(ts);
        }
        return;
    case CobType::Time:
        decode_time(f, out);
        return;
    case CobType::Emcy:
        decode_emcy(f, info.node, out);
        return;
    case CobType::Heartbeat:
        decode_error_control(f, info.node, ts, out);
        return;
    case CobType::LssMaster:
    case CobType::LssSlave:
        decode_lss(f, info.type == CobType::LssMaster, out);
        return;
    case CobType::SdoRx:
    case CobType::SdoTx:
        decode_sdo(f, info.node, info.type == CobType::SdoRx, ts, out);
        return;
    default:
        break;
    }
    if (f.rtr()) {
        // The PDO that uses the COB-ID now, also one moved there by its 1400h/1800h:01.
        const NodeId requested = pdo_.remote_request(f.id, out.text);
        if (requested != 0) {
            out.service = Service::Pdo;
            out.node = requested;
        }
        return;
    }
    const NodeId node = pdo_.decode(f.id, f.payload(), out.text);
    if (node != 0) {
        out.service = Service::Pdo;
        out.node = node;
        if (stats_ != nullptr) {
            stats_->on_pdo(node, info.is_tpdo(), ts);
        }
    }
}

bool Decoder::decode_stray_remote(const CobInfo& info, Decoded& out) {
    // CiA 301 requests only node guarding and PDOs by remote frame; NMT, SYNC, TIME, EMCY and
    // LSS frames carry data, so a remote frame there is not one of them (and is no SYNC).
    switch (info.type) {
    case CobType::Nmt:
        out.service = Service::Nmt;
        break;
    case CobType::Sync:
        out.service = Service::Sync;
        break;
    case CobType::Time:
        out.service = Service::Time;
        break;
    case CobType::Emcy:
        out.service = Service::Emcy;
        out.node = info.node;
        break;
    case CobType::LssMaster:
    case CobType::LssSlave:
        out.service = Service::Lss;
        break;
    default:
        return false;
    }
    out.severity = Severity::Warning;
    fmt::format_to(std::back_inserter(out.text),
                   "remote frame on the {} COB-ID (only node guarding and PDOs are requested by "
                   "remote frames)",
                   to_string(info.type));
    return true;
}

void Decoder::decode_nmt(const Frame& f, Decoded& out) {
    out.service = Service::Nmt;
    auto it = std::back_inserter(out.text);
    const auto cmd = nmt::parse_command_frame(f);
    if (!cmd) {
        out.severity = Severity::Warning;
        if (f.len >= 2) {
            fmt::format_to(it, "NMT invalid command 0x{:02X} for node {}", f.data[0], f.data[1]);
        } else {
            fmt::format_to(it, "NMT frame too short ({} bytes)", f.len);
        }
        return;
    }
    out.node = cmd->node;
    out.severity = Severity::Notice;
    fmt::format_to(it, "NMT {} ", nmt::to_string(cmd->command));
    if (cmd->node == nmt::kAllNodes) {
        text::put(out.text, "all nodes");
    } else if (cmd->command == nmt::NmtCommand::ResetNode) {
        fmt::format_to(it, "{}", cmd->node); // "reset node 15", not "reset node node 15"
    } else {
        fmt::format_to(it, "node {}", cmd->node);
    }
}

void Decoder::decode_sync(const Frame& f, Decoded& out) {
    out.service = Service::Sync;
    if (f.len == 0) {
        text::put(out.text, "SYNC");
    } else if (f.len == 1) {
        text::put(out.text, "SYNC counter ");
        text::put_uint(out.text, f.data[0]);
    } else {
        out.severity = Severity::Warning;
        fmt::format_to(std::back_inserter(out.text), "SYNC with {} bytes (0 or 1 expected)", f.len);
    }
}

void Decoder::decode_time(const Frame& f, Decoded& out) {
    out.service = Service::Time;
    const auto t = sync::decode_time_of_day(f.payload());
    if (!t) {
        out.severity = Severity::Warning;
        fmt::format_to(std::back_inserter(out.text), "TIME malformed ({} bytes)", f.len);
        return;
    }
    fmt::format_to(std::back_inserter(out.text), "TIME {}", sync::to_string(*t));
    if (f.len != sync::kTimeOfDayLen) {
        // CiA 301 §7.2.6.1: the TIME object carries exactly one TIME_OF_DAY (6 bytes).
        out.severity = Severity::Warning;
        fmt::format_to(std::back_inserter(out.text), " ({} bytes, TIME_OF_DAY has {})", f.len,
                       sync::kTimeOfDayLen);
    }
}

void Decoder::decode_emcy(const Frame& f, NodeId node, Decoded& out) {
    out.service = Service::Emcy;
    out.node = node;
    const auto m = emcy::parse_emcy(f);
    if (!m) {
        out.severity = Severity::Warning;
        fmt::format_to(std::back_inserter(out.text), "node {}: EMCY malformed ({} bytes)", node,
                       f.len);
        return;
    }
    const auto* prof = nodes_[node].profile;
    const auto* vendor = prof != nullptr ? prof->emcy_text() : nullptr;
    const auto text = emcy::describe(*m, vendor);
    text::put(out.text, text);
    out.severity = m->is_reset() ? Severity::Notice : Severity::Error;
    if (stats_ != nullptr) {
        stats_->on_emcy(node, m->error_code, emcy::error_code_text(m->error_code));
    }
}

void Decoder::decode_error_control(const Frame& f, NodeId node, std::int64_t ts, Decoded& out) {
    out.service = Service::Heartbeat;
    out.node = node;
    auto it = std::back_inserter(out.text);
    NodeState& n = nodes_[node];
    if (f.rtr()) {
        n.guard_requested = true;
        fmt::format_to(it, "node {} guarding request", node);
        if (stats_ != nullptr) {
            stats_->on_guard_request(node);
        }
        return;
    }
    if (f.len < 1) {
        out.severity = Severity::Warning;
        fmt::format_to(it, "node {} error control frame without data", node);
        return;
    }
    const std::uint8_t b = f.data[0];
    const auto state = nmt::state_from_byte(b);
    const std::string_view name = state ? nmt::to_string(*state) : std::string_view("invalid");
    if (n.guard_requested) {
        n.guard_requested = false;
        fmt::format_to(it, "node {} guarding reply {} (toggle {})", node, name, b >> 7);
        if (stats_ != nullptr) { // not a heartbeat: its period is the master's guard time
            stats_->on_guard_reply(node, static_cast<std::uint8_t>(b & 0x7F), (b & 0x80) != 0);
        }
        return;
    } else if (b == 0) {
        out.severity = Severity::Notice;
        fmt::format_to(it, "node {} boot-up", node);
    } else if (!state || (b & 0x80) != 0) {
        out.severity = Severity::Warning;
        fmt::format_to(it, "node {} heartbeat invalid state 0x{:02X}", node, b);
        return;
    } else {
        text::put(out.text, "node ");
        text::put_uint(out.text, node);
        text::put(out.text, " heartbeat ");
        text::put(out.text, name);
    }
    if (state && stats_ != nullptr) {
        stats_->on_heartbeat(node, static_cast<std::uint8_t>(b & 0x7F), ts);
    }
}

void Decoder::decode_lss(const Frame& f, bool from_master, Decoded& out) {
    // CiA 305 §6 command specifiers.
    out.service = Service::Lss;
    auto it = std::back_inserter(out.text);
    if (f.len < 1) {
        fmt::format_to(it, "LSS {} frame without data", from_master ? "master" : "slave");
        out.severity = Severity::Warning;
        return;
    }
    const std::uint8_t cs = f.data[0];
    const std::uint32_t u32 = f.len >= 5 ? get_le<std::uint32_t>(f.data.data() + 1) : 0;
    static constexpr std::string_view kIdent[] = {"vendor-ID", "product code", "revision number",
                                                  "serial number"};
    if (from_master) {
        text::put(out.text, "LSS ");
        if (cs == 0x04) {
            fmt::format_to(it, "switch state global: {}",
                           f.data[1] == 1 ? "configuration" : "waiting");
        } else if (cs >= 0x40 && cs <= 0x43) {
            fmt::format_to(it, "switch state selective {} 0x{:08X}", kIdent[cs - 0x40], u32);
        } else if (cs == 0x11) {
            fmt::format_to(it, "configure node-ID {}", f.data[1]);
        } else if (cs == 0x13) {
            fmt::format_to(it, "configure bit timing table {} index {}", f.data[1], f.data[2]);
        } else if (cs == 0x15) {
            fmt::format_to(it, "activate bit timing (switch delay {} ms)",
                           get_le<std::uint16_t>(f.data.data() + 1));
        } else if (cs == 0x17) {
            text::put(out.text, "store configuration");
        } else if (cs >= 0x46 && cs <= 0x4B) {
            static constexpr std::string_view kRange[] = {
                "vendor-ID",           "product code",
                "revision number low", "revision number high",
                "serial number low",   "serial number high"};
            fmt::format_to(it, "identify remote slave {} 0x{:08X}", kRange[cs - 0x46], u32);
        } else if (cs == 0x4C) {
            text::put(out.text, "identify non-configured remote slave");
        } else if (cs == 0x51) {
            fmt::format_to(it, "fastscan id 0x{:08X} bit {} sub {} next {}", u32, f.data[5],
                           f.data[6], f.data[7]);
        } else if (cs >= 0x5A && cs <= 0x5D) {
            fmt::format_to(it, "inquire {}", kIdent[cs - 0x5A]);
        } else if (cs == 0x5E) {
            text::put(out.text, "inquire node-ID");
        } else {
            fmt::format_to(it, "unknown master command 0x{:02X}", cs);
            out.severity = Severity::Warning;
        }
        return;
    }
    text::put(out.text, "LSS slave: ");
    static constexpr std::string_view kResult[] = {"ok", "not supported / out of range",
                                                   "storage access error"};
    const auto result = [&](std::uint8_t code) {
        return code < 3 ? kResult[code] : std::string_view("manufacturer error");
    };
    if (cs == 0x11 || cs == 0x13 || cs == 0x17) {
        static constexpr std::string_view kWhat[] = {"configure node-ID", "configure bit timing",
                                                     "store configuration"};
        const std::size_t w = cs == 0x11 ? 0 : cs == 0x13 ? 1 : 2;
        fmt::format_to(it, "{}: {}", kWhat[w], result(f.data[1]));
        if (f.data[1] != 0) {
            out.severity = Severity::Warning;
        }
    } else if (cs == 0x44) {
        text::put(out.text, "switch state selective confirmed");
    } else if (cs == 0x4F) {
        text::put(out.text, "identify slave");
    } else if (cs == 0x50) {
        text::put(out.text, "identify non-configured slave");
    } else if (cs >= 0x5A && cs <= 0x5D) {
        fmt::format_to(it, "{} 0x{:08X}", kIdent[cs - 0x5A], u32);
    } else if (cs == 0x5E) {
        fmt::format_to(it, "node-ID {}", f.data[1]);
    } else {
        fmt::format_to(it, "unknown response 0x{:02X}", cs);
        out.severity = Severity::Warning;
    }
}

void Decoder::decode_sdo(const Frame& f, NodeId node, bool client, std::int64_t ts, Decoded& out) {
    out.service = Service::Sdo;
    out.node = node;
    if (f.rtr()) {
        fmt::format_to(std::back_inserter(out.text), "node {} SDO remote frame (not allowed)",
                       node);
        out.severity = Severity::Warning;
        return;
    }
    const auto o = sdo_.on_frame(node, client ? sdo::Sender::Client : sdo::Sender::Server,
                                 f.payload(), ts, out.text, timed_, clock_);
    switch (o.kind) {
    case SdoOutcome::Kind::None:
        return;
    case SdoOutcome::Kind::Completed:
        out.severity = Severity::Notice;
        if (stats_ != nullptr) {
            stats_->on_sdo_done(node, o.duration_ns, o.timed);
        }
        (void)pdo_.learn(node, o.index, o.subindex, o.data);
        if (o.index == 0x1018 && (o.subindex == 1 || o.subindex == 2) && o.data.size() >= 4) {
            learn_identity(node, o.subindex, get_le<std::uint32_t>(o.data.data()));
        }
        if (stats_ != nullptr && o.index == 0x1018 && (o.subindex == 3 || o.subindex == 4) &&
            o.data.size() >= 4) {
            stats_->on_identity(node, o.subindex, get_le<std::uint32_t>(o.data.data()));
        }
        if (stats_ != nullptr && o.index == 0x1008 && o.subindex == 0) {
            std::string_view name(reinterpret_cast<const char*>(o.data.data()), o.data.size());
            stats_->on_device_name(node, name.substr(0, name.find('\0')));
        }
        return;
    case SdoOutcome::Kind::Aborted:
        out.severity = Severity::Error;
        if (stats_ != nullptr) {
            stats_->on_sdo_abort(node);
        }
        return;
    case SdoOutcome::Kind::ProtocolError:
        out.severity = Severity::Warning;
        return;
    }
}

} // namespace codrive::dump
