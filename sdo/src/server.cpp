// SPDX-License-Identifier: Apache-2.0
// The SDO server on a CAN channel: frames in and out of the SDO server machine.
#include <codrive/sdo/server.hpp>

namespace codrive::sdo {

SdoServer::SdoServer(ObjectDictionary& od, ICanBus& bus, ServerConfig config)
    : bus_(bus), request_id_(config.request_id != 0 ? config.request_id : cob::sdo_rx(config.node)),
      response_id_(config.response_id != 0 ? config.response_id : cob::sdo_tx(config.node)),
      machine_(od, config, SdoServerFraming{},
               [this](const Payload& p, std::span<const std::uint8_t>) {
                   (void)bus_.send(Frame::make(response_id_, p));
               }) {}

bool SdoServer::on_frame(const Frame& frame, TimePoint now) {
    if (frame.id != request_id_ || frame.extended() || frame.rtr() || frame.error()) {
        machine_.count_ignored();
        return false;
    }
    machine_.on_request(frame.payload(), now);
    return true;
}

} // namespace codrive::sdo
