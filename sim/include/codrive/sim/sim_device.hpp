// SPDX-License-Identifier: Apache-2.0
// A simulated CANopen drive: object dictionary, SDO server, NMT slave, heartbeat, SYNC, EMCY,
// PDOs and one or two CiA 402 axes, on any ICanBus (SocketCAN or the virtual bus).
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/eds.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/nmt/state.hpp>
#include <codrive/sim/active_errors.hpp>
#include <codrive/sim/drive_core.hpp>
#include <codrive/sim/profile.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace codrive::nmt {
class NmtSlave;
class HeartbeatProducer;
class HeartbeatConsumer;
class NodeGuardingResponder;
} // namespace codrive::nmt
namespace codrive::sdo {
class SdoServer;
}
namespace codrive::sync {
class SyncConsumer;
}
namespace codrive::emcy {
class EmcyProducer;
}
namespace codrive::pdo {
class DevicePdo;
}

namespace codrive::sim {

class ParameterStore;

/// The manufacturer object that controls the simulation (sub-indexes below); axis n uses
/// kControlObject + n. Writing 1 injects, writing 0 to kControlSto releases STO.
inline constexpr std::uint16_t kControlObject = 0x2FF0;
inline constexpr std::uint8_t kControlSto = 1;
inline constexpr std::uint8_t kControlOverCurrent = 2;
inline constexpr std::uint8_t kControlFollowingError = 3;
inline constexpr std::uint8_t kControlHeartbeatLoss = 4;
inline constexpr std::uint8_t kControlNodeReset = 5;
/// Touch probe inputs (drives with 60B8h, AKD2G §4.1.5): sub 6/7 (UNSIGNED8) set the input of
/// probe 1/2 now (an edge latches the actual position); sub 8/9 (INTEGER32) put a sensor at a
/// position: the input is high at or beyond it, and an edge latches that position.
inline constexpr std::uint8_t kControlProbe1Input = 6;
inline constexpr std::uint8_t kControlProbe2Input = 7;
inline constexpr std::uint8_t kControlProbe1At = 8;
inline constexpr std::uint8_t kControlProbe2At = 9;

struct SimDeviceConfig {
    NodeId node = 1;
    const SimProfile* profile = nullptr;  ///< required
    unsigned axes = 0;                    ///< 0: the profile's default
    Duration step = milliseconds(1);      ///< motion step
    std::optional<MachineConfig> machine; ///< per axis; nullopt: the profile's machine
};

/// Counters for tests and the daemon's status line.
struct SimDeviceStats {
    std::uint64_t emcy_sent = 0;
    std::uint64_t boot_ups = 0;
    std::uint64_t steps = 0;
};

/// One simulated node. Sans-I/O: feed frames with on_frame(), run on_tick() at
/// next_deadline(); it sends through the bus given at construction. Nothing is sent before
/// start() (power-on: boot-up message, then pre-operational).
class SimDevice final : public ITimed {
public:
    using LogHandler = std::function<void(const std::string&)>;

    /// Builds the dictionary and services. `config.profile` must be set.
    SimDevice(ICanBus& bus, SimDeviceConfig config);
    ~SimDevice() override;
    SimDevice(const SimDevice&) = delete;
    SimDevice& operator=(const SimDevice&) = delete;

    /// Power-on: sends the boot-up message and enters pre-operational (CiA 301 §7.3.2.1).
    void start(TimePoint now);
    void on_frame(const Frame& frame, TimePoint now);
    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    /// Fault injection on one axis (NodeReset and HeartbeatLoss act on the whole device).
    void inject(unsigned axis, FaultKind kind, TimePoint now);
    /// NMT reset node done locally: application + communication parameters, boot-up.
    void reset_node(TimePoint now);
    /// Sets a parameter as if it had been saved with 1010h, so resets keep it (command-line
    /// settings such as the producer heartbeat time). Errors: the dictionary's write abort.
    tl::expected<void, SdoAbort> store_parameter(std::uint16_t index, std::uint8_t subindex,
                                                 std::span<const std::uint8_t> data);

    [[nodiscard]] ObjectDictionary& od() { return od_; }
    [[nodiscard]] DriveCore& axis(unsigned i) { return *axes_.at(i); }
    [[nodiscard]] std::size_t axis_count() const { return axes_.size(); }
    /// The node-ID in effect (changes when a commissioned 5000h takes effect at reset node).
    [[nodiscard]] NodeId node() const { return config_.node; }
    /// The bit-rate code in effect (DS-BVS 5002h), 0 for a drive without one.
    [[nodiscard]] std::uint8_t bit_rate_code() const { return bit_rate_code_; }
    [[nodiscard]] const SimProfile& profile() const { return *config_.profile; }
    [[nodiscard]] nmt::NmtState nmt_state() const;
    [[nodiscard]] const SimDeviceStats& stats() const { return stats_; }
    /// "node 1 akd2g (2 axes)".
    [[nodiscard]] std::string summary() const;
    /// Messages worth a log line ("node 1: EMCY 0x8611 F6001 ... (axis 1)").
    void set_log_handler(LogHandler h) { log_ = std::move(h); }

    /// The device described as an EDS (CiA 306): identity, PDO counts, every object with its
    /// type, access, mappability, factory default and limits.
    [[nodiscard]] DeviceDescription describe() const;

private:
    void assemble();
    void build_objects();
    void install_hooks();
    /// At reset node: applies a new bit rate (recorded) and a new node-ID (restart_as_).
    bool take_commissioning();
    void restart_as(NodeId node, TimePoint now);
    void apply_comm_parameters(TimePoint now);
    void on_axis_event(const AxisEvent& e);
    void send_emcy(const emcy::EmcyMessage& m);
    void heartbeat_lost();
    void heartbeat_recovered();
    void log(const std::string& text);

    ICanBus& bus_;
    SimDeviceConfig config_;
    ObjectDictionary od_;
    std::vector<std::unique_ptr<DriveCore>> axes_;
    std::unique_ptr<sdo::SdoServer> server_;
    std::unique_ptr<nmt::NmtSlave> nmt_;
    std::unique_ptr<nmt::HeartbeatProducer> heartbeat_;
    std::unique_ptr<nmt::HeartbeatConsumer> consumer_;
    std::unique_ptr<nmt::NodeGuardingResponder> guarding_;
    std::unique_ptr<sync::SyncConsumer> sync_;
    std::unique_ptr<emcy::EmcyProducer> emcy_;
    std::unique_ptr<pdo::DevicePdo> pdo_;
    std::unique_ptr<ParameterStore> store_;      ///< 1010h/1011h: what reset node restores
    ActiveErrors errors_{od_, *config_.profile}; ///< 1001h, histories, EMCY per change
    std::uint8_t consumer_node_ = 0;
    std::optional<NodeId> restart_as_; ///< the node-ID to boot as at the next tick
    std::uint8_t bit_rate_code_ = 0;   ///< DS-BVS 5002h in effect
    bool started_ = false;
    bool reset_pending_ = false;
    bool emcy_enabled_ = true;
    TimePoint now_{};
    TimePoint next_step_ = kNever;
    SimDeviceStats stats_;
    LogHandler log_;
};

} // namespace codrive::sim
