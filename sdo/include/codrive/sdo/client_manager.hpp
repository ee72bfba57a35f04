// SPDX-License-Identifier: Apache-2.0
// SDO clients for many nodes: one queue per node, all nodes in parallel, one frame dispatcher.
#pragma once

#include <codrive/sdo/client.hpp>

#include <array>
#include <memory>
#include <vector>

namespace codrive::sdo {

/// Owns one SdoClient per node (default SDO channel, created on first use) plus any extra
/// channels, routes received frames to them and aggregates their deadlines.
class SdoClientManager final : public ITimed {
public:
    /// `defaults` is the template for clients created by client(); its node is replaced.
    SdoClientManager(ICanBus& bus, const IClock& clock, ClientConfig defaults = {});

    /// The client of the default channel of `node` (1..127), created on first use.
    SdoClient& client(NodeId node);
    /// Adds a client for a non-default channel (its own COB-IDs).
    SdoClient& add_channel(ClientConfig config);

    /// Routes a frame to the client(s) it belongs to. True if an SDO client used it.
    bool on_frame(const Frame& frame, TimePoint now);
    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;
    /// SdoClient::cancel_all() on every client; the number of transfers ended.
    std::size_t cancel_all(std::string_view why);
    /// True if any client has a transfer running or queued.
    [[nodiscard]] bool busy() const;

private:
    ICanBus& bus_;
    const IClock& clock_;
    ClientConfig defaults_;
    std::array<std::unique_ptr<SdoClient>, kMaxNodeId + 1> by_node_{};
    std::vector<std::unique_ptr<SdoClient>> extra_;
};

} // namespace codrive::sdo
