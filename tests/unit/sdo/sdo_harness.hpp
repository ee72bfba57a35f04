// SPDX-License-Identifier: Apache-2.0
// Test harness: an SDO client and server on a virtual bus with a fake clock, plus tampering.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sdo/server.hpp>

#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace codrive::sdo::testing {

/// An ICanBus that lets a test rewrite, drop or refuse frames before they reach the wire, and
/// counts how they were handed over (one by one, or in send_many() bursts).
class TamperBus final : public ICanBus {
public:
    /// Returns false to drop the frame.
    using Mutator = std::function<bool(Frame&)>;
    /// Returns true to refuse the frame as a full transmit queue does (CoreErrc::TxQueueFull).
    using Refuser = std::function<bool(const Frame&)>;
    explicit TamperBus(ICanBus& inner) : inner_(inner) {}
    VoidResult send(const Frame& frame) override {
        ++single_sends;
        return forward(frame);
    }
    std::size_t send_many(std::span<const Frame> frames) override {
        ++bursts;
        std::size_t n = 0;
        while (n < frames.size() && forward(frames[n])) {
            ++n;
        }
        burst_frames += n;
        return n;
    }
    void set_frame_handler(FrameHandler h) override { inner_.set_frame_handler(std::move(h)); }
    void set_event_handler(EventHandler h) override { inner_.set_event_handler(std::move(h)); }
    [[nodiscard]] std::size_t tx_pending() const override { return inner_.tx_pending(); }
    [[nodiscard]] const BusStats& stats() const override { return inner_.stats(); }
    [[nodiscard]] const std::string& name() const override { return inner_.name(); }
    Mutator mutate;
    Refuser refuse;
    std::size_t single_sends = 0; ///< send() calls
    std::size_t bursts = 0;       ///< send_many() calls
    std::size_t burst_frames = 0; ///< frames send_many() accepted

private:
    VoidResult forward(const Frame& frame) {
        if (refuse && refuse(frame)) {
            return codrive::fail(CoreErrc::TxQueueFull);
        }
        Frame f = frame;
        if (mutate && !mutate(f)) {
            return {};
        }
        return inner_.send(f);
    }
    ICanBus& inner_;
};

inline constexpr NodeId kNode = 4;

/// Bytes 0..n-1 of a pattern that differs at every position of a 7-byte segment.
inline Bytes pattern(std::size_t n, std::uint8_t seed = 1) {
    Bytes b(n);
    for (std::size_t i = 0; i < n; ++i) {
        b[i] = static_cast<std::uint8_t>((i * 31U + seed + (i >> 8)) & 0xFFU);
    }
    return b;
}

/// Fills the dictionary with the objects the tests use.
inline void add_test_objects(ObjectDictionary& od) {
    od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
               Value(DataType::Unsigned32, {0x92, 0x01, 0x02, 0x00}));
    od.add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
               Value::from_string("codrive test"));
    od.add_var(0x2000, "Writable u32", DataType::Unsigned32, Access::Rw,
               Value(DataType::Unsigned32, {0, 0, 0, 0}));
    od.add_var(0x2001, "Write-only u16", DataType::Unsigned16, Access::Wo,
               Value(DataType::Unsigned16, {0, 0}));
    SubObject limited;
    limited.subindex = 0;
    limited.name = "Limited u16";
    limited.type = DataType::Unsigned16;
    limited.access = Access::Rw;
    limited.value = Value(DataType::Unsigned16, {10, 0});
    limited.low_limit = Value(DataType::Unsigned16, {5, 0});
    limited.high_limit = Value(DataType::Unsigned16, {100, 0});
    Object obj;
    obj.index = 0x2002;
    obj.name = "Limited u16";
    obj.subs[0] = limited;
    od.insert(obj);
    od.add_var(0x2100, "Domain", DataType::Domain, Access::Rw, Value(DataType::Domain, {}));
    SubObject s0;
    s0.subindex = 0;
    s0.name = "Highest sub-index supported";
    s0.type = DataType::Unsigned8;
    s0.access = Access::Const;
    s0.value = Value(DataType::Unsigned8, {2});
    od.add_sub(0x1018, s0, "Identity object");
    SubObject s1 = s0;
    s1.subindex = 1;
    s1.name = "Vendor-ID";
    s1.type = DataType::Unsigned32;
    s1.access = Access::Ro;
    s1.value = Value(DataType::Unsigned32, {0x78, 0x56, 0x34, 0x12});
    od.add_sub(0x1018, s1);
    SubObject s2 = s1;
    s2.subindex = 2;
    s2.name = "Product code";
    s2.value = Value(DataType::Unsigned32, {2, 0, 0, 0});
    od.add_sub(0x1018, s2);
}

/// Client (endpoint "master") and server of node 4 (endpoint "node") on one virtual network.
struct Harness {
    explicit Harness(ServerConfig server_config = {}, ClientConfig client_config = {})
        : master(net.endpoint("master")), node(net.endpoint("node")), client_bus(master),
          server_bus(node), server(od, server_bus, with_node(server_config)),
          client(client_bus, clock, with_node(client_config)) {
        add_test_objects(od);
        master.set_frame_handler([this](const Frame& f, TimePoint t) { client.on_frame(f, t); });
        node.set_frame_handler([this](const Frame& f, TimePoint t) { server.on_frame(f, t); });
    }

    template <typename C>
    static C with_node(C c) {
        c.node = kNode;
        return c;
    }

    /// Runs the network until `until_done` or the time passes.
    void run(Duration d = std::chrono::seconds(10)) {
        net.run_until(clock, clock.now() + d, {&client, &server});
    }

    std::optional<SdoResult<Bytes>> upload(std::uint16_t index, std::uint8_t sub,
                                           TransferOptions o = {}) {
        std::optional<SdoResult<Bytes>> out;
        client.upload(
            index, sub, [&](SdoResult<Bytes> r) { out = std::move(r); }, std::move(o));
        run();
        return out;
    }
    std::optional<SdoResult<void>> download(std::uint16_t index, std::uint8_t sub, Bytes data,
                                            TransferOptions o = {}) {
        std::optional<SdoResult<void>> out;
        client.download(
            index, sub, std::move(data), [&](SdoResult<void> r) { out = std::move(r); },
            std::move(o));
        run();
        return out;
    }

    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master;
    VirtualBus& node;
    TamperBus client_bus;
    TamperBus server_bus;
    ObjectDictionary od;
    SdoServer server;
    SdoClient client;
};

/// The error sentence of a failed result, or "" if it succeeded.
template <typename T>
std::string message(const std::optional<SdoResult<T>>& r) {
    if (!r) {
        return "<no result>";
    }
    return *r ? std::string() : r->error().to_string();
}

} // namespace codrive::sdo::testing
