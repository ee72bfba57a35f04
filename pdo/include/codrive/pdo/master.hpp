// SPDX-License-Identifier: Apache-2.0
// Master-side PDO engine: per-node process images, RPDOs on SYNC/change, TPDO decoding and
// monitoring (CiA 301 §7.2.2), with no allocation on the cyclic path.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/pdo/error.hpp>
#include <codrive/pdo/process_image.hpp>
#include <codrive/pdo/types.hpp>

#include <array>
#include <functional>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace codrive::pdo {

enum class PdoEventKind : std::uint8_t {
    TpdoMissing,    ///< a SYNC-driven TPDO did not arrive in its SYNC window
    TpdoSilent,     ///< an event-driven TPDO with an event timer went quiet
    TpdoRecovered,  ///< a missing/silent TPDO arrived again
    TpdoTooShort,   ///< a TPDO frame shorter than its mapping (not applied)
    RpdoSendFailed, ///< the bus refused an RPDO
};
[[nodiscard]] std::string_view to_string(PdoEventKind k);

/// A PDO event. Plain data (no allocation when raised); to_string() makes the sentence.
struct PdoEvent {
    PdoEventKind kind = PdoEventKind::TpdoMissing;
    NodeId node = 0;
    PdoDir dir = PdoDir::Tpdo;
    std::uint8_t number = 0;
    std::uint32_t can_id = 0;
    std::uint8_t transmission_type = 0;
    std::uint64_t sync = 0; ///< the SYNC after which the TPDO was expected
    std::uint8_t got_len = 0;
    std::uint8_t want_len = 0;
    Duration silent_for{0};
    Duration event_timer{0};
    TimePoint time{};
    std::error_code error; ///< RpdoSendFailed
};
/// "node 2: TPDO1 (0x182) missing after SYNC 1234 (expected every SYNC)",
/// "node 2: TPDO2 (0x282) silent for 25 ms (event timer 10 ms)",
/// "node 2: TPDO1 (0x182) has 4 bytes but its mapping needs 6 (frame ignored)",
/// "node 2: RPDO1 (0x202) not sent: <bus error>".
[[nodiscard]] std::string to_string(const PdoEvent& e);
/// The kind and source of an event without its per-occurrence details, for rate limiting
/// (EventRateLimiter): "node 2: TPDO1 (0x182) missing after SYNC".
[[nodiscard]] std::string event_key(const PdoEvent& e);

struct PdoMasterOptions {
    /// An event-driven TPDO with event timer T is reported silent after T × this factor.
    double event_timeout_factor = 2.0;
    /// A SYNC-driven TPDO may arrive this many windows late before it counts as missing: with
    /// 1, the answer to SYNC k may still come after SYNC k+1 (a loaded host, or a master whose
    /// timer runs before it reads the socket); it is reported at SYNC k+2 if it never comes.
    unsigned missing_tolerance = 1;
};

struct PdoMasterStats {
    std::uint64_t rpdos_sent = 0;
    std::uint64_t tpdos_received = 0;
    std::uint64_t tpdos_missing = 0;
    std::uint64_t tpdos_late = 0; ///< arrived after the window they answer had closed
    std::uint64_t tpdos_too_short = 0;
    std::uint64_t send_errors = 0;
    std::uint64_t syncs = 0;
};

/// The master's PDO engine for many nodes.
///
/// Setup (allocates): add_node() with the node's PDO configurations (as written with
/// PdoConfigurator), then ProcessImage::slot() for every object the application uses.
/// Cyclic path (no allocation, no lookup by name, only bus sends): on_sync() from the SYNC
/// producer's hook, on_frame() for received frames, ProcessImage::set/get, flush()/on_tick().
///
/// RPDOs (the master produces them): type 1..240 sent on every n-th SYNC; type 0 sent on the
/// SYNC after a change; 254/255 sent on change by flush()/on_tick() (respecting the configured
/// inhibit time) and repeated every event timer period if set. TPDOs (the master consumes
/// them): received data lands in the image with its timestamp; a SYNC-driven TPDO that did not
/// arrive for its window of n SYNCs (allowing options.missing_tolerance windows of lateness) is
/// reported (TpdoMissing), an event-driven one with an
/// event timer that stays quiet for event_timeout_factor × timer is reported (TpdoSilent).
class PdoMaster final : public ITimed {
public:
    using EventHandler = std::function<void(const PdoEvent&)>;

    explicit PdoMaster(ICanBus& bus, PdoMasterOptions options = {});
    ~PdoMaster() override;
    PdoMaster(const PdoMaster&) = delete;
    PdoMaster& operator=(const PdoMaster&) = delete;

    /// Adds a node with its enabled PDOs (disabled ones are ignored). Errors: AlreadyConfigured,
    /// InvalidMapping/LengthExceeded (more than 64 bits), InvalidCommunication (no COB-ID, or
    /// a TPDO COB-ID another node already uses).
    PdoResult<ProcessImage*> add_node(NodeId node, std::span<const PdoConfig> pdos);
    PdoResult<ProcessImage*> add_node(NodeId node, std::initializer_list<PdoConfig> pdos) {
        return add_node(node, std::span<const PdoConfig>(pdos.begin(), pdos.size()));
    }
    /// Removes a node (setup time). False if unknown.
    bool remove_node(NodeId node);
    [[nodiscard]] ProcessImage* image(NodeId node);
    [[nodiscard]] const ProcessImage* image(NodeId node) const;

    void set_event_handler(EventHandler handler) { handler_ = std::move(handler); }

    /// A SYNC went out (call from SyncProducer's hook with SyncInfo::cycle). Checks the TPDO
    /// windows that ended, then sends the RPDOs due at this SYNC.
    void on_sync(std::uint64_t cycle, TimePoint now);
    /// The same, for a SYNC not sent yet: `sync` goes to the bus first and the RPDOs due at it
    /// right behind, in the same ICanBus::send_many() call (one sendmmsg() per cycle on
    /// SocketCAN). CiA 301 §7.2.2.2 / §7.2.5: synchronous RPDOs are received inside the
    /// synchronous window that opens with a SYNC (1007h) and actuated at the next SYNC, so they
    /// follow the SYNC, never precede it. True if the bus took the SYNC (a refused SYNC is not
    /// retried: the producer counts it as a send error and the next one is due a period later).
    bool on_sync(std::uint64_t cycle, TimePoint now, const Frame& sync);
    /// A received frame. True if it was a TPDO of a configured node.
    bool on_frame(const Frame& frame, TimePoint now);
    /// Sends event-driven RPDOs that changed (inhibit time permitting).
    void flush(TimePoint now);
    /// Sends an RTR for a TPDO (types 252/253, or any TPDO whose COB-ID allows RTR).
    /// Errors: UnknownNode, UnknownObject (no such TPDO), or the bus error.
    VoidResult request(NodeId node, unsigned tpdo_number);

    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    [[nodiscard]] const PdoMasterStats& stats() const { return stats_; }

private:
    void send(detail::PdoChannel& p, TimePoint now);
    /// The SYNC cycle's RPDOs go to the bus together (ICanBus::send_many: one sendmmsg() on
    /// SocketCAN), in the order they were due; queue_send() collects, flush_sends() sends.
    void queue_send(detail::PdoChannel& p, TimePoint now);
    void flush_sends(TimePoint now);
    static Frame frame_of(const detail::PdoChannel& p);
    /// A PDO handed to the bus at `now` (whether or not the bus takes it).
    static void leaving(detail::PdoChannel& p, TimePoint now);
    /// A PDO the bus took: counted.
    void sent(detail::PdoChannel& p);
    void emit(const PdoEvent& e);
    void check_window(detail::PdoChannel& p, std::uint64_t cycle, TimePoint now);
    void rebuild_lists();

    ICanBus& bus_;
    PdoMasterOptions options_;
    std::array<std::unique_ptr<ProcessImage>, kMaxNodeId + 1> images_{};
    /// Flat lists over all nodes, rebuilt at setup, walked on the cyclic path.
    std::vector<detail::PdoChannel*> rpdos_;
    std::vector<detail::PdoChannel*> tpdos_;
    std::vector<detail::PdoChannel*> event_rpdos_;
    std::vector<detail::PdoChannel*> timed_tpdos_;
    std::array<detail::PdoChannel*, 0x800> by_id_{};  ///< 11-bit TPDO COB-ID → channel
    std::vector<detail::PdoChannel*> extended_tpdos_; ///< 29-bit TPDOs (linear search)
    static constexpr std::size_t kSendBatch = 32;
    std::array<Frame, kSendBatch> batch_{};
    /// nullptr: the SYNC leading the batch (on_sync() with a frame).
    std::array<detail::PdoChannel*, kSendBatch> batch_channels_{};
    std::size_t batch_size_ = 0;
    bool lead_refused_ = false; ///< the last batch's leading SYNC was not taken
    bool changed_ = false;      ///< some image was written since the last flush
    TimePoint next_timer_ = kNever;
    EventHandler handler_;
    PdoMasterStats stats_;
};

} // namespace codrive::pdo
