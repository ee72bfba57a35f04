// SPDX-License-Identifier: Apache-2.0
// The controller: composes master (boot-up, supervision), PDO configuration and engine, SYNC
// and CiA 402 axes per bus, and shuts everything down safely.
#include <codrive/controller/controller.hpp>

#include "ecat_segment.hpp"
#include "handoff_transport.hpp"
#include "seqlock.hpp"
#include "spsc_ring.hpp"

#include <codrive/core/socket_can_bus.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/drives/safe_stop.hpp>
#include <codrive/master/master.hpp>
#include <codrive/pdo/configure.hpp>
#include <codrive/pdo/master.hpp>
#include <codrive/sync/producer.hpp>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <sstream>

namespace codrive::controller {

struct Controller::Node {
    master::NodeEntry entry;
    const drives::Profile* profile = nullptr;
    std::shared_ptr<ObjectDictionary> od; ///< the profile's dictionary, for PDO validation
    std::vector<pdo::PdoConfig> pdos;
    std::unique_ptr<pdo::PdoConfigurator> configurator;
    std::unique_ptr<drives::CanopenTransport> transport;
    /// Dedicated-cyclic mode: the axes' transport (object accesses handed to the acyclic side).
    std::unique_ptr<HandoffTransport> handoff;
    std::vector<std::unique_ptr<drives::Axis>> axes;
    bool image_bound = false;
    std::atomic<std::uint16_t> emcy_code{0}; ///< dedicated mode: last EMCY, for the axes
};

struct Controller::Bus {
    master::BusConfig config;
    std::unique_ptr<SocketCanBus> socket;
    ICanBus* bus = nullptr;
    std::unique_ptr<master::Master> master;
    std::unique_ptr<pdo::PdoMaster> pdo;
    std::unique_ptr<sync::SyncProducer> sync;
    std::map<NodeId, std::unique_ptr<Node>> nodes;
    std::uint64_t bus_errors = 0;
    /// Dedicated-cyclic mode: the cyclic thread's own socket (SYNC and RPDOs out, TPDOs in,
    /// filtered by the kernel) and the PDO events it hands to the acyclic thread.
    std::unique_ptr<SocketCanBus> cyclic_socket;
    SpscRing<pdo::PdoEvent, 64> pdo_events;
};

/// The cyclic figures of stats(), published by whichever thread owns the cycles (the loop
/// thread in Threading::Single, the cyclic thread in Threading::DedicatedCyclic, the loop thread
/// again after the cyclic thread was joined): one writer at a time, lock-free readers.
struct Controller::StatsCell {
    Seqlock<ControllerStats> snapshot;
    // Writer side only: percentiles scan the histogram (a few thousand buckets), so they are
    // recomputed every kPercentileEvery publications, not every cycle.
    static constexpr std::uint64_t kPercentileEvery = 256;
    std::uint64_t publications = 0;
    Duration p50{0};
    Duration p99{0};
};

/// Dedicated-cyclic mode, acyclic side: starts the object accesses the cyclic thread queued
/// and reports its PDO events, once per millisecond.
class Controller::Pump final : public ITimed {
public:
    explicit Pump(Controller& c) : c_(c) {}
    [[nodiscard]] TimePoint next_deadline() const override { return next_; }
    void on_tick(TimePoint now) override {
        if (now < next_) {
            return;
        }
        next_ = now + milliseconds(1);
        c_.pump_acyclic();
    }

private:
    Controller& c_;
    TimePoint next_{};
};

namespace {

/// The controller SIGINT/SIGTERM stop (stop_on_signals()); atomic because the handler reads it.
std::atomic<Controller*> g_signal_target{nullptr};
static_assert(std::atomic<Controller*>::is_always_lock_free, "read in a signal handler");

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
                       "errors {}, EtherCAT frame errors {}",
                       cycles, overruns, to_ms(period_error_p50) * 1000,
                       to_ms(period_error_p99) * 1000, to_ms(period_error_max) * 1000,
                       tpdos_received, tpdos_missing, rpdos_sent, sdo_completed, sdo_failed,
                       bus_errors, ecat_frame_errors);
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

Controller::~Controller() {
    if (started_ && !stopped_) {
        shutdown();
    }
    Controller* self = this;
    (void)g_signal_target.compare_exchange_strong(self, nullptr);
    if (limiter_) {
        loop_->remove_timed(limiter_.get());
    }
    for (auto& b : buses_) {
        for (auto& [id, n] : b->nodes) {
            for (auto& a : n->axes) {
                loop_->remove_timed(a.get());
            }
        }
        if (b->master) {
            loop_->remove_timed(b->master.get());
        }
        if (b->pdo) {
            loop_->remove_timed(b->pdo.get());
        }
        if (b->sync) {
            loop_->remove_timed(b->sync.get());
        }
    }
    for (auto& seg : segments_) {
        loop_->remove_timed(seg.get());
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

tl::expected<std::unique_ptr<Controller>, std::string>
Controller::from_file(const std::string& path, ControllerOptions options) {
    LoadedBusFile loaded = load_bus_file(path);
    if (!loaded.findings.empty()) {
        std::string errors;
        for (const auto& f : loaded.findings) {
            errors += f + "\n";
        }
        return tl::unexpected(errors);
    }
    return create(std::move(loaded.buses), std::move(loaded.segments), std::move(options));
}

tl::expected<std::unique_ptr<Controller>, std::string>
Controller::create(std::vector<master::BusConfig> buses, ControllerOptions options) {
    return create(std::move(buses), {}, std::move(options));
}

tl::expected<std::unique_ptr<Controller>, std::string>
Controller::create(std::vector<master::BusConfig> buses, std::vector<EcatSegmentConfig> segments,
                   ControllerOptions options) {
    if (buses.empty() && segments.empty()) {
        return tl::unexpected(std::string("no bus configured"));
    }
    std::unique_ptr<Controller> c(
        new Controller(std::move(buses), std::move(segments), std::move(options)));
    auto loop = EventLoop::create();
    if (!loop) {
        return tl::unexpected(
            fmt::format("cannot create the event loop: {}", loop.error().message()));
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

tl::expected<void, std::string> Controller::open_bus(Bus& b, std::size_t index) {
    if (index < options_.buses.size() && options_.buses[index] != nullptr) {
        b.bus = options_.buses[index];
        return {};
    }
    SocketCanOptions so;
    so.rcvbuf_bytes = options_.rcvbuf_bytes;
    auto s = SocketCanBus::open(b.config.iface, so);
    if (!s) {
        return tl::unexpected(describe_can_open_error(b.config.iface, s.error()));
    }
    if (auto r = (*s)->attach(*loop_); !r) {
        return tl::unexpected(
            fmt::format("cannot watch {}: {}", b.config.iface, r.error().message()));
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
        n->handoff = std::make_unique<HandoffTransport>(*n->transport);
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

tl::expected<void, std::string> Controller::start() {
    if (!dedicated()) {
        caller_schedule_.emplace();
        for (const auto& w : apply_realtime(options_.realtime)) {
            emit("warning: " + w);
        }
    } else {
        for (auto* given : options_.buses) {
            if (given != nullptr) {
                return tl::unexpected(std::string(
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
                return tl::unexpected(fmt::format("cannot open {} for the cyclic thread: {}",
                                                  b.config.iface, cs.error().message()));
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
                    fmt::format("cannot set the cyclic socket's filters on {}: {}", b.config.iface,
                                r.error().message()));
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
        return tl::unexpected(
            fmt::format("boot-up did not finish within {:.0f} ms", to_ms(options_.boot_timeout)));
    }
    const bool all_ok = boot_ok_;
    if (!all_ok) {
        std::string msg = "boot-up failed:";
        for (const auto& r : reports_) {
            if (!r.ok) {
                msg += "\n  " + r.error();
            }
        }
        return tl::unexpected(msg);
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
            return tl::unexpected(fmt::format("cannot configure SYNC on {}: {}", bp->config.iface,
                                              r.error().message()));
        }
        bp->sync->set_hook([this, bp](const sync::SyncInfo& s) {
            on_sync(*bp, CycleInfo{s.cycle, s.ideal, s.actual, 0});
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

tl::expected<void, std::string> Controller::start_cyclic_thread() {
    // The segments cycled from the loop while the CAN nodes booted; the cyclic thread owns
    // their cycles from now on.
    for (auto& seg : segments_) {
        loop_->remove_timed(seg.get());
    }
    pump_ = std::make_unique<Pump>(*this);
    loop_->add_timed(pump_.get());
    cyclic_thread_ = std::thread([this] { cyclic_main(); });
    // The thread reports its real-time warnings before its first cycle.
    while (!cyclic_ready_.load(std::memory_order_acquire)) {
        std::this_thread::yield();
    }
    for (const auto& w : cyclic_warnings_) {
        emit("warning: " + w);
    }
    return {};
}

void Controller::for_each_axis(const std::function<void(drives::Axis&)>& fn) {
    for (auto& b : buses_) {
        for (auto& [id, n] : b->nodes) {
            for (auto& a : n->axes) {
                fn(*a);
            }
        }
    }
    for (auto& seg : segments_) {
        seg->for_each_axis(fn);
    }
}

void Controller::pump_acyclic() {
    for (auto& b : buses_) {
        for (auto& [id, n] : b->nodes) {
            if (n->handoff) {
                n->handoff->pump_requests();
            }
        }
        pdo::PdoEvent e;
        while (b->pdo_events.pop(e)) {
            emit(pdo::to_string(e), pdo::event_key(e));
        }
    }
    const TimePoint now = loop_->now();
    for (auto& seg : segments_) {
        seg->acyclic_step(now);
    }
}

void Controller::set_cycle_callback(CycleCallback cb) {
    if (!dedicated() || !cyclic_thread_.joinable() ||
        std::this_thread::get_id() == cyclic_thread_.get_id()) {
        cycle_cb_ = std::move(cb); // no other thread calls it
        return;
    }
    // The cyclic thread calls cycle_cb_: it swaps the new one in at its next wake-up (a swap of
    // two std::function objects allocates nothing); the old one comes back in pending_cb_ and is
    // destroyed here, off the cyclic thread.
    pending_cb_ = std::move(cb);
    cb_handoff_.store(true, std::memory_order_release);
    while (cb_handoff_.load(std::memory_order_acquire)) {
        std::this_thread::yield();
    }
    pending_cb_ = nullptr;
}

void Controller::cyclic_main() {
    cyclic_warnings_ = apply_realtime(options_.realtime);
    cyclic_ready_.store(true, std::memory_order_release);
    bool safe_stop_started = false;
    while (!cyclic_exit_.load(std::memory_order_acquire)) {
        // Sleep until the earliest SYNC (at most 20 ms, to notice a stop request).
        TimePoint wake = SteadyClock::now() + milliseconds(20);
        for (auto& b : buses_) {
            wake = std::min(wake, b->sync->next_deadline());
        }
        for (auto& seg : segments_) {
            wake = std::min(wake, seg->next_cycle());
        }
        const auto ns = wake.time_since_epoch().count();
        timespec ts{static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
        while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
        }
        if (cb_handoff_.load(std::memory_order_acquire)) {
            std::swap(cycle_cb_, pending_cb_);
            cb_handoff_.store(false, std::memory_order_release);
        }
        const TimePoint now = SteadyClock::now();
        for (auto& b : buses_) {
            (void)b->cyclic_socket->read_available(); // this cycle's TPDOs into the image
            for (auto& [id, n] : b->nodes) {
                if (n->handoff) {
                    n->handoff->deliver_completions();
                }
                if (const std::uint16_t code = n->emcy_code.exchange(0); code != 0) {
                    for (auto& a : n->axes) {
                        a->note_error_code(code);
                    }
                }
            }
            if (b->sync->next_deadline() <= now) {
                b->sync->on_tick(now); // SYNC out, then on_sync(): callback, axes, RPDOs
            }
            if (b->pdo->next_deadline() <= now) {
                b->pdo->on_tick(now);
            }
            for (auto& [id, n] : b->nodes) {
                for (auto& a : n->axes) {
                    if (a->next_deadline() <= now) {
                        a->on_tick(now); // operation timeouts (SDO polling without PDOs)
                    }
                }
            }
            (void)b->cyclic_socket->flush();
        }
        for (auto& seg : segments_) {
            seg->cyclic_step(now);
        }
        if (safe_stop_requested_.load(std::memory_order_acquire) && !safe_stop_started) {
            safe_stop_started = true;
            begin_safe_stop(now);
        }
        if (safe_stop_started && safe_stop_over(now)) {
            end_safe_stop();
            for (auto& b : buses_) {
                b->sync->stop();
            }
            axes_safe_.store(true, std::memory_order_release);
            safe_stop_started = false;
        }
    }
}

void Controller::on_sync(Bus& b, const CycleInfo& info) {
    // Inputs of the last cycle are in the image: let the application compute set-points, the
    // axes turn them into controlwords and targets, then the RPDOs for this SYNC go out.
    if (cycle_cb_) {
        cycle_cb_(info);
    }
    for (auto& [id, n] : b.nodes) {
        if (!n->image_bound) {
            continue;
        }
        for (auto& a : n->axes) {
            a->on_cycle(info.actual);
        }
    }
    b.pdo->on_sync(info.cycle, info.actual);
    publish_cyclic_stats(false);
}

void Controller::begin_safe_stop(TimePoint now) {
    safe_stop_ = SafeStop{true, 0, now + options_.shutdown_timeout};
    for_each_axis([this](drives::Axis& a) {
        drives::Axis* ax = &a;
        ++safe_stop_.pending; // before: done may run before safe_stop() returns
        const bool started = drives::safe_stop(
            a, safe_stop_.deadline, RealClock::instance(), [this, ax](drives::DriveVoid r) {
                if (!safe_stop_.active) {
                    return; // cancelled by end_safe_stop(): the shutdown is over
                }
                if (!r && !dedicated()) {
                    emit(fmt::format("{}: safe stop during shutdown failed: {}", ax->name(),
                                     r.error().message));
                }
                --safe_stop_.pending;
            });
        if (!started) {
            --safe_stop_.pending;
        }
    });
}

bool Controller::safe_stop_over(TimePoint now) const {
    return safe_stop_.pending == 0 || now >= safe_stop_.deadline;
}

void Controller::end_safe_stop() {
    // Out of time: the operations still running on drives that did not answer end here, so no
    // callback of this shutdown runs during a later run_for().
    safe_stop_.active = false;
    for_each_axis([](drives::Axis& a) {
        if (a.busy()) {
            a.cancel();
        }
    });
    safe_stop_.pending = 0;
}

void Controller::run_loop_until(const std::function<bool()>& pred, TimePoint deadline) {
    while (!pred()) {
        const TimePoint now = loop_->now();
        if (now >= deadline) {
            return;
        }
        (void)loop_->run_until(pred, deadline - now);
    }
}

void Controller::stop_buses() {
    for (auto& b : buses_) {
        (void)b->master->nmt().enter_pre_operational(0);
        if (b->sync) {
            b->sync->stop();
        }
    }
    for (auto& seg : segments_) {
        seg->stop(); // ESM back to PRE-OP: outputs no longer applied
        loop_->remove_timed(seg.get());
    }
    // Let the NMT frames and any queued frames leave.
    const TimePoint flushed = loop_->now() + milliseconds(20);
    run_loop_until([] { return false; }, flushed);
}

tl::expected<void, std::string> Controller::abandon_start(std::string why) {
    // The boot-up state machines must not start a node after the NMT command below: they get
    // no more frames and no more ticks.
    for (auto& b : buses_) {
        if (b->master) {
            loop_->remove_timed(b->master.get());
            b->bus->set_frame_handler(nullptr);
            b->bus->set_event_handler(nullptr);
        }
    }
    stop_buses();
    if (caller_schedule_) {
        caller_schedule_->restore();
        caller_schedule_.reset();
    }
    return tl::unexpected(std::move(why));
}

void Controller::shutdown() {
    if (!started_ || stopped_) {
        return;
    }
    stopped_ = true;
    if (dedicated()) {
        // The axes belong to the cyclic thread: it stops them while this thread keeps serving
        // their SDO accesses, then it stops SYNC and exits.
        safe_stop_requested_.store(true, std::memory_order_release);
        run_loop_until([&] { return axes_safe_.load(std::memory_order_acquire); },
                       loop_->now() + options_.shutdown_timeout + milliseconds(100));
        cyclic_exit_.store(true, std::memory_order_release);
        if (cyclic_thread_.joinable()) {
            cyclic_thread_.join();
        }
        if (safe_stop_.active) {
            end_safe_stop(); // the cyclic thread did not get to it; it has exited now
        }
        loop_->remove_timed(pump_.get());
        pump_acyclic(); // the last PDO events
    } else {
        begin_safe_stop(loop_->now());
        run_loop_until([&] { return safe_stop_over(loop_->now()); }, safe_stop_.deadline);
        end_safe_stop();
    }
    for_each_axis([this](drives::Axis& a) {
        if (a.state() == drives::cia402::State::QuickStopActive) {
            // Not disabled on purpose: disable voltage during the ramp would let it coast.
            emit(fmt::format("{}: still QUICK STOP ACTIVE after the safe shutdown: no standstill "
                             "(statusword bit 10) within {:.0f} ms; left decelerating on its "
                             "quick-stop ramp, not disabled",
                             a.name(), to_ms(options_.shutdown_timeout)));
        } else if (drives::needs_safe_stop(a.state())) {
            emit(fmt::format("{}: still {} after the safe shutdown: the drive did not confirm "
                             "quick stop and disable within {:.0f} ms",
                             a.name(), drives::cia402::to_string(a.state()),
                             to_ms(options_.shutdown_timeout)));
        }
    });
    stop_buses();
    if (caller_schedule_) {
        caller_schedule_->restore();
        caller_schedule_.reset();
    }
    publish_cyclic_stats(true); // cycles have ended (cyclic thread joined): exact figures
}

void Controller::run() {
    while (!stop_requested_ && !stopped_) {
        (void)loop_->poll_once(milliseconds(50));
    }
    shutdown();
}

void Controller::run_for(Duration d) {
    const TimePoint end = loop_->now() + d;
    while (!stop_requested_ && loop_->now() < end) {
        (void)loop_->poll_once(std::min<Duration>(end - loop_->now(), milliseconds(50)));
    }
}

bool Controller::run_until(const std::function<bool()>& pred, Duration timeout) {
    return loop_->run_until([&] { return pred() || stop_requested_.load(); }, timeout) && pred();
}

void Controller::request_stop() {
    stop_requested_ = true;
    if (loop_) {
        loop_->stop(); // an atomic store and an eventfd write: async-signal-safe
    }
}

void Controller::on_signal(int sig) {
    if (Controller* c = g_signal_target.load(); c != nullptr) {
        int none = 0;
        (void)c->stop_signal_.compare_exchange_strong(none, sig); // the first signal counts
        c->request_stop();
    }
}

void Controller::stop_on_signals() {
    g_signal_target = this;
    struct sigaction sa {};
    sa.sa_handler = &Controller::on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART; // stdio and blocking calls elsewhere need not handle EINTR
    (void)::sigaction(SIGINT, &sa, nullptr);
    (void)::sigaction(SIGTERM, &sa, nullptr);
}

void Controller::post(std::function<void()> fn) {
    loop_->post(std::move(fn));
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
                out.push_back(AxisRef{i, id, a->number(), a.get(), a->name()});
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

void Controller::publish_cyclic_stats(bool exact_percentiles) {
    // Runs on the cycle owner: reads only what that thread owns (SYNC producers, PDO engines,
    // segments' cycle counters and histograms), allocates nothing.
    StatsCell& cell = *stats_cell_;
    const bool refresh = exact_percentiles || cell.publications % StatsCell::kPercentileEvery == 0;
    ++cell.publications;
    ControllerStats s;
    Duration p50{0};
    Duration p99{0};
    const auto add_period = [&](const sync::PeriodStats& pe) {
        if (refresh) {
            p50 = std::max(p50, pe.p50());
            p99 = std::max(p99, pe.p99());
        }
        s.period_error_max = std::max(s.period_error_max, pe.max());
    };
    for (const auto& b : buses_) {
        if (b->sync) {
            s.cycles += b->sync->sent();
            s.overruns += b->sync->skipped();
            add_period(b->sync->period_error());
        }
        if (b->pdo) {
            s.tpdos_received += b->pdo->stats().tpdos_received;
            s.tpdos_missing += b->pdo->stats().tpdos_missing;
            s.rpdos_sent += b->pdo->stats().rpdos_sent;
        }
    }
    for (const auto& seg : segments_) {
        s.cycles += seg->cycles();
        s.overruns += seg->overruns();
        add_period(seg->period_error());
        s.ecat_frame_errors += seg->frame_errors();
    }
    if (refresh) {
        cell.p50 = p50;
        cell.p99 = p99;
    }
    s.period_error_p50 = cell.p50;
    s.period_error_p99 = cell.p99;
    cell.snapshot.store(s);
}

ControllerStats Controller::stats() const {
    ControllerStats s = stats_cell_->snapshot.load();
    // The loop thread's own figures.
    for (const auto& b : buses_) {
        if (b->master) {
            for (auto* n : const_cast<master::Master&>(*b->master).nodes()) {
                s.sdo_completed += n->sdo().stats().completed;
                s.sdo_failed += n->sdo().stats().failed;
            }
        }
        s.bus_errors += b->bus_errors + (b->bus != nullptr ? b->bus->stats().error_frames : 0);
    }
    return s;
}

} // namespace codrive::controller
