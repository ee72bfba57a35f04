// SPDX-License-Identifier: Apache-2.0
// Frame routing and deadline aggregation over the SDO clients of many nodes.
#include <codrive/sdo/client_manager.hpp>

#include <algorithm>

namespace codrive::sdo {

SdoClientManager::SdoClientManager(ICanBus& bus, const IClock& clock, ClientConfig defaults)
    : bus_(bus), clock_(clock), defaults_(defaults) {}

SdoClient& SdoClientManager::client(NodeId node) {
    auto& slot = by_node_.at(node);
    if (!slot) {
        ClientConfig config = defaults_;
        config.node = node;
        config.request_id = 0;
        config.response_id = 0;
        slot = std::make_unique<SdoClient>(bus_, clock_, config);
    }
    return *slot;
}

SdoClient& SdoClientManager::add_channel(ClientConfig config) {
    extra_.push_back(std::make_unique<SdoClient>(bus_, clock_, config));
    return *extra_.back();
}

std::size_t SdoClientManager::cancel_all(std::string_view why) {
    std::size_t ended = 0;
    for (auto& c : by_node_) {
        ended += c ? c->cancel_all(why) : 0;
    }
    for (auto& c : extra_) {
        ended += c->cancel_all(why);
    }
    return ended;
}

bool SdoClientManager::on_frame(const Frame& frame, TimePoint now) {
    if (frame.extended() || frame.error()) {
        return false;
    }
    bool used = false;
    const std::uint32_t id = frame.id;
    if (id > cob::kSdoTx && id <= cob::kSdoTx + kMaxNodeId) {
        if (auto& c = by_node_[id - cob::kSdoTx]; c && c->response_id() == id) {
            used = c->on_frame(frame, now) || used;
        }
    } else if (id > cob::kHeartbeat && id <= cob::kHeartbeat + kMaxNodeId) {
        if (auto& c = by_node_[id - cob::kHeartbeat]) {
            (void)c->on_frame(frame, now);
        }
    }
    for (auto& c : extra_) {
        if (c->response_id() == id || id == cob::heartbeat(c->config().node)) {
            used = c->on_frame(frame, now) || used;
        }
    }
    return used;
}

TimePoint SdoClientManager::next_deadline() const {
    TimePoint t = kNever;
    for (const auto& c : by_node_) {
        if (c) {
            t = std::min(t, c->next_deadline());
        }
    }
    for (const auto& c : extra_) {
        t = std::min(t, c->next_deadline());
    }
    return t;
}

void SdoClientManager::on_tick(TimePoint now) {
    for (auto& c : by_node_) {
        if (c && c->next_deadline() <= now) {
            c->on_tick(now);
        }
    }
    for (auto& c : extra_) {
        if (c->next_deadline() <= now) {
            c->on_tick(now);
        }
    }
}

bool SdoClientManager::busy() const {
    return std::any_of(by_node_.begin(), by_node_.end(),
                       [](const auto& c) { return c && c->busy(); }) ||
           std::any_of(extra_.begin(), extra_.end(), [](const auto& c) { return c->busy(); });
}

} // namespace codrive::sdo
