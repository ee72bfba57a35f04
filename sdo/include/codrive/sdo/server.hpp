// SPDX-License-Identifier: Apache-2.0
// SDO server of one CAN node (CiA 301 §7.2.4): the SDO server machine (server_machine.hpp) on a
// CAN channel: expedited, segmented and block transfers, domain streaming and access hooks.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/cob_id.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/sdo/server_machine.hpp>

#include <array>
#include <cstdint>

namespace codrive::sdo {

/// The SDO server of one node on CAN: requests on its request COB-ID go to an SdoServerMachine
/// with CAN's framing, its responses go out on the response COB-ID.
class SdoServer final : public ITimed {
public:
    SdoServer(ObjectDictionary& od, ICanBus& bus, ServerConfig config);
    SdoServer(const SdoServer&) = delete;
    SdoServer& operator=(const SdoServer&) = delete;

    /// Serves uploads of index:sub from `handler` instead of the dictionary.
    void set_domain_upload(std::uint16_t index, std::uint8_t sub, DomainUploadHandler handler) {
        machine_.set_domain_upload(index, sub, std::move(handler));
    }
    /// Sends downloads to index:sub to `handler` instead of the dictionary.
    void set_domain_download(std::uint16_t index, std::uint8_t sub, DomainDownloadHandler handler) {
        machine_.set_domain_download(index, sub, std::move(handler));
    }
    void set_access_hook(AccessHook hook) { machine_.set_access_hook(std::move(hook)); }

    /// Feeds a received frame; true if it was a request on this server's channel.
    bool on_frame(const Frame& frame, TimePoint now);
    [[nodiscard]] TimePoint next_deadline() const override { return machine_.next_deadline(); }
    void on_tick(TimePoint now) override {
        machine_.on_tick(now);
        flush();
    }

    [[nodiscard]] bool busy() const { return machine_.busy(); }
    [[nodiscard]] const ServerStats& stats() const { return machine_.stats(); }
    [[nodiscard]] const ServerConfig& config() const { return machine_.config(); }
    [[nodiscard]] std::uint32_t request_id() const { return request_id_; }

private:
    /// Hands the responses of one request (a whole sub-block of a block upload: up to 127
    /// segments) to the bus together: ICanBus::send_many(), one sendmmsg() per batch on
    /// SocketCAN instead of a system call per segment.
    void flush();

    static constexpr std::size_t kBurst = 32;
    ICanBus& bus_;
    std::uint32_t request_id_;
    std::uint32_t response_id_;
    std::array<Frame, kBurst> out_{}; ///< responses not yet handed to the bus, in order
    std::size_t out_count_ = 0;
    SdoServerMachine machine_;
};

} // namespace codrive::sdo
