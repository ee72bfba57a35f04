// SPDX-License-Identifier: Apache-2.0
// A minimal CANopen device for integration tests: object dictionary, SDO server, NMT slave,
// heartbeat producer, EMCY producer and a SYNC-driven TPDO on one virtual bus endpoint.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/emcy/producer.hpp>
#include <codrive/nmt/heartbeat_producer.hpp>
#include <codrive/nmt/slave.hpp>
#include <codrive/pdo/device.hpp>
#include <codrive/pdo/od_objects.hpp>
#include <codrive/sdo/server.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace codrive::integration {

/// Identity every mini device reports (1000h, 1018h:01..02).
inline constexpr std::uint32_t kDeviceType = 0x00020192;
inline constexpr std::uint32_t kVendorId = 0x000000C0;
inline constexpr std::uint32_t kProductCode = 0x00000D01;

/// Object 2100h: a read-write DOMAIN the tests download to and upload from.
inline constexpr std::uint16_t kScratch = 0x2100;
/// Objects 2200h + k: read-only DOMAINs of kReferenceSizes[k] bytes of reference_pattern().
inline constexpr std::uint16_t kReference = 0x2200;
inline constexpr std::array<std::size_t, 9> kReferenceSizes{0,   1,    4,    7,    100,
                                                            889, 1000, 8192, 65536};

/// Object 2300h: a u32 the device counts up on every SYNC, mapped into TPDO1 (180h + node,
/// transmission type 1: one TPDO after every SYNC while operational).
inline constexpr std::uint16_t kSyncCounter = 0x2300;
[[nodiscard]] inline pdo::PdoConfig counter_tpdo() {
    return pdo::tpdo(1, {{kSyncCounter, 0, 32}}, 1);
}

/// Deterministic content, different per size, so a mixed-up transfer cannot pass.
inline std::vector<std::uint8_t> reference_pattern(std::size_t size, std::uint32_t seed = 0) {
    std::vector<std::uint8_t> out(size);
    std::uint32_t x = 0x9E3779B9U ^ static_cast<std::uint32_t>(size) ^ (seed * 0x85EBCA6BU);
    for (auto& b : out) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        b = static_cast<std::uint8_t>(x);
    }
    return out;
}

/// The device is one ITimed for the test loop: its parts are rebuilt on reboot.
class MiniDevice final : public ITimed {
public:
    MiniDevice(VirtualBus& bus, NodeId node) : bus_(bus), node_(node) {
        bus_.set_frame_handler([this](const Frame& f, TimePoint now) { on_frame(f, now); });
        producer_ = std::make_unique<nmt::HeartbeatProducer>(bus_, node_);
        emcy_ = std::make_unique<emcy::EmcyProducer>(bus_, node_);
        build();
    }
    MiniDevice(const MiniDevice&) = delete;
    MiniDevice& operator=(const MiniDevice&) = delete;

    /// Power-on or reboot: a fresh dictionary (power-on values) and SDO server, then the boot-up
    /// message and pre-operational (CiA 301 §7.3.2.1). A transfer in progress is simply gone.
    void power_on(TimePoint now) {
        last_now_ = now;
        build();
        nmt_ = std::make_unique<nmt::NmtSlave>(node_);
        nmt_->set_state_handler([this](nmt::NmtState, nmt::NmtState to) {
            producer_->set_state(to);
            pdo_->set_operational(to == nmt::NmtState::Operational, last_now_);
        });
        nmt_->set_reset_handler([this](nmt::NmtCommand) { pending_reset_ = true; });
        nmt_->boot_up();
        producer_->set_period(milliseconds(0), now);
        (void)producer_->send_boot_up();
        ++boots_;
    }

    [[nodiscard]] TimePoint next_deadline() const override {
        return std::min({server_->next_deadline(), producer_->next_deadline(),
                         emcy_->next_deadline(), pdo_->next_deadline()});
    }
    void on_tick(TimePoint now) override {
        last_now_ = now;
        for (ITimed* t :
             std::array<ITimed*, 4>{server_.get(), producer_.get(), emcy_.get(), pdo_.get()}) {
            if (t->next_deadline() <= now) {
                t->on_tick(now);
            }
        }
    }
    [[nodiscard]] NodeId node() const { return node_; }
    [[nodiscard]] ObjectDictionary& od() { return *od_; }
    [[nodiscard]] sdo::SdoServer& server() { return *server_; }
    [[nodiscard]] emcy::EmcyProducer& emcy() { return *emcy_; }
    [[nodiscard]] pdo::DevicePdo& pdo() { return *pdo_; }
    [[nodiscard]] nmt::HeartbeatProducer& heartbeat() { return *producer_; }
    [[nodiscard]] nmt::NmtState state() const {
        return nmt_ ? nmt_->state() : nmt::NmtState::BootUp;
    }
    [[nodiscard]] unsigned boots() const { return boots_; }
    /// Bytes currently stored in the scratch DOMAIN.
    [[nodiscard]] std::vector<std::uint8_t> scratch() const {
        const SubObject* s = od_->find(kScratch, 0);
        const auto b = s->value.bytes();
        return {b.begin(), b.end()};
    }
    /// Server statistics survive reboots (summed over every server instance).
    [[nodiscard]] sdo::ServerStats server_stats() const {
        sdo::ServerStats s = retired_stats_;
        add(s, server_->stats());
        return s;
    }

private:
    static void add(sdo::ServerStats& into, const sdo::ServerStats& s) {
        into.requests += s.requests;
        into.completed += s.completed;
        into.aborts_sent += s.aborts_sent;
        into.aborts_received += s.aborts_received;
        into.timeouts += s.timeouts;
        into.frames_ignored += s.frames_ignored;
        into.early_acks += s.early_acks;
        into.repeats_ignored += s.repeats_ignored;
        into.acks_repeated += s.acks_repeated;
    }

    void build() {
        if (server_) {
            add(retired_stats_, server_->stats());
        }
        server_.reset(); // the server and the PDO engine refer to the dictionary: drop them first
        pdo_.reset();
        od_ = std::make_unique<ObjectDictionary>();
        ObjectDictionary& od = *od_;
        od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
                   *Value::from_uint(DataType::Unsigned32, kDeviceType));
        od.add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
                   Value::from_string("codrive mini device"));
        od.add_var(0x1017, "Producer heartbeat time", DataType::Unsigned16, Access::Rw,
                   Value::zero(DataType::Unsigned16));
        od.add_sub(0x1018,
                   SubObject::make(0, "Highest sub-index", DataType::Unsigned8, Access::Ro,
                                   *Value::from_uint(DataType::Unsigned8, 2)),
                   "Identity object");
        od.add_sub(0x1018, SubObject::make(1, "Vendor-ID", DataType::Unsigned32, Access::Ro,
                                           *Value::from_uint(DataType::Unsigned32, kVendorId)));
        od.add_sub(0x1018, SubObject::make(2, "Product code", DataType::Unsigned32, Access::Ro,
                                           *Value::from_uint(DataType::Unsigned32, kProductCode)));
        od.add_var(kScratch, "Scratch domain", DataType::Domain, Access::Rw,
                   Value(DataType::Domain, {}));
        for (std::size_t k = 0; k < kReferenceSizes.size(); ++k) {
            od.add_var(static_cast<std::uint16_t>(kReference + k), "Reference domain",
                       DataType::Domain, Access::Ro,
                       Value(DataType::Domain, reference_pattern(kReferenceSizes[k])));
        }
        // 1017h starts or stops the heartbeat (CiA 301 §7.5.2.15).
        od.on_write(0x1017,
                    [this](std::uint16_t, std::uint8_t,
                           std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                        producer_->set_period(milliseconds(get_le<std::uint16_t>(d.data())),
                                              last_now_);
                        return {};
                    });
        od.add_var(kSyncCounter, "SYNC counter", DataType::Unsigned32, Access::Ro,
                   Value::zero(DataType::Unsigned32), /*pdo_mappable=*/true);
        const std::array<pdo::PdoConfig, 1> preset{counter_tpdo()};
        pdo::PdoObjectDefaults defaults;
        defaults.preset = preset;
        pdo::add_pdo_objects(od, node_, pdo::PdoQuirks{}, defaults);
        pdo::DevicePdoOptions po;
        po.node = node_;
        pdo_ = std::make_unique<pdo::DevicePdo>(od, bus_, po);
        sdo::ServerConfig sc;
        sc.node = node_;
        server_ = std::make_unique<sdo::SdoServer>(od, bus_, sc);
        // CiA 301 Table 50: no SDO in stopped.
        server_->set_access_hook(
            [this](std::uint16_t, std::uint8_t, sdo::Direction) -> std::optional<SdoAbort> {
                if (nmt_ && !nmt_->sdo_allowed()) {
                    return SdoAbort::DataTransferState;
                }
                return std::nullopt;
            });
    }

    void on_frame(const Frame& f, TimePoint now) {
        last_now_ = now;
        if (nmt_ == nullptr) {
            return; // powered but not booted yet
        }
        if (server_->on_frame(f, now)) {
            return;
        }
        if (f.id == cob::kSync && !f.extended()) {
            SubObject* counter = od_->find(kSyncCounter, 0);
            counter->value = *Value::from_uint(
                DataType::Unsigned32, (counter->value.as_uint().value_or(0) + 1) & 0xFFFFFFFFU);
        }
        if (pdo_->on_frame(f, now)) {
            return;
        }
        nmt_->on_frame(f, now);
        if (pending_reset_) {
            pending_reset_ = false;
            power_on(now);
        }
    }

    VirtualBus& bus_;
    NodeId node_;
    std::unique_ptr<ObjectDictionary> od_;
    std::unique_ptr<sdo::SdoServer> server_;
    std::unique_ptr<nmt::HeartbeatProducer> producer_;
    std::unique_ptr<emcy::EmcyProducer> emcy_;
    std::unique_ptr<nmt::NmtSlave> nmt_;
    std::unique_ptr<pdo::DevicePdo> pdo_;
    sdo::ServerStats retired_stats_;
    TimePoint last_now_{};
    unsigned boots_ = 0;
    bool pending_reset_ = false;
};

} // namespace codrive::integration
