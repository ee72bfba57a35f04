// SPDX-License-Identifier: Apache-2.0
// A minimal CANopen slave for master tests: object dictionary, SDO server, NMT slave, heartbeat.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/nmt/heartbeat_producer.hpp>
#include <codrive/nmt/slave.hpp>
#include <codrive/sdo/server.hpp>

#include <memory>

namespace codrive::testing {

class TestDevice {
public:
    TestDevice(VirtualBus& bus, NodeId node, std::uint32_t vendor = 0x6A)
        : bus_(bus), node_(node), vendor_(vendor) {
        build();
        bus_.set_frame_handler([this](const Frame& f, TimePoint now) { on_frame(f, now); });
    }

    /// Power-on / reset: fresh dictionary, boot-up message, pre-operational.
    void boot(TimePoint now) {
        // A reset restores the power-on values of the communication and application objects.
        od_.set<std::uint16_t>(0x1017, 0, 0);
        od_.set<std::int8_t>(0x6060, 0, 0);
        nmt_ = std::make_unique<nmt::NmtSlave>(node_);
        nmt_->set_state_handler(
            [this](nmt::NmtState, nmt::NmtState to) { producer_->set_state(to); });
        nmt_->set_reset_handler([this](nmt::NmtCommand) { pending_reset_ = true; });
        nmt_->boot_up();
        (void)producer_->send_boot_up();
        producer_->set_period(milliseconds(0), now);
    }

    std::vector<ITimed*> timed() { return {server_.get(), producer_.get()}; }
    ObjectDictionary& od() { return od_; }
    nmt::NmtState state() const { return nmt_->state(); }
    int writes_to_6060 = 0;

private:
    void build() {
        od_ = ObjectDictionary{};
        od_.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
                    *Value::from_uint(DataType::Unsigned32, 0x00020192));
        od_.add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
                    Value::from_string("TestDrive"));
        od_.add_var(0x1017, "Producer heartbeat time", DataType::Unsigned16, Access::Rw,
                    Value::zero(DataType::Unsigned16));
        od_.add_var(0x100C, "Guard time", DataType::Unsigned16, Access::Rw,
                    Value::zero(DataType::Unsigned16));
        od_.add_var(0x100D, "Life time factor", DataType::Unsigned8, Access::Rw,
                    Value::zero(DataType::Unsigned8));
        od_.add_var(0x6060, "Modes of operation", DataType::Integer8, Access::Rw,
                    Value::zero(DataType::Integer8));
        od_.add_sub(0x1018,
                    SubObject::make(0, "Highest sub-index", DataType::Unsigned8, Access::Ro,
                                    *Value::from_uint(DataType::Unsigned8, 4)),
                    "Identity object");
        const std::uint32_t ids[4] = {vendor_, 0x1234, 0x00010002, 0xCAFE};
        for (std::uint8_t s = 1; s <= 4; ++s) {
            od_.add_sub(0x1018,
                        SubObject::make(s, "id", DataType::Unsigned32, Access::Ro,
                                        *Value::from_uint(DataType::Unsigned32, ids[s - 1])));
        }
        od_.on_write(0x1017,
                     [this](std::uint16_t, std::uint8_t,
                            std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                         producer_->set_period(milliseconds(get_le<std::uint16_t>(d.data())),
                                               last_now_);
                         return {};
                     });
        od_.on_write(0x6060,
                     [this](std::uint16_t, std::uint8_t,
                            std::span<const std::uint8_t>) -> tl::expected<void, SdoAbort> {
                         ++writes_to_6060;
                         return {};
                     });
        sdo::ServerConfig sc;
        sc.node = node_;
        server_ = std::make_unique<sdo::SdoServer>(od_, bus_, sc);
        if (!producer_) {
            producer_ = std::make_unique<nmt::HeartbeatProducer>(bus_, node_);
        }
        nmt_ = std::make_unique<nmt::NmtSlave>(node_);
    }

    void on_frame(const Frame& f, TimePoint now) {
        last_now_ = now;
        if (server_->on_frame(f, now)) {
            return;
        }
        nmt_->on_frame(f, now);
        if (pending_reset_) {
            pending_reset_ = false;
            boot(now);
        }
    }

    VirtualBus& bus_;
    NodeId node_;
    std::uint32_t vendor_;
    ObjectDictionary od_;
    std::unique_ptr<sdo::SdoServer> server_;
    std::unique_ptr<nmt::HeartbeatProducer> producer_;
    std::unique_ptr<nmt::NmtSlave> nmt_;
    TimePoint last_now_{};
    bool pending_reset_ = false;
};

} // namespace codrive::testing
