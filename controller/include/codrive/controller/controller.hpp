// SPDX-License-Identifier: Apache-2.0
// codrive::controller::Controller — a bus file (or BusConfig) in; booted, PDO-configured nodes,
// CiA 402 axes and an application callback on every SYNC out; safe shutdown on the way out.
#pragma once

#include <codrive/controller/error.hpp>
#include <codrive/controller/ethercat_segment.hpp>
#include <codrive/controller/realtime.hpp>

#include <codrive/core/can_bus.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/event_rate_limiter.hpp>
#include <codrive/drives/axis.hpp>
#include <codrive/master/boot_report.hpp>
#include <codrive/master/bus_config.hpp>
#include <codrive/master/events.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace codrive::master {
class Master;
}

namespace codrive::controller {

class EcatSegment;

/// Where the per-cycle work runs.
enum class Threading : std::uint8_t {
    /// Everything on the thread that calls run(): SYNC, PDOs, SDO, supervision, callbacks.
    Single,
    /// SYNC, PDO exchange, axis updates and the cycle callback on a dedicated cyclic thread
    /// (with `realtime` applied to it); SDO, NMT, heartbeat, EMCY, logging on the thread that
    /// calls run(). Hand-off between them is lock-free (see docs/controller.md).
    DedicatedCyclic,
};

struct ControllerOptions {
    /// Single: applied to the thread that calls start(); DedicatedCyclic: to the cyclic thread.
    RealtimeOptions realtime;
    Threading threading = Threading::Single;
    Duration boot_timeout = seconds(15);
    Duration shutdown_timeout = seconds(1);
    /// Receive buffer of every CAN socket the controller opens (SO_RCVBUFFORCE when privileged,
    /// else SO_RCVBUF, which the kernel caps at net.core.rmem_max). A thread delayed for a while
    /// must not lose TPDOs or heartbeats to a full socket; 0 keeps the kernel's default.
    int rcvbuf_bytes = 1 << 20;
    /// Repeated events of one kind from one source (a TPDO missing after every SYNC) are passed
    /// to the event callback as the first sentence and then one summary per interval:
    /// "node 3: TPDO1 (0x183) missing after SYNC ×412 in the last 1 s" (EventRateLimiter).
    /// Zero passes every event on. `codrive run` uses 1 s.
    Duration event_summary_interval = Duration::zero();
    /// Buses to use instead of opening the bus files' interfaces (tests: VirtualBus), by bus
    /// index. The controller does not own them.
    std::vector<ICanBus*> buses;
};

/// Passed to the cyclic callback on every SYNC.
struct CycleInfo {
    std::uint64_t cycle = 0;
    TimePoint ideal{};   ///< when this SYNC was due
    TimePoint actual{};  ///< when it went out
    std::size_t bus = 0; ///< which bus or EtherCAT segment (segments follow the CAN buses)
};

/// Where an axis lives.
struct AxisRef {
    std::size_t bus = 0;
    NodeId node = 0; ///< CAN node id, or EtherCAT slave position
    unsigned number = 1;
    drives::Axis* axis = nullptr;
    std::string name; ///< "node 1 axis 2 (gantry)"
    /// The operation mode the bus file gives the axis (6060h value: 8 = CSP, 9 = CSV), if any.
    std::optional<std::int8_t> mode;
};

struct ControllerStats {
    std::uint64_t cycles = 0;
    std::uint64_t overruns = 0; ///< SYNC slots skipped because a cycle ran late
    Duration period_error_p50{0};
    Duration period_error_p99{0};
    Duration period_error_max{0};
    std::uint64_t tpdos_received = 0;
    std::uint64_t tpdos_missing = 0;
    std::uint64_t rpdos_sent = 0;
    std::uint64_t sdo_completed = 0;
    std::uint64_t sdo_failed = 0;
    std::uint64_t bus_errors = 0;        ///< error frames and bus events
    std::uint64_t ecat_frame_errors = 0; ///< EtherCAT cycles with a lost frame or a WKC error
    /// Of the lost frames, those that came back after their cycle (read and dropped by a later
    /// one): the host was late, not the wire. ecat_frame_errors minus this is what never came
    /// back or came back with a short working counter (the frames lost since the last one read
    /// may still be on their way). The master's ProcessDataStats::late_frames is the source: a
    /// frame that came back in time but garbled is not counted here, it stays a wire error.
    std::uint64_t ecat_late_frames = 0;
    /// The frame errors that are not late returns: frames the segment never sent back and short
    /// working counters. On a sound segment in OP this stays near 0 however busy the host is.
    [[nodiscard]] std::uint64_t ecat_wire_errors() const {
        return ecat_frame_errors > ecat_late_frames ? ecat_frame_errors - ecat_late_frames : 0;
    }
    [[nodiscard]] std::string to_string() const;
};

/// Validates a bus file (CAN part and `ethercat:` section) without opening any bus: every
/// finding as "bus.yml:14: sentence", in file order per part; empty when the file is usable.
/// `codrive run --check` prints these.
[[nodiscard]] std::vector<std::string> check_bus_file(const std::string& path);

/// The controller. Single-threaded: everything (SYNC, PDOs, SDO, supervision, the cyclic
/// callback and axis operations) runs on the thread that calls run()/run_for(); services are
/// sans-I/O and non-blocking, so acyclic work never blocks a cycle. Axis operations must be
/// started from that thread (in a callback, or via post()).
class Controller {
public:
    using CycleCallback = std::function<void(const CycleInfo&)>;
    using EventCallback = std::function<void(const std::string& text)>;

    /// Loads a bus file. Error: ControllerErrc::BusFileInvalid, its detail lists every finding
    /// ("bus.yml:14: ..."), one a line; or an error of create().
    static tl::expected<std::unique_ptr<Controller>, ControllerError>
    from_file(const std::string& path, ControllerOptions options = {});
    /// From parsed bus configurations (one per bus). Errors: InvalidConfiguration (no bus),
    /// EventLoopFailed.
    static tl::expected<std::unique_ptr<Controller>, ControllerError>
    create(std::vector<master::BusConfig> buses, ControllerOptions options = {});
    /// CAN buses and EtherCAT segments. Bus indexes: CAN buses first, then the segments.
    static tl::expected<std::unique_ptr<Controller>, ControllerError>
    create(std::vector<master::BusConfig> buses, std::vector<EcatSegmentConfig> segments,
           ControllerOptions options = {});
    ~Controller();
    Controller(const Controller&) = delete;
    Controller& operator=(const Controller&) = delete;

    /// Opens the buses, boots and configures every node (boot reports available after), maps
    /// PDOs, binds the axes and starts SYNC. Error: its code tells the stage (AlreadyStarted,
    /// InvalidConfiguration, BusOpenFailed, SegmentFailed, StopRequested, BootTimeout,
    /// NodeBootFailed, SyncFailed), its detail is a sentence naming the interface, slave or the
    /// nodes that failed with their boot report lines. Warnings (real-time settings) go to the
    /// event callback. A controller starts once: a second call fails with AlreadyStarted.
    tl::expected<void, ControllerError> start();
    /// Safe shutdown: every enabled axis gets quick stop then disable, every node NMT
    /// pre-operational, SYNC stops, EtherCAT segments back to PRE-OP. Returns within
    /// shutdown_timeout + about 120 ms even when drives never answer (their axes are then named
    /// in an event); a stop request or signal arriving meanwhile does not cut it short.
    /// Idempotent. See docs/controller.md "Safe shutdown".
    void shutdown();

    /// Runs the loop until request_stop() (signal-safe) or shutdown; then shuts down safely.
    void run();
    /// Runs the loop for a while / until pred is true. Both return at once when a stop was
    /// requested (check running() or stop_requested() after them), so a program's own loop
    /// ends on a signal instead of spinning.
    void run_for(Duration d);
    bool run_until(const std::function<bool()>& pred, Duration timeout);
    /// Async-signal-safe: makes run(), run_for(), run_until() and a start() still booting return;
    /// run() then shuts down safely (other callers call shutdown() or destroy the controller).
    void request_stop();
    /// Installs SIGINT/SIGTERM handlers that call request_stop() on this controller (and
    /// remember the signal: stop_signal()).
    void stop_on_signals();
    /// True once request_stop() was called or a signal arrived (after stop_on_signals()).
    [[nodiscard]] bool stop_requested() const { return stop_requested_.load(); }
    /// The signal that requested the stop (SIGINT, SIGTERM); 0 if none did.
    [[nodiscard]] int stop_signal() const { return stop_signal_.load(); }
    /// Runs fn on the loop thread (thread-safe).
    void post(std::function<void()> fn);

    /// Sets (or, with nullptr, clears) the callback run on every cycle. In
    /// Threading::DedicatedCyclic, while the cyclic thread runs, the new callback is handed to
    /// that thread at its next wake-up and this call waits for it (at most about 20 ms): once it
    /// returns, the previous callback is no longer called and has been destroyed on this thread.
    void set_cycle_callback(CycleCallback cb);
    /// Master events, PDO events, boot reports and warnings, each a sentence.
    void set_event_callback(EventCallback cb) { event_cb_ = std::move(cb); }

    [[nodiscard]] const std::vector<master::BootReport>& boot_reports() const { return reports_; }
    /// An axis by CAN node id (or EtherCAT slave position), axis number and bus index; nullptr
    /// if there is none.
    [[nodiscard]] drives::Axis* axis(NodeId node, unsigned number = 1, std::size_t bus = 0);
    [[nodiscard]] std::vector<AxisRef> axes() const;
    [[nodiscard]] master::Master& master(std::size_t bus = 0);

    /// Result of read_object(): the object's bytes (little-endian, as on the wire), or a
    /// drives::DriveError: `code` to branch on (the transfer's own: an SDO abort code, a
    /// timeout; or ControllerErrc::NotStarted, NoSuchDevice) and `message`, a
    /// sentence naming the node or slave, the object and the cause.
    using ObjectRead = std::function<void(drives::DriveResult<drives::Bytes>)>;
    /// Result of write_object(): nothing, or a drives::DriveError as for ObjectRead.
    using ObjectWritten = std::function<void(drives::DriveVoid)>;
    /// Reads one object of a device, whatever its transport: an SDO upload from CAN node `node`
    /// on CAN bus `bus`, or a CoE SDO upload from the slave at position `node` of an EtherCAT
    /// segment (bus indexes: CAN buses first, then the segments). Asynchronous: `done` runs
    /// later on the loop thread (never inside this call), from run()/run_for()/run_until(). Call
    /// it on the loop thread after start(), in either threading mode (in
    /// Threading::DedicatedCyclic an EtherCAT slave's access is handed to the cyclic thread,
    /// which owns its mailbox, and its completion handed back). Errors (as sentences): unknown
    /// bus, node or slave; not started; the transfer's own failure (abort code, timeout).
    void read_object(std::size_t bus, NodeId node, std::uint16_t index, std::uint8_t subindex,
                     ObjectRead done);
    /// Writes one object (expedited, segmented or CoE as the size needs); as read_object().
    void write_object(std::size_t bus, NodeId node, std::uint16_t index, std::uint8_t subindex,
                      drives::Bytes data, ObjectWritten done);
    /// The cycle period of a bus (its SYNC period; 0 without SYNC) or EtherCAT segment.
    [[nodiscard]] Duration cycle_period(std::size_t bus = 0) const;
    /// Statistics. The cyclic figures (cycles, overruns, SYNC period error, PDO counts,
    /// EtherCAT frame errors) come from a snapshot the cycle publishes lock-free after every
    /// cycle, so any thread may read them while the cyclic thread runs (percentiles are
    /// refreshed every 256 cycles, exactly at shutdown). The SDO and bus-error figures belong
    /// to the thread that runs the loop: call stats() there (a callback, post()) or after
    /// run() returned.
    [[nodiscard]] ControllerStats stats() const;
    [[nodiscard]] EventLoop& loop() { return *loop_; }
    /// True after a successful start() until a stop is requested or shutdown() runs:
    /// `while (c.running()) c.run_for(...)` ends on Ctrl-C.
    [[nodiscard]] bool running() const { return started_ && !stopped_ && !stop_requested_.load(); }
    [[nodiscard]] const master::BusConfig& config(std::size_t bus = 0) const;
    /// Number of CAN buses and of EtherCAT segments.
    [[nodiscard]] std::size_t can_bus_count() const { return buses_.size(); }
    [[nodiscard]] std::size_t ethercat_segment_count() const { return segments_.size(); }

private:
    struct Bus;
    struct Node;
    struct StatsCell;
    Controller(std::vector<master::BusConfig> buses, std::vector<EcatSegmentConfig> segments,
               ControllerOptions options);
    void emit(const std::string& text);
    /// `key`: kind and source of the event, for the rate limiter.
    void emit(const std::string& text, const std::string& key);
    /// One CAN cycle: callback, axes, then `sync` and the RPDOs in one batch. True if the bus
    /// took the SYNC.
    bool on_sync(Bus& bus, const CycleInfo& info, const Frame& sync);
    tl::expected<void, ControllerError> open_bus(Bus& b, std::size_t index);
    void setup_node(Bus& b, const master::NodeEntry& entry);
    void after_boot(Bus& b, Node& n);
    class Pump;
    [[nodiscard]] bool dedicated() const {
        return options_.threading == Threading::DedicatedCyclic;
    }
    tl::expected<void, ControllerError> start_cyclic_thread();
    void cyclic_main();
    /// The safe stop of every axis (on the thread that owns the axes: the loop thread, or the
    /// cyclic thread in dedicated mode). Its state is a member, not a local, because the axes'
    /// callbacks outlive a safe stop that ran out of time until end_safe_stop() cancels them.
    void begin_safe_stop(TimePoint now);
    [[nodiscard]] bool safe_stop_over(TimePoint now) const;
    void end_safe_stop();
    /// NMT pre-operational to every node, SYNC off, segments to PRE-OP, frames flushed.
    void stop_buses();
    /// start() was interrupted or failed after the buses opened: freeze the boot-up and leave
    /// every node pre-operational and every segment in PRE-OP.
    tl::expected<void, ControllerError> abandon_start(std::string why);
    /// Runs the loop until pred or deadline; unlike EventLoop::run_until a stop() (a second
    /// signal) does not end it early.
    void run_loop_until(const std::function<bool()>& pred, TimePoint deadline);
    static void on_signal(int sig);
    void pump_acyclic();
    void for_each_axis(const std::function<void(drives::Axis&)>& fn);
    /// The transport object accesses of read_object()/write_object() go through, or the error
    /// saying why there is none.
    drives::DriveResult<drives::DriveTransport*> object_transport(std::size_t bus, NodeId node);
    /// Cycle owner: aggregates the cyclic counters into the snapshot stats() reads.
    void publish_cyclic_stats(bool exact_percentiles);

    ControllerOptions options_;
    std::unique_ptr<EventLoop> loop_;
    std::unique_ptr<EventRateLimiter> limiter_; ///< when event_summary_interval > 0
    std::vector<std::unique_ptr<Bus>> buses_;
    std::vector<std::unique_ptr<EcatSegment>> segments_;
    std::vector<master::BootReport> reports_;
    CycleCallback cycle_cb_;
    EventCallback event_cb_;
    std::atomic<bool> stop_requested_{false};
    std::atomic<int> stop_signal_{0};
    struct SafeStop {
        bool active = false;
        std::size_t pending = 0; ///< axes whose stop has not ended
        TimePoint deadline = kNever;
    };
    SafeStop safe_stop_;
    std::size_t boot_pending_ = 0; ///< buses still booting (start())
    bool boot_ok_ = true;
    // Dedicated-cyclic mode.
    std::unique_ptr<Pump> pump_;
    std::thread cyclic_thread_;
    std::atomic<bool> cyclic_ready_{false};
    std::atomic<bool> safe_stop_requested_{false}; ///< acyclic → cyclic: stop the axes
    std::atomic<bool> axes_safe_{false};           ///< cyclic → acyclic: axes stopped, SYNC off
    std::atomic<bool> cyclic_exit_{false};
    std::vector<std::string> cyclic_warnings_; ///< written before cyclic_ready_
    CycleCallback pending_cb_; ///< set_cycle_callback() → cyclic thread (swapped there)
    std::atomic<bool> cb_handoff_{false};   ///< pending_cb_ is ready to be swapped in
    std::unique_ptr<StatsCell> stats_cell_; ///< the published cyclic statistics
    /// Threading::Single: the caller's thread settings before apply_realtime(), restored at
    /// shutdown.
    std::optional<SavedThreadSchedule> caller_schedule_;

    bool start_called_ = false; ///< start() ran once (successfully or not)
    bool started_ = false;
    bool stopped_ = false;
};

} // namespace codrive::controller
