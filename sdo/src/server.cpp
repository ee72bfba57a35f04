// SPDX-License-Identifier: Apache-2.0
// The SDO server on a CAN channel: frames in and out of the SDO server machine.
#include <codrive/sdo/server.hpp>

namespace codrive::sdo {

SdoServer::SdoServer(ObjectDictionary& od, ICanBus& bus, ServerConfig config)
    : bus_(bus), request_id_(config.request_id != 0 ? config.request_id : cob::sdo_rx(config.node)),
      response_id_(config.response_id != 0 ? config.response_id : cob::sdo_tx(config.node)),
      machine_(od, config, SdoServerFraming{},
               [this](const Payload& p, std::span<const std::uint8_t>) {
                   if (out_count_ == out_.size()) {
                       flush();
                   }
                   out_[out_count_++] = Frame::make(response_id_, p);
               }) {}

void SdoServer::flush() {
    // A frame the bus refuses (its transmit queue is full) is dropped, as a single send() would
    // drop it: the client's timeout or a repeated request recovers, as on a lossy bus.
    std::size_t done = 0;
    while (done < out_count_) {
        done += bus_.send_many(std::span<const Frame>(out_.data() + done, out_count_ - done));
        if (done < out_count_) {
            ++done;
        }
    }
    out_count_ = 0;
}

bool SdoServer::on_frame(const Frame& frame, TimePoint now) {
    if (frame.id != request_id_ || frame.extended() || frame.rtr() || frame.error()) {
        machine_.count_ignored();
        return false;
    }
    machine_.on_request(frame.payload(), now);
    flush();
    return true;
}

} // namespace codrive::sdo
