// SPDX-License-Identifier: Apache-2.0
// The vcan soak: a Controller drives simulated CiA 402 drives in CSP for N SYNC cycles while a
// second socket counts every SYNC and PDO on the wire; heap, fds and threads are sampled.
//
// Shared by bench/soak.cpp (long runs) and tests/vcan/soak_test.cpp (the short CI run). Header
// only: the support library links codrive::core alone, the soak needs the controller.
#pragma once

#include <codrive/controller/controller.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/master/master.hpp>

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <dirent.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <malloc.h>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace codrive::testing {

/// One simulated node as codrive-sim hosts it (`--node ID:PROFILE:1`).
struct SoakNode {
    NodeId id = 1;
    std::string profile = "akd2g";
    /// csp: a position triangle; csv: velocity 0; off: in CSV, booted but never enabled.
    std::string mode = "csp";
};

/// An SDO write the soak makes to every node of a profile (all if empty) after boot-up.
struct SoakWrite {
    std::string profile;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::vector<std::uint8_t> data; ///< little-endian value
};

struct SoakOptions {
    std::string iface = "vcan0";
    std::uint64_t cycles = 20'000;
    std::uint64_t sample_at = 10'000; ///< first resource sample (the second is at the end)
    std::uint32_t sync_period_us = 2000;
    std::vector<SoakNode> nodes = {{1, "akd2g"}, {2, "akd2g"}, {3, "akd2g"}, {4, "akd2g"}};
    /// Master heartbeat (1017h of the master) in ms.
    std::uint16_t master_heartbeat_ms = 100;
    /// Boot-up SDO timeout of every node in ms (bus.sdo_timeout_ms); 0: the master's default.
    /// Longer under valgrind, where the simulator answers 20-50 times slower.
    std::uint32_t sdo_timeout_ms = 0;
    /// Time limit of each axis's enable (the drive model's default is 2 s). Longer under
    /// valgrind, where a drive can take seconds to follow a controlword.
    Duration enable_timeout = seconds(2);
    /// Bus-file `writes:` of the nodes with a matching profile (all if empty), written during
    /// boot-up (e.g. 1016h:01 so the nodes supervise the master's heartbeat).
    std::vector<SoakWrite> writes;
    /// Called with every controller event (master, PDO, boot), outside the cyclic path.
    std::function<void(const std::string&)> on_event;
    /// Called once the axes are enabled and the counting window is open.
    std::function<void()> on_running;
    /// Every `progress_every` cycles (0: never), outside the cyclic path: a line with the
    /// cycle, heap, fds and the PDO frames counted so far, so a run cut short still has figures.
    std::uint64_t progress_every = 0;
    std::function<void(const std::string&)> on_progress;
    /// Stop early when this returns true (checked between cycles' run slices).
    std::function<bool()> stop;
};

/// Process resources at one moment.
struct ResourceSample {
    std::uint64_t cycle = 0;
    std::size_t heap_in_use = 0; ///< mallinfo2().uordblks: bytes handed out by malloc
    std::size_t heap_mapped = 0; ///< mallinfo2().hblkhd: bytes in mmap'ed blocks
    int fds = 0;                 ///< entries of /proc/self/fd
    int threads = 0;             ///< entries of /proc/self/task
};

struct SoakPdo {
    std::uint32_t cob_id = 0;
    bool tpdo = false; ///< sent by the node (TPDO), else by the master (RPDO)
    std::uint64_t frames = 0;
    std::uint64_t lost = 0;        ///< smallest deficit SYNCs − frames, if positive
    std::uint64_t extra = 0;       ///< frames beyond the SYNCs, if any
    std::uint64_t late_cycles = 0; ///< SYNC intervals in which this PDO did not appear
    std::uint64_t in_flight = 0;   ///< answers to the last SYNCs not yet seen at the end
};

struct SoakReport {
    std::string error;       ///< empty when the run completed (figures below are valid)
    std::uint64_t syncs = 0; ///< SYNCs counted on the wire in the window
    std::vector<SoakPdo> pdos;
    std::uint64_t lost = 0; ///< sum of SoakPdo::lost
    std::uint64_t monitor_rx_dropped = 0;
    /// Frames the kernel dropped from its per-CPU input backlog during the run (the "dropped"
    /// column of /proc/net/softnet_stat, net.core.netdev_max_backlog): vcan delivers every frame
    /// through it, and a drop there reaches no socket, so no SO_RXQ_OVFL counts it.
    std::uint64_t kernel_backlog_drops = 0;
    controller::ControllerStats stats;
    std::uint64_t master_rx_dropped = 0;
    std::uint64_t events = 0;
    std::vector<std::string> first_events;
    ResourceSample first;
    ResourceSample last;
    double wall_s = 0;
    double period_us = 0; ///< mean SYNC interval on the wire
    std::string bus_file;

    [[nodiscard]] std::string to_string() const;
    /// Empty when the soak passed: it ran, no PDO lost, heap within kHeapSlack bytes of the
    /// first sample, the same fds and threads; else one sentence per failed criterion.
    [[nodiscard]] std::string verdict() const;
    /// Heap growth tolerated between the samples: the controller keeps the first event
    /// sentences (a few hundred bytes each); anything per cycle would grow by megabytes.
    static constexpr long long kHeapSlack = 4096;
};

/// "1:akd2g,3:ds-bvs:csv" (ID:PROFILE[:MODE]) → nodes; false on a malformed item.
inline bool parse_soak_nodes(const std::string& text, std::vector<SoakNode>& out) {
    out.clear();
    for (std::string rest = text; !rest.empty();) {
        const auto comma = rest.find(',');
        const std::string item = rest.substr(0, comma);
        rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
        const auto colon = item.find(':');
        if (colon == std::string::npos || colon == 0) {
            return false;
        }
        const unsigned long id = std::strtoul(item.c_str(), nullptr, 10);
        if (id < 1 || id > 127) {
            return false;
        }
        std::string profile = item.substr(colon + 1);
        std::string mode = "csp";
        if (const auto second = profile.find(':'); second != std::string::npos) {
            mode = profile.substr(second + 1);
            profile.resize(second);
        }
        if (mode != "csp" && mode != "csv" && mode != "off") {
            return false;
        }
        out.push_back({static_cast<NodeId>(id), profile, mode});
    }
    return !out.empty();
}

/// Entries of a /proc directory other than "." and "..".
inline int count_dir_entries(const char* path) {
    int n = 0;
    if (DIR* d = ::opendir(path)) {
        while (const dirent* e = ::readdir(d)) {
            n += e->d_name[0] != '.' ? 1 : 0;
        }
        ::closedir(d);
    }
    return n;
}

/// Threads of this process (reads /proc/self/task). Call start_runtime_threads() before taking
/// a baseline, and threads_after_joins() after threads have been joined.
inline int count_threads() {
    return count_dir_entries("/proc/self/task");
}

/// The thread count once threads that were joined have left /proc/self/task. pthread_join()
/// returns when the kernel clears the thread's tid (in exit_mm), a moment before the task is
/// unhashed from the thread group, so a count taken at once can still include a joined thread.
/// Waits up to `limit` for the count to reach `expected`, and returns the count it saw last.
inline int threads_after_joins(int expected,
                               std::chrono::milliseconds limit = std::chrono::milliseconds(2000)) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    int n = count_threads();
    while (n != expected && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        n = count_threads();
    }
    return n;
}

/// ThreadSanitizer's runtime starts a background thread of its own at the process's first
/// pthread_create(): one throwaway thread, so that a thread count taken afterwards changes only
/// with the threads the code under test starts and ends, in any build and test order. Returns
/// once the throwaway thread has left /proc/self/task (see threads_after_joins()).
inline void start_runtime_threads() {
    pid_t tid = 0;
    std::thread([&tid] { tid = ::gettid(); }).join();
    const std::string task = fmt::format("/proc/self/task/{}", tid);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (::access(task.c_str(), F_OK) == 0 && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

/// Current process resources (reads /proc; not for the cyclic path).
inline ResourceSample sample_resources(std::uint64_t cycle) {
    ResourceSample s;
    s.cycle = cycle;
    const struct mallinfo2 mi = ::mallinfo2();
    s.heap_in_use = mi.uordblks + mi.hblkhd;
    s.heap_mapped = mi.hblkhd;
    s.fds = count_dir_entries("/proc/self/fd") - 1; // minus the one opendir() holds
    s.threads = count_threads();
    return s;
}

/// The bus file the soak runs: every node in CSP with the profile's default PDO mapping.
inline std::string soak_bus_yaml(const SoakOptions& o) {
    std::string y = fmt::format("# generated by codrive::testing soak\nbus:\n  interface: {}\n"
                                "  sync_period_us: {}\n  master: {{node_id: 127, heartbeat_ms: "
                                "{}}}\nnodes:\n",
                                o.iface, o.sync_period_us, o.master_heartbeat_ms);
    if (o.sdo_timeout_ms != 0) {
        y.insert(y.find("  master:"), fmt::format("  sdo_timeout_ms: {}\n", o.sdo_timeout_ms));
    }
    for (const auto& n : o.nodes) {
        y += fmt::format("  - id: {}\n    profile: {}\n    heartbeat_ms: 100\n"
                         "    axes:\n      - {{axis: 1, mode: {}}}\n",
                         n.id, n.profile, n.mode == "off" ? "csv" : n.mode);
        std::string writes;
        for (const auto& w : o.writes) {
            if (!w.profile.empty() && w.profile != n.profile) {
                continue;
            }
            std::uint64_t value = 0;
            for (std::size_t i = 0; i < w.data.size() && i < 8; ++i) {
                value |= static_cast<std::uint64_t>(w.data[i]) << (8 * i);
            }
            writes += fmt::format("      - {{object: \"0x{:04X}:{:02X}\", value: {}}}\n", w.index,
                                  w.subindex, value);
        }
        if (!writes.empty()) {
            y += "    writes:\n" + writes;
        }
    }
    return y;
}

namespace soak_detail {

/// Sum of the "dropped" column (second, hex) of /proc/net/softnet_stat over all CPUs.
inline std::uint64_t kernel_backlog_drops() {
    std::ifstream in("/proc/net/softnet_stat");
    std::uint64_t total = 0;
    std::string processed;
    std::string dropped;
    std::string rest;
    while (in >> processed >> dropped && std::getline(in, rest)) {
        total += std::strtoull(dropped.c_str(), nullptr, 16);
    }
    return total;
}

/// Counts SYNCs and PDO frames per COB-ID on a second socket. The frame handler only
/// increments fixed arrays (no allocation, so it cannot disturb the heap figures).
///
/// A TPDO answering SYNC k may arrive after SYNC k+1 (a starved drive is late, not lost), so
/// losses are judged by the deficit "SYNCs so far − frames so far", taken whenever a SYNC
/// arrives: every frame seen then answers an earlier SYNC, so the deficit is the frames lost plus
/// those still in flight. After the window's last SYNC the counter keeps watching for kGrace
/// more SYNC intervals and takes the smallest deficit seen: a stream that catches up once in
/// that time shows exactly its losses, even if it trailed by one or more at the window's end.
struct WireCounter {
    static constexpr std::size_t kIds = 0x800;
    static constexpr std::uint64_t kGrace = 50;
    std::array<std::uint64_t, kIds> total{};     ///< frames since the window opened
    std::array<std::uint64_t, kIds> in_window{}; ///< frames until the window closed
    std::array<std::uint64_t, kIds> in_cycle{};
    std::array<std::uint64_t, kIds> late{};
    /// Frames beyond one in the first interval: answers to the SYNC before the window.
    std::array<std::uint64_t, kIds> leading_extra{};
    std::array<std::int64_t, kIds> deficit_at_close{};
    std::array<std::int64_t, kIds> min_deficit{};
    std::uint64_t syncs = 0;     ///< SYNCs that opened a counted interval of the window
    std::uint64_t all_syncs = 0; ///< the same, plus those of the grace intervals
    std::uint64_t grace_seen = 0;
    bool open = false;
    bool closed = false; ///< the window is over (grace intervals may still run)
    bool done = false;   ///< the grace intervals are over too
    std::uint64_t limit = 0;
    TimePoint first_sync{};
    TimePoint last_sync{};

    static bool is_pdo(std::uint32_t id) { return id >= 0x180 && id < 0x580; }

    [[nodiscard]] std::int64_t deficit(std::uint32_t id) const {
        return static_cast<std::int64_t>(all_syncs) -
               static_cast<std::int64_t>(total[id] - leading_extra[id]);
    }

    void on_frame(const Frame& f, TimePoint t) {
        if (f.error() || f.extended() || done) {
            return;
        }
        const std::uint32_t id = f.id & 0x7FF;
        if (id != 0x080) {
            if (open && is_pdo(id)) {
                ++total[id];
                ++in_cycle[id];
            }
            return;
        }
        if (!open) {
            open = true;
            first_sync = t;
            last_sync = t;
            ++syncs;
            ++all_syncs;
            return;
        }
        // An interval ends.
        for (std::uint32_t i = 0x180; i < 0x580; ++i) {
            if (!closed) {
                if (syncs == 1 && in_cycle[i] > 1) {
                    leading_extra[i] = in_cycle[i] - 1;
                }
                if (total[i] != 0 && in_cycle[i] == 0) {
                    ++late[i]; // seen 0 times in this interval: late (or lost)
                }
            }
            in_cycle[i] = 0;
            if (syncs >= limit && total[i] != 0) {
                const std::int64_t d = deficit(i);
                if (!closed) {
                    deficit_at_close[i] = d;
                    min_deficit[i] = d;
                    in_window[i] = total[i];
                } else {
                    min_deficit[i] = std::min(min_deficit[i], d);
                }
            }
        }
        if (syncs >= limit) {
            if (!closed) {
                closed = true;
                last_sync = t;
            } else if (++grace_seen >= kGrace) {
                done = true;
            }
            ++all_syncs;
            return;
        }
        ++syncs;
        ++all_syncs;
        last_sync = t;
    }

    /// A run stopped before its window closed: judge the streams as they stand.
    void close_now() {
        if (closed) {
            return;
        }
        for (std::uint32_t i = 0x180; i < 0x580; ++i) {
            if (total[i] != 0) {
                deficit_at_close[i] = min_deficit[i] = deficit(i);
                in_window[i] = total[i];
            }
        }
        closed = true;
    }
};

} // namespace soak_detail

/// Runs the soak against nodes already simulated on o.iface (codrive-sim). Never throws; the
/// report's `error` says what went wrong before the figures could be taken.
inline SoakReport run_soak(const SoakOptions& o) {
    SoakReport rep;
    const auto wall_start = std::chrono::steady_clock::now();
    const std::uint64_t backlog_drops_before = soak_detail::kernel_backlog_drops();
    rep.bus_file = fmt::format("{}/codrive-soak-{}.yml",
                               std::filesystem::temp_directory_path().string(), ::getpid());
    {
        std::ofstream out(rep.bus_file);
        out << soak_bus_yaml(o);
    }
    controller::ControllerOptions copt;
    copt.boot_timeout = seconds(20);
    auto created = controller::Controller::from_file(rep.bus_file, copt);
    std::filesystem::remove(rep.bus_file);
    if (!created) {
        rep.error = "bus file: " + created.error().detail;
        return rep;
    }
    controller::Controller& c = **created;
    rep.first_events.reserve(16);
    c.set_event_callback([&](const std::string& text) {
        ++rep.events;
        if (rep.first_events.size() < 16) {
            rep.first_events.push_back(text);
        }
        if (o.on_event) {
            o.on_event(text);
        }
    });
    if (auto r = c.start(); !r) {
        rep.error = "start: " + r.error().detail;
        return rep;
    }
    // The axes to drive, with their node's mode ("off": booted, never enabled).
    struct Driven {
        drives::Axis* axis = nullptr;
        std::string mode;
        std::int32_t origin = 0;
    };
    std::vector<Driven> axes;
    for (const auto& ref : c.axes()) {
        for (const auto& n : o.nodes) {
            if (n.id == ref.node && n.mode != "off") {
                axes.push_back({ref.axis, n.mode, 0});
            }
        }
    }
    const auto all_have_status = [&] {
        for (const auto& d : axes) {
            if (!d.axis->has_statusword()) {
                return false;
            }
        }
        return true;
    };
    const Duration status_wait = std::max<Duration>(seconds(5), o.enable_timeout);
    if (!c.run_until(all_have_status, status_wait)) {
        rep.error = fmt::format("not every axis has a cyclic statusword {} s after boot-up",
                                std::chrono::duration_cast<seconds>(status_wait).count());
        return rep;
    }
    std::size_t enabled = 0;
    std::string enable_error;
    for (const auto& d : axes) {
        d.axis->enable(
            [&, a = d.axis](drives::DriveVoid r) {
                ++enabled;
                if (!r) {
                    enable_error += a->name() + ": " + r.error().message + "; ";
                }
            },
            o.enable_timeout);
    }
    c.run_until([&] { return enabled == axes.size(); }, o.enable_timeout + seconds(8));
    if (enabled != axes.size() || !enable_error.empty()) {
        rep.error = "enable failed: " + enable_error;
        return rep;
    }

    // CSP: every axis follows a triangle around where it stands, one set-point per SYNC
    // (about 10 increments per ms; CiA 402 CSP, the drive interpolates nothing itself).
    for (auto& d : axes) {
        d.origin = d.axis->position_actual().value_or(0);
    }
    std::uint64_t cycle = 0;
    c.set_cycle_callback([&](const controller::CycleInfo&) {
        ++cycle;
        const auto phase = static_cast<std::int64_t>(cycle % 20'000);
        const std::int64_t tri = phase < 10'000 ? phase : 20'000 - phase;
        const auto step = static_cast<std::int64_t>(o.sync_period_us) / 100;
        for (const auto& d : axes) {
            if (d.mode == "csv") {
                d.axis->set_target_velocity(0);
            } else {
                d.axis->set_target_position(static_cast<std::int32_t>(d.origin + tri * step));
            }
        }
    });

    SocketCanOptions monitor_options;
    monitor_options.rcvbuf_bytes = 4 << 20; // the counter must not be the one that drops
    auto monitor_bus = SocketCanBus::open(o.iface, monitor_options);
    if (!monitor_bus) {
        rep.error = "monitor socket: " + monitor_bus.error().message();
        return rep;
    }
    soak_detail::WireCounter wire;
    wire.limit = o.cycles;
    (*monitor_bus)->set_frame_handler([&wire](const Frame& f, TimePoint t) {
        wire.on_frame(f, t);
    });
    if (auto r = (*monitor_bus)->attach(c.loop()); !r) {
        rep.error = "monitor attach: " + r.error().message();
        return rep;
    }
    if (o.on_running) {
        o.on_running();
    }
    const auto stopped = [&] { return o.stop && o.stop(); };
    // Long runs in slices so a hung bus ends the run instead of blocking forever.
    const Duration slice = seconds(10);
    const auto run_to = [&](std::uint64_t n) {
        std::uint64_t before = wire.syncs;
        while (wire.syncs < n && !wire.closed && !stopped()) {
            c.run_until([&] { return wire.syncs >= n || wire.closed || stopped(); }, slice);
            if (wire.syncs == before) {
                return false; // no SYNC for 10 s
            }
            before = wire.syncs;
        }
        return true;
    };
    bool ok = run_to(std::min(o.sample_at, o.cycles));
    rep.first = sample_resources(wire.syncs);
    const auto progress = [&] {
        std::uint64_t min_frames = ~std::uint64_t{0};
        for (std::uint32_t id = 0x180; id < 0x580; ++id) {
            if (wire.total[id] != 0) {
                min_frames = std::min(min_frames, wire.total[id]);
            }
        }
        const ResourceSample r = sample_resources(wire.syncs);
        o.on_progress(fmt::format(
            "soak: progress: {} SYNCs, fewest frames of a PDO stream {}, "
            "heap {} B, fds {}, threads {}, {:.0f} s",
            wire.syncs, min_frames, r.heap_in_use, r.fds, r.threads,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count()));
    };
    if (o.progress_every != 0 && o.on_progress) {
        progress();
        for (std::uint64_t next = wire.syncs + o.progress_every;
             ok && next < o.cycles && !stopped(); next += o.progress_every) {
            ok = run_to(next);
            progress();
        }
    }
    ok = ok && run_to(o.cycles);
    if (ok && !stopped()) {
        c.run_until([&] { return wire.done; }, seconds(5));
    }
    rep.last = sample_resources(wire.syncs);
    rep.stats = c.stats();
    rep.master_rx_dropped = 0;
    (*monitor_bus)->detach();
    rep.monitor_rx_dropped = (*monitor_bus)->stats().rx_dropped;
    rep.kernel_backlog_drops = soak_detail::kernel_backlog_drops() - backlog_drops_before;
    c.shutdown();
    rep.syncs = wire.syncs;
    wire.close_now();
    for (std::uint32_t id = 0x180; id < 0x580; ++id) {
        if (wire.total[id] == 0) {
            continue;
        }
        SoakPdo p;
        p.cob_id = id;
        // Predefined connection set: TPDOn at 180h/280h/380h/480h + node, RPDOn 80h above.
        p.tpdo = ((id >> 7) & 1U) == 1U;
        p.frames = wire.in_window[id];
        const std::int64_t least = wire.min_deficit[id];
        p.lost = least > 0 ? static_cast<std::uint64_t>(least) : 0;
        p.extra = least < 0 ? static_cast<std::uint64_t>(-least) : 0;
        // Answers to the window's SYNCs that came after it closed.
        p.in_flight = static_cast<std::uint64_t>(std::max<std::int64_t>(
            0, wire.deficit_at_close[id] - std::max<std::int64_t>(least, 0)));
        p.late_cycles = wire.late[id];
        rep.lost += p.lost;
        rep.pdos.push_back(p);
    }
    if (rep.syncs > 1) {
        rep.period_us =
            std::chrono::duration<double, std::micro>(wire.last_sync - wire.first_sync).count() /
            static_cast<double>(rep.syncs);
    }
    rep.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (!ok) {
        rep.error = fmt::format("SYNC stopped on the wire after {} cycles", wire.syncs);
    } else if (rep.syncs < o.cycles && !stopped()) {
        rep.error = fmt::format("only {} of {} cycles ran", rep.syncs, o.cycles);
    }
    return rep;
}

inline std::string SoakReport::to_string() const {
    std::string s;
    if (!error.empty()) {
        s += "soak: ERROR: " + error + "\n";
    }
    s += fmt::format("soak: {} SYNC cycles, mean period {:.1f} us, wall {:.1f} s\n", syncs,
                     period_us, wall_s);
    std::uint64_t rx = 0;
    std::uint64_t tx = 0;
    for (const auto& p : pdos) {
        (p.tpdo ? rx : tx) += p.frames;
        s += fmt::format("soak:   {} 0x{:03X}: {} frames, lost {}, extra {}, late in {} cycles, "
                         "{} in flight at the end\n",
                         p.tpdo ? "TPDO" : "RPDO", p.cob_id, p.frames, p.lost, p.extra,
                         p.late_cycles, p.in_flight);
    }
    s += fmt::format("soak: PDOs on the wire: {} RPDO + {} TPDO frames in {} PDO streams; "
                     "lost (not injected) {}; monitor socket drops {}; kernel input backlog "
                     "drops {}\n",
                     tx, rx, pdos.size(), lost, monitor_rx_dropped, kernel_backlog_drops);
    s += fmt::format("soak: controller: {}\n", stats.to_string());
    const auto diff = [](std::size_t a, std::size_t b) {
        return static_cast<long long>(b) - static_cast<long long>(a);
    };
    s += fmt::format("soak: heap in use {} B at cycle {}, {} B at cycle {} ({:+d} B); "
                     "fds {} -> {}; threads {} -> {}\n",
                     first.heap_in_use, first.cycle, last.heap_in_use, last.cycle,
                     diff(first.heap_in_use, last.heap_in_use), first.fds, last.fds, first.threads,
                     last.threads);
    s += fmt::format("soak: {} controller events\n", events);
    for (const auto& e : first_events) {
        s += "soak:   event: " + e + "\n";
    }
    return s;
}

inline std::string SoakReport::verdict() const {
    std::string v = error.empty() ? "" : error + ". ";
    if (lost != 0) {
        v += fmt::format("{} PDO frames lost (no loss was injected)", lost);
        v += kernel_backlog_drops != 0
                 ? fmt::format("; the kernel dropped {} frames from its input backlog "
                               "(net.core.netdev_max_backlog) before any socket saw them. ",
                               kernel_backlog_drops)
                 : ". ";
    }
    if (monitor_rx_dropped != 0) {
        v += fmt::format("the monitor socket dropped {} frames, so the counts are incomplete. ",
                         monitor_rx_dropped);
    }
    const long long growth =
        static_cast<long long>(last.heap_in_use) - static_cast<long long>(first.heap_in_use);
    if (growth > kHeapSlack) {
        v += fmt::format("the heap grew by {} B between cycle {} and cycle {}. ", growth,
                         first.cycle, last.cycle);
    }
    if (last.fds != first.fds) {
        v += fmt::format("open file descriptors went from {} to {}. ", first.fds, last.fds);
    }
    if (last.threads != first.threads) {
        v += fmt::format("threads went from {} to {}. ", first.threads, last.threads);
    }
    return v;
}

} // namespace codrive::testing
