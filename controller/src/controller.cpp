// SPDX-License-Identifier: Apache-2.0
// The controller's composition: the bus file, the buses, nodes, PDO configuration, SYNC and
// CiA 402 axes per bus, the EtherCAT segments, and the boot-up (start()). Its cycles are in
// controller_runtime.cpp, its safe shutdown and signals in controller_shutdown.cpp.
#include <codrive/controller/controller.hpp>

#include "controller_parts.hpp"

#include <codrive/drives/profile.hpp>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <sstream>

namespace codrive::controller {
namespace {

pdo::PdoConfig to_pdo(const master::PdoConfig& c) {
    pdo::PdoConfig p;
    p.dir = c.transmit ? PdoDir::Tpdo : PdoDir::Rpdo;
    p.number = c.number;
    p.enabled = c.enabled;
    p.comm.can_id = c.cob_id.value_or(0);
    p.comm.transmission_type = c.transmission;
    p.comm.inhibit_time = c.inhibit_100us.value_or(0);
    p.comm.event_timer = c.event_timer_ms.value_or(0);
    p.comm.sync_start = c.sync_start.value_or(0);
    for (const auto& e : c.map) {
        p.mapping.push_back(pdo::MappingEntry{e.index, e.subindex, e.bits});
    }
    return p;
}

} // namespace

std::string ControllerStats::to_string() const {
    return fmt::format("cycles {}, overruns {}, SYNC error p50 {:.0f} us p99 {:.0f} us max {:.0f} "
                       "us, TPDOs received {} missing {}, RPDOs sent {}, SDO ok {} failed {}, bus "
                       "errors {}, EtherCAT frame errors {} ({} came back late)",
                       cycles, overruns, to_ms(period_error_p50) * 1000,
                       to_ms(period_error_p99) * 1000, to_ms(period_error_max) * 1000,
                       tpdos_received, tpdos_missing, rpdos_sent, sdo_completed, sdo_failed,
                       bus_errors, ecat_frame_errors, ecat_late_frames);
}

Controller::Controller(std::vector<master::BusConfig> buses,
                       std::vector<EcatSegmentConfig> segments, ControllerOptions options)
    : options_(std::move(options)), stats_cell_(std::make_unique<StatsCell>()) {
    for (auto& c : buses) {
        auto b = std::make_unique<Bus>();
        b->config = std::move(c);
        buses_.push_back(std::move(b));
    }
    for (auto& s : segments) {
        segments_.push_back(
            std::make_unique<EcatSegment>(std::move(s), buses_.size() + segments_.size(),
                                          [this](const std::string& text) { emit(text); }));
    }
}

namespace {

struct LoadedBusFile {
    std::vector<master::BusConfig> buses;
    std::vector<EcatSegmentConfig> segments;
    std::vector<std::string> findings; ///< "bus.yml:14: ..."
};

// Parses both parts of a bus file and collects every finding of both; opens no bus.
LoadedBusFile load_bus_file(const std::string& path) {
    LoadedBusFile out;
    const auto resolver =
        master::eds_resolver([](const master::NodeEntry& n,
                                std::string& error) -> std::shared_ptr<const ObjectDictionary> {
            const drives::Profile* p = drives::find_profile(n.profile);
            if (p == nullptr) {
                error = fmt::format("unknown profile `{}` (known: akd2g, ds-bvs, fio, generic)",
                                    n.profile);
                return nullptr;
            }
            auto od = std::make_shared<ObjectDictionary>();
            drives::build_device_dictionary(*od, *p, p->max_axes);
            return od;
        });
    std::ifstream in(path);
    if (!in) {
        out.findings.push_back(fmt::format("{}: cannot read the bus file", path));
        return out;
    }
    std::stringstream text;
    text << in.rdbuf();
    const BusFileSections sections = split_bus_file(text.str(), path);
    out.findings = sections.errors;
    if (sections.has_can) {
        auto r = master::parse_bus_config(sections.can_text, path, resolver);
        for (const auto& f : r.errors) {
            out.findings.push_back(f.to_string());
        }
        if (r.config) {
            out.buses.push_back(std::move(*r.config));
        }
    }
    if (sections.ethercat) {
        out.segments.push_back(*sections.ethercat);
    }
    return out;
}

} // namespace

std::vector<std::string> check_bus_file(const std::string& path) {
    return load_bus_file(path).findings;
}

tl::expected<std::unique_ptr<Controller>, ControllerError>
Controller::from_file(const std::string& path, ControllerOptions options) {
    LoadedBusFile loaded = load_bus_file(path);
    if (!loaded.findings.empty()) {
        std::string errors;
        for (const auto& f : loaded.findings) {
            errors += f + "\n";
        }
        return tl::unexpected(ControllerError(ControllerErrc::BusFileInvalid, std::move(errors)));
    }
    return create(std::move(loaded.buses), std::move(loaded.segments), std::move(options));
}

tl::expected<std::unique_ptr<Controller>, ControllerError>
Controller::create(std::vector<master::BusConfig> buses, ControllerOptions options) {
    return create(std::move(buses), {}, std::move(options));
}

tl::expected<std::unique_ptr<Controller>, ControllerError>
Controller::create(std::vector<master::BusConfig> buses, std::vector<EcatSegmentConfig> segments,
                   ControllerOptions options) {
    if (buses.empty() && segments.empty()) {
        return tl::unexpected(
            ControllerError(ControllerErrc::InvalidConfiguration, "no bus configured"));
    }
    std::unique_ptr<Controller> c(
        new Controller(std::move(buses), std::move(segments), std::move(options)));
    auto loop = EventLoop::create();
    if (!loop) {
        return tl::unexpected(ControllerError(
            ControllerErrc::EventLoopFailed,
            fmt::format("cannot create the event loop: {}", loop.error().message()), loop.error()));
    }
    c->loop_ = std::move(*loop);
    if (c->options_.event_summary_interval > Duration::zero()) {
        Controller* raw = c.get();
        c->limiter_ = std::make_unique<EventRateLimiter>(
            [raw](std::string_view text) {
                if (raw->event_cb_) {
                    raw->event_cb_(std::string(text));
                }
            },
            c->options_.event_summary_interval);
        c->loop_->add_timed(c->limiter_.get());
    }
    return c;
}

void Controller::emit(const std::string& text) {
    emit(text, text);
}

void Controller::emit(const std::string& text, const std::string& key) {
    if (limiter_) {
        limiter_->offer(key, text, loop_->now());
    } else if (event_cb_) {
        event_cb_(text);
    }
}

tl::expected<void, ControllerError> Controller::open_bus(Bus& b, std::size_t index) {
    if (index < options_.buses.size() && options_.buses[index] != nullptr) {
        b.bus = options_.buses[index];
        return {};
    }
    SocketCanOptions so;
    so.rcvbuf_bytes = options_.rcvbuf_bytes;
    auto s = SocketCanBus::open(b.config.iface, so);
    if (!s) {
        return tl::unexpected(ControllerError(ControllerErrc::BusOpenFailed,
                                              describe_can_open_error(b.config.iface, s.error()),
                                              s.error()));
    }
    if (auto r = (*s)->attach(*loop_); !r) {
        return tl::unexpected(ControllerError(
            ControllerErrc::BusOpenFailed,
            fmt::format("cannot watch {}: {}", b.config.iface, r.error().message()), r.error()));
    }
    b.socket = std::move(*s);
    b.bus = b.socket.get();
    return {};
}

void Controller::setup_node(Bus& b, const master::NodeEntry& entry) {
    auto n = std::make_unique<Node>();
    n->entry = entry;
    n->profile = entry.profile.empty() ? nullptr : drives::find_profile(entry.profile);
    master::NodeConfig nc = master::to_node_config(entry);
    if (n->profile != nullptr) {
        n->od = std::make_shared<ObjectDictionary>();
        drives::build_device_dictionary(*n->od, *n->profile, n->profile->max_axes);
        b.master->emcy().set_text_provider(entry.id, drives::emcy_text_provider(*n->profile));
        // Mode writes go to each axis's own 6060h (AKD2G axis 2: 6860h).
        for (auto& w : nc.writes) {
            for (const auto& ax : entry.axes) {
                if (ax.mode && w.index == 0x6060 + 0x800 * (ax.axis - 1)) {
                    w.index = n->profile->axis_index(0x6060, ax.axis);
                }
            }
        }
    }
    for (const auto& p : entry.pdos) {
        n->pdos.push_back(to_pdo(p));
    }
    if (n->pdos.empty() && n->profile != nullptr && !entry.axes.empty()) {
        std::vector<drives::cia402::Mode> modes;
        for (const auto& ax : entry.axes) {
            modes.push_back(static_cast<drives::cia402::Mode>(ax.mode.value_or(8)));
        }
        if (auto configs = drives::mode_pdo_configs(*n->profile, modes); configs) {
            n->pdos = std::move(*configs);
        } else {
            emit(fmt::format("node {}: no PDO layout for the configured modes ({}); axes will be "
                             "polled over SDO",
                             entry.id, configs.error().message));
        }
    }
    Node* raw = n.get();
    if (!n->pdos.empty()) {
        nc.steps.push_back(master::NamedStep{
            "PDO configuration", [this, raw](sdo::SdoClient& client, master::StepDone done) {
                pdo::DeviceModel dm;
                dm.od = raw->od.get();
                if (raw->profile != nullptr) {
                    dm.quirks = drives::pdo_quirks(*raw->profile);
                }
                raw->configurator = std::make_unique<pdo::PdoConfigurator>(client, dm);
                const bool ok = raw->configurator->configure(
                    raw->pdos, [done](pdo::PdoResult<pdo::ConfigureReport> r) {
                        if (!r) {
                            done(r.error().message);
                        } else {
                            done(std::nullopt);
                        }
                    });
                if (!ok) {
                    done(fmt::format("node {}: a PDO configuration is already running",
                                     raw->entry.id));
                }
            }});
    }
    b.master->add_node(std::move(nc));
    n->transport = std::make_unique<drives::CanopenTransport>(b.master->sdo().client(entry.id));
    drives::DriveTransport* axis_transport = n->transport.get();
    if (dedicated()) {
        n->handoff = std::make_unique<HandoffTransport>(*n->transport, "acyclic thread");
        axis_transport = n->handoff.get();
    }
    const unsigned axis_count = entry.axes.empty() ? (n->profile != nullptr ? 1U : 0U)
                                                   : static_cast<unsigned>(entry.axes.size());
    for (unsigned i = 0; i < axis_count; ++i) {
        drives::AxisConfig ac;
        ac.axis = entry.axes.empty() ? 1 : entry.axes[i].axis;
        ac.profile = n->profile;
        ac.name = fmt::format("node {} axis {}{}", entry.id, ac.axis,
                              entry.name.empty() ? std::string() : " (" + entry.name + ")");
        auto axis = std::make_unique<drives::Axis>(*axis_transport, ac);
        if (!dedicated()) {
            loop_->add_timed(axis.get()); // dedicated: the cyclic thread ticks it
        }
        n->axes.push_back(std::move(axis));
    }
    b.nodes[entry.id] = std::move(n);
}

void Controller::after_boot(Bus& b, Node& n) {
    if (n.image_bound || n.pdos.empty()) {
        return;
    }
    auto image = b.pdo->add_node(n.entry.id, n.pdos);
    if (!image) {
        emit(fmt::format("node {}: PDOs not used: {}", n.entry.id, image.error().message));
        return;
    }
    n.transport->set_image(*image);
    for (auto& a : n.axes) {
        a->bind();
    }
    n.image_bound = true;
}

namespace {

/// The kernel filters for the cyclic socket: the TPDOs of every node (CiA 301 §7.3.5 predefined
/// COB-IDs when the file gives none). Empty (= receive everything) if one cannot be told.
std::vector<CanFilter> tpdo_filters(const std::vector<std::pair<NodeId, pdo::PdoConfig>>& pdos) {
    std::vector<CanFilter> out;
    for (const auto& [node, p] : pdos) {
        if (p.dir != PdoDir::Tpdo || !p.enabled) {
            continue;
        }
        std::uint32_t id = p.comm.can_id & 0x7FFU;
        if (id == 0) {
            if (p.number > 4) {
                return {};
            }
            id = 0x80U + 0x100U * p.number + node;
        }
        out.push_back(CanFilter{id, 0x7FF, false, false});
    }
    if (out.empty()) {
        out.push_back(CanFilter{0, 0x7FF, false, false}); // NMT only: the cyclic side ignores it
    }
    return out;
}

} // namespace

tl::expected<void, ControllerError> Controller::start() {
    if (start_called_) {
        return tl::unexpected(ControllerError(
            ControllerErrc::AlreadyStarted,
            "start() was already called on this controller; a controller starts once"));
    }
    start_called_ = true;
    if (!dedicated()) {
        caller_schedule_.emplace();
        for (const auto& w : apply_realtime(options_.realtime)) {
            emit("warning: " + w);
        }
    } else {
        for (auto* given : options_.buses) {
            if (given != nullptr) {
                return tl::unexpected(ControllerError(
                    ControllerErrc::InvalidConfiguration,
                    "Threading::DedicatedCyclic needs SocketCAN interfaces (the cyclic thread "
                    "opens its own socket); ControllerOptions::buses work in Threading::Single"));
            }
        }
    }
    for (std::size_t i = 0; i < buses_.size(); ++i) {
        Bus& b = *buses_[i];
        if (auto r = open_bus(b, i); !r) {
            return r;
        }
        ICanBus* cyclic_bus = b.bus;
        if (dedicated()) {
            SocketCanOptions so;
            so.error_frames = false; // the acyclic socket reports bus errors
            so.timestamps = false;   // no clock reads per frame on the cyclic path
            so.filters = {CanFilter{0, 0x7FF, false, false}}; // until the TPDOs are known
            so.rcvbuf_bytes = options_.rcvbuf_bytes;
            auto cs = SocketCanBus::open(b.config.iface, so);
            if (!cs) {
                return tl::unexpected(
                    ControllerError(ControllerErrc::BusOpenFailed,
                                    fmt::format("cannot open {} for the cyclic thread: {}",
                                                b.config.iface, cs.error().message()),
                                    cs.error()));
            }
            b.cyclic_socket = std::move(*cs);
            cyclic_bus = b.cyclic_socket.get();
        }
        master::MasterConfig mc;
        mc.node_id = b.config.master_id;
        mc.heartbeat_period = b.config.master_heartbeat;
        b.master = std::make_unique<master::Master>(*b.bus, RealClock::instance(), mc);
        b.pdo = std::make_unique<pdo::PdoMaster>(*cyclic_bus);
        b.sync = std::make_unique<sync::SyncProducer>(*cyclic_bus);
        Bus* bp = &b;
        if (dedicated()) {
            b.cyclic_socket->set_frame_handler(
                [bp](const Frame& f, TimePoint t) { bp->pdo->on_frame(f, t); });
            b.pdo->set_event_handler([bp](const pdo::PdoEvent& e) {
                pdo::PdoEvent copy = e;
                (void)bp->pdo_events.push(copy); // dropped when 64 are waiting: counted in stats
            });
        } else {
            b.master->add_listener([bp](const Frame& f, TimePoint t) { bp->pdo->on_frame(f, t); });
            b.pdo->set_event_handler(
                [this](const pdo::PdoEvent& e) { emit(pdo::to_string(e), pdo::event_key(e)); });
        }
        b.master->set_event_handler([this, bp](const master::MasterEvent& e) {
            if (e.kind == master::MasterEventKind::BusEvent) {
                ++bp->bus_errors;
            }
            if (e.kind == master::MasterEventKind::Emcy) {
                if (auto it = bp->nodes.find(e.node); it != bp->nodes.end()) {
                    if (auto* rn = bp->master->node(e.node); rn != nullptr && rn->last_emcy()) {
                        const std::uint16_t code = rn->last_emcy()->message.error_code;
                        if (dedicated()) {
                            it->second->emcy_code.store(code); // the cyclic thread applies it
                        } else {
                            for (auto& a : it->second->axes) {
                                a->note_error_code(code);
                            }
                        }
                    }
                }
            }
            if (e.kind == master::MasterEventKind::BootCompleted ||
                e.kind == master::MasterEventKind::BootFailed) {
                // The boot report (emitted below for every node) and start()'s error carry the
                // same sentence; forwarding it too printed every boot failure twice.
                return;
            }
            emit(e.text,
                 e.node == 0
                     ? fmt::format("bus {}: {}", bp->config.iface, master::to_string(e.kind))
                     : fmt::format("node {}: {}", e.node, master::to_string(e.kind)));
        });
        loop_->add_timed(b.master.get());
        if (!dedicated()) {
            loop_->add_timed(b.pdo.get());
        }
        std::vector<std::pair<NodeId, pdo::PdoConfig>> all_pdos;
        for (const auto& entry : b.config.nodes) {
            setup_node(b, entry);
            for (const auto& p : b.nodes[entry.id]->pdos) {
                all_pdos.emplace_back(entry.id, p);
            }
        }
        if (dedicated()) {
            if (auto r = b.cyclic_socket->set_filters(tpdo_filters(all_pdos)); !r) {
                return tl::unexpected(
                    ControllerError(ControllerErrc::BusOpenFailed,
                                    fmt::format("cannot set the cyclic socket's filters on {}: {}",
                                                b.config.iface, r.error().message()),
                                    r.error()));
            }
        }
    }
    // EtherCAT segments come up synchronously (the EtherCAT master's acyclic API waits for each
    // frame); they cycle from the loop from then on, also while the CAN nodes boot.
    for (auto& seg : segments_) {
        if (auto r = seg->bring_up(nullptr, dedicated()); !r) {
            return r;
        }
        seg->start_cycles(loop_->now() + milliseconds(1), [this](const CycleInfo& info) {
            if (cycle_cb_) {
                cycle_cb_(info);
            }
            publish_cyclic_stats(false);
        });
        loop_->add_timed(seg.get());
    }
    if (stop_requested_) {
        return abandon_start("stopped by request before the boot-up");
    }
    // Boot every bus's nodes in parallel. The counters are members: a boot-up abandoned by a
    // stop request or its timeout must not leave callbacks pointing into this stack frame.
    boot_pending_ = buses_.size();
    boot_ok_ = true;
    for (auto& bptr : buses_) {
        Bus* bp = bptr.get();
        bp->master->boot_all([this, bp](const std::vector<master::BootReport>& r) {
            for (const auto& rep : r) {
                reports_.push_back(rep);
                emit(rep.to_string());
                boot_ok_ = boot_ok_ && rep.ok;
                if (rep.ok) {
                    if (auto it = bp->nodes.find(rep.node); it != bp->nodes.end()) {
                        after_boot(*bp, *it->second);
                    }
                }
            }
            --boot_pending_;
        });
    }
    const bool booted = loop_->run_until([&] { return boot_pending_ == 0 || stop_requested_; },
                                         options_.boot_timeout);
    if (stop_requested_) {
        return abandon_start("stopped by request during the boot-up");
    }
    if (!booted) {
        return tl::unexpected(ControllerError(
            ControllerErrc::BootTimeout,
            fmt::format("boot-up did not finish within {:.0f} ms", to_ms(options_.boot_timeout))));
    }
    const bool all_ok = boot_ok_;
    if (!all_ok) {
        std::string msg = "boot-up failed:";
        for (const auto& r : reports_) {
            if (!r.ok) {
                msg += "\n  " + r.error();
            }
        }
        return tl::unexpected(ControllerError(ControllerErrc::NodeBootFailed, std::move(msg)));
    }
    // Axes learn the state from the first TPDOs; SYNC drives everything from now on.
    for (auto& bptr : buses_) {
        Bus* bp = bptr.get();
        if (bp->config.sync_period_us == 0) {
            continue;
        }
        sync::SyncConfig sc;
        sc.period = microseconds(bp->config.sync_period_us);
        if (auto r = bp->sync->configure(sc); !r) {
            return tl::unexpected(
                ControllerError(ControllerErrc::SyncFailed,
                                fmt::format("cannot configure SYNC on {}: {}", bp->config.iface,
                                            r.error().message()),
                                r.error()));
        }
        // The cycle computes its RPDOs first, then the SYNC and the RPDOs leave in one
        // send_many() (SYNC first: CiA 301 §7.2.2.2, the RPDOs ride in the synchronous window
        // it opens and are actuated at the next SYNC).
        bp->sync->set_sender([this, bp](const Frame& f, const sync::SyncInfo& s) {
            return on_sync(*bp, CycleInfo{s.cycle, s.ideal, s.actual, 0}, f);
        });
        bp->sync->start(loop_->now() + milliseconds(1));
        if (!dedicated()) {
            loop_->add_timed(bp->sync.get());
        }
    }
    started_ = true;
    if (dedicated()) {
        return start_cyclic_thread();
    }
    return {};
}

drives::Axis* Controller::axis(NodeId node, unsigned number, std::size_t bus) {
    if (bus >= buses_.size()) {
        const std::size_t seg = bus - buses_.size();
        return seg < segments_.size() ? segments_[seg]->axis(node, number) : nullptr;
    }
    auto it = buses_[bus]->nodes.find(node);
    if (it == buses_[bus]->nodes.end()) {
        return nullptr;
    }
    for (auto& a : it->second->axes) {
        if (a->number() == number) {
            return a.get();
        }
    }
    return nullptr;
}

std::vector<AxisRef> Controller::axes() const {
    std::vector<AxisRef> out;
    for (std::size_t i = 0; i < buses_.size(); ++i) {
        for (const auto& [id, n] : buses_[i]->nodes) {
            for (const auto& a : n->axes) {
                std::optional<std::int8_t> mode;
                for (const auto& e : n->entry.axes) {
                    if (e.axis == a->number()) {
                        mode = e.mode;
                    }
                }
                out.push_back(AxisRef{i, id, a->number(), a.get(), a->name(), mode});
            }
        }
    }
    for (const auto& seg : segments_) {
        seg->collect_axes(out);
    }
    return out;
}

master::Master& Controller::master(std::size_t bus) {
    return *buses_.at(bus)->master;
}

const master::BusConfig& Controller::config(std::size_t bus) const {
    return buses_.at(bus)->config;
}

} // namespace codrive::controller
