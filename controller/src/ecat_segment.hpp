// SPDX-License-Identifier: Apache-2.0
// Runtime of one EtherCAT segment inside the Controller: bring-up to OP with the profiles' PDO
// layouts, CiA 402 axes over CoE, and the per-cycle LRW exchange.
#pragma once

#include "handoff_transport.hpp"
#include "spsc_ring.hpp"

#include <codrive/controller/controller.hpp>
#include <codrive/controller/ethercat_segment.hpp>

#include <codrive/drives/axis.hpp>
#include <codrive/ethercat/coe_transport.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/raw_socket_link.hpp>
#include <codrive/sync/period_stats.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace codrive::controller {

class EcatSegment final : public ITimed {
public:
    using Emit = std::function<void(const std::string&)>;
    using CycleHook = std::function<void(const CycleInfo&)>;

    EcatSegment(EcatSegmentConfig config, std::size_t bus_index, Emit emit);
    ~EcatSegment() override;
    EcatSegment(const EcatSegment&) = delete;
    EcatSegment& operator=(const EcatSegment&) = delete;

    /// Opens the interface (or uses `link` when given), scans, checks every configured slave's
    /// identity against its profile, writes the modes and the profiles' PDO layouts in PRE-OP,
    /// steps to OP and binds the axes. Error: one sentence naming the slave and the step.
    /// `dedicated`: cycles will run on the dedicated cyclic thread; object accesses from the
    /// loop thread (loop_transport()) are then handed to it.
    tl::expected<void, ControllerError> bring_up(ethercat::IEcatLink* link, bool dedicated = false);
    /// First cycle at `first`, then every cycle_us.
    void start_cycles(TimePoint first, CycleHook hook);

    /// The cyclic part: LRW (outputs of the last cycle out, inputs in), the hook, every axis's
    /// on_cycle(). No allocation, no locks, no logging I/O.
    void cycle(TimePoint now);
    /// The acyclic part: emergencies and error reports as events.
    void acyclic(TimePoint now);

    /// Dedicated-cyclic mode, cyclic thread: the cycle if it is due. The master belongs to
    /// this thread while cycles run: CoE transfers ride in the cyclic frame as state machines,
    /// so no acyclic work can hold the master or make a cycle wait.
    void cyclic_step(TimePoint now);
    /// Dedicated-cyclic mode, acyclic thread: turns what the cycle handed over (emergencies,
    /// working-counter diagnosis, lost-frame runs) into events. Never touches the link.
    void acyclic_step(TimePoint now);

    // ITimed: single-thread mode runs both parts from the controller's loop.
    [[nodiscard]] TimePoint next_deadline() const override { return next_; }
    void on_tick(TimePoint now) override;
    /// Time of the next cycle (dedicated-thread mode waits for it itself).
    [[nodiscard]] TimePoint next_cycle() const { return next_; }
    /// Stops cycling (next_deadline() = never) and steps the slaves down to PRE-OP.
    void stop();
    /// Shutdown, once no thread cycles the segment any more (the cyclic thread has been joined,
    /// or single-thread mode): every object access still queued or in flight ends now with a
    /// sentence naming the slave, the object and `why`, and its callback runs, so that no
    /// read_object()/write_object() callback waits for a frame that will never come.
    void abandon_object_accesses(std::string_view why);

    [[nodiscard]] drives::Axis* axis(unsigned position, unsigned number);
    /// The transport the loop thread uses for object accesses to the slave at `position`: its
    /// CoE transport when the loop runs the cycles, the hand-off to the cyclic thread in
    /// dedicated-cyclic mode (the slave's mailbox rides in the cyclic frame, which that thread
    /// owns). nullptr when the bus file has no slave there or the segment is not up.
    [[nodiscard]] drives::DriveTransport* loop_transport(unsigned position);
    void collect_axes(std::vector<AxisRef>& out) const;
    void for_each_axis(const std::function<void(drives::Axis&)>& fn);
    [[nodiscard]] const EcatSegmentConfig& config() const { return config_; }
    [[nodiscard]] const sync::PeriodStats& period_error() const { return period_error_; }
    [[nodiscard]] std::uint64_t cycles() const { return cycles_; }
    [[nodiscard]] std::uint64_t overruns() const { return overruns_; }
    [[nodiscard]] std::uint64_t frame_errors() const { return frame_errors_; }
    /// Lost frames that came back after their cycle (read and dropped by a later cycle).
    [[nodiscard]] std::uint64_t late_frames() const {
        return late_frames_.load(std::memory_order_relaxed);
    }
    [[nodiscard]] ethercat::Master* master() { return master_.get(); }

private:
    struct Slave {
        EcatSlaveEntry entry;
        std::size_t index = 0; ///< position on the segment
        const drives::Profile* profile = nullptr;
        /// The device of the slave's ESI file its SII identity matched (in entry.esi); nullptr
        /// without `esi:`.
        const ethercat::EsiDevice* esi_device = nullptr;
        std::shared_ptr<const emcy::IEmcyTextProvider> emcy_text; ///< the profile's EMCY texts
        std::unique_ptr<ethercat::CoeTransport> transport;
        /// Dedicated-cyclic mode: the loop thread's object accesses, carried out by the cycle
        /// (pump_requests() before the frame goes out), delivered by acyclic().
        std::unique_ptr<HandoffTransport> loop_access;
        std::vector<std::unique_ptr<drives::Axis>> axes;
        std::atomic<std::uint16_t> emcy_code{0}; ///< written by the acyclic side
        /// AL control value the acyclic side asks the cycle to send (0 = none).
        std::atomic<std::uint16_t> al_request{0};
        // Recovery of a slave that left OP (acyclic side only).
        bool left_op = false;
        bool stuck_reported = false;
        unsigned op_requests = 0;
        TimePoint left_at{};
        TimePoint next_request{};
        Duration backoff{};
    };
    /// Acyclic side: a slave the probes show outside OP is reported once and asked back to OP
    /// (error acknowledged first) with back-off; its return is reported.
    void recover_slaves(TimePoint now);
    /// "slave 0 (FIO): back in OP after N OP request(s), T ms ..." once, if it had left.
    void report_back_in_op(Slave& s, TimePoint now);
    tl::expected<void, ControllerError> configure_slave(Slave& s);
    /// 1C32h/1C33h and, with `dc`, SYNC0 (ethercat::configure_sync), in PRE-OP.
    tl::expected<void, ControllerError> synchronise_slave(Slave& s);

    EcatSegmentConfig config_;
    std::size_t bus_index_;
    Emit emit_;
    std::unique_ptr<ethercat::RawSocketLink> own_link_;
    std::unique_ptr<ethercat::Master> master_;
    std::vector<std::unique_ptr<Slave>> slaves_;
    CycleHook hook_;
    Duration period_{0};
    TimePoint next_ = kNever;
    std::atomic<std::int64_t> next_ns_{0}; ///< next_ for the acyclic thread
    std::uint64_t cycles_ = 0;
    std::uint64_t overruns_ = 0;
    std::atomic<std::uint64_t> frame_errors_{0};
    std::atomic<std::uint64_t> late_frames_{0};
    bool frame_error_reported_ = false;
    std::atomic<bool> last_cycle_ok_{true};
    std::uint64_t failed_at_report_ = 0; ///< frame_errors_ when the failure was reported
    // Handed from the cycle to acyclic(): emergencies, AL status probes, lost-frame runs.
    struct EmcyEvent {
        std::size_t slave = 0;
        emcy::EmcyMessage message;
    };
    SpscRing<EmcyEvent, 32> emcy_;
    std::vector<ethercat::Master::AlProbe> probes_; ///< written by the cycle while !probes_ready_
    std::uint16_t probes_wkc_ = 0;
    std::atomic<bool> probes_ready_{false};
    /// A cycle that failed in the link or the master rather than on the wire (the interface
    /// went down: ENETDOWN from send or receive); written by the cycle while
    /// !link_failure_ready_, put into words by acyclic() once per run of failed cycles.
    struct LinkFailure {
        bool sending = false;
        std::error_code error;
    };
    LinkFailure link_failure_;
    std::atomic<bool> link_failure_ready_{false};
    std::atomic<std::uint64_t> lost_run_{0};
    std::atomic<std::uint64_t> lost_frames_{0};
    sync::PeriodStats period_error_;
};

} // namespace codrive::controller
