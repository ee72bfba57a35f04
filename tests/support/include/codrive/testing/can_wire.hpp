// SPDX-License-Identifier: Apache-2.0
// What a test sees on a CAN interface from its own socket while other processes (a master, the
// simulated drives) use it: heartbeat states, EMCY codes, TPDO/SYNC counts, the controlwords a
// master sends and the statuswords the drives report; plus one SDO read of its own.
#pragma once

#include <codrive/core/endian.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/sdo/client.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace codrive::testing {

/// CiA 301 §7.2.8.3.2 heartbeat states.
inline constexpr std::uint8_t kNmtPreOperational = 0x7F;
inline constexpr std::uint8_t kNmtOperational = 0x05;

class CanWire {
public:
    explicit CanWire(const std::string& iface = "vcan0") {
        auto loop = EventLoop::create();
        auto bus = SocketCanBus::open(iface);
        if (!loop || !bus) {
            return;
        }
        loop_ = std::move(*loop);
        bus_ = std::move(*bus);
        bus_->set_frame_handler([this](const Frame& f, TimePoint t) { on_frame(f, t); });
        (void)bus_->attach(*loop_);
    }
    [[nodiscard]] bool ok() const { return bus_ != nullptr; }

    bool wait(const std::function<bool()>& pred, Duration timeout) {
        return loop_->run_until(pred, timeout);
    }
    void run_for(Duration d) { (void)loop_->run_until(loop_->now() + d); }

    [[nodiscard]] bool emcy_seen(NodeId node, std::uint16_t code) const {
        for (auto c : emcy_[node]) {
            if (c == code) {
                return true;
            }
        }
        return false;
    }
    [[nodiscard]] std::optional<std::uint8_t> hb_state(NodeId node) const { return hb_[node]; }
    [[nodiscard]] std::uint64_t tpdos(NodeId node) const { return tpdo_[node]; }
    [[nodiscard]] std::uint64_t syncs() const { return syncs_; }
    /// SDO requests (0x600 + node) any client sent to `node`.
    [[nodiscard]] std::uint64_t sdo_requests(NodeId node) const { return sdo_rx_[node]; }
    /// NMT commands seen (CiA 301 §7.2.8.3.1): command specifier and node (0 = all), in order.
    [[nodiscard]] const std::vector<std::pair<std::uint8_t, std::uint8_t>>& nmt() const {
        return nmt_;
    }
    /// Controlwords (6040h) the master sent to `node`, in order, consecutive repeats folded:
    /// the first two bytes of RPDO1 (every drive layout maps 6040h first) and expedited SDO
    /// downloads to 6040h:00.
    [[nodiscard]] const std::vector<std::uint16_t>& controlwords(NodeId node) const {
        return cw_[node];
    }
    /// Statuswords (6041h) `node` reported in the first two bytes of TPDO1, repeats folded.
    [[nodiscard]] const std::vector<std::uint16_t>& statuswords(NodeId node) const {
        return sw_[node];
    }

    /// Controlwords and statuswords of `node` in the order they were on the wire (repeats
    /// folded): statuswords from TPDO1 and from expedited SDO uploads of 6041h:00 (a master
    /// that polls them), controlwords as controlwords() has them.
    struct WordEvent {
        bool controlword; ///< true: the master's 6040h; false: the drive's 6041h
        std::uint16_t value;
    };
    [[nodiscard]] const std::vector<WordEvent>& timeline(NodeId node) const {
        return timeline_[node];
    }

    /// Reads an object of `node` by SDO (expedited); nullopt on failure. Only while no other
    /// SDO client talks to the node (the COB-IDs are the node's).
    std::optional<std::uint16_t> read_u16(NodeId node, std::uint16_t index) {
        sdo::ClientConfig cc;
        cc.node = node;
        cc.timeout = std::chrono::milliseconds(500);
        client_ = std::make_unique<sdo::SdoClient>(*bus_, RealClock::instance(), cc);
        loop_->add_timed(client_.get());
        std::optional<sdo::SdoResult<std::uint16_t>> r;
        client_->read<std::uint16_t>(index, 0,
                                     [&](sdo::SdoResult<std::uint16_t> v) { r = std::move(v); });
        loop_->run_until([&] { return r.has_value(); }, std::chrono::seconds(2));
        loop_->remove_timed(client_.get());
        client_.reset();
        if (!r || !*r) {
            return std::nullopt;
        }
        return **r;
    }

    VoidResult send(const Frame& f) { return bus_->send(f); }

private:
    static void fold(std::vector<std::uint16_t>& v, std::uint16_t x) {
        if (v.empty() || v.back() != x) {
            v.push_back(x);
        }
    }
    void note(NodeId node, bool controlword, std::uint16_t x) {
        auto& t = timeline_[node];
        if (t.empty() || t.back().controlword != controlword || t.back().value != x) {
            t.push_back({controlword, x});
        }
    }
    void on_frame(const Frame& f, TimePoint t) {
        if (client_) {
            client_->on_frame(f, t);
        }
        if (f.error() || f.extended()) {
            return;
        }
        const std::uint32_t fn = f.id & 0x780;
        const auto node = static_cast<NodeId>(f.id & 0x7F);
        if (f.id == 0x000 && f.len == 2) {
            nmt_.emplace_back(f.data[0], f.data[1]);
        } else if (f.id == 0x80) {
            ++syncs_;
        } else if (fn == 0x080 && f.len >= 2) {
            emcy_[node].push_back(get_le<std::uint16_t>(f.data.data()));
        } else if (fn == 0x700 && f.len == 1) {
            hb_[node] = static_cast<std::uint8_t>(f.data[0] & 0x7F);
        } else if (fn == 0x180 || fn == 0x280 || fn == 0x380 || fn == 0x480) {
            ++tpdo_[node];
            if (fn == 0x180 && f.len >= 2) {
                fold(sw_[node], get_le<std::uint16_t>(f.data.data()));
                note(node, false, get_le<std::uint16_t>(f.data.data()));
            }
        } else if (fn == 0x200 && f.len >= 2) {
            fold(cw_[node], get_le<std::uint16_t>(f.data.data()));
            note(node, true, get_le<std::uint16_t>(f.data.data()));
        }
        if (fn == 0x580 && f.len == 8 && (f.data[0] & 0xE3) == 0x43 &&
            get_le<std::uint16_t>(&f.data[1]) == 0x6041 && f.data[3] == 0) {
            // CiA 301 §7.2.4.3.4: initiate upload response, expedited (scs 2, e = 1, s = 1).
            note(node, false, get_le<std::uint16_t>(&f.data[4]));
        }
        if (fn == 0x600) {
            ++sdo_rx_[node];
        }
        if (fn == 0x600 && f.len == 8 && (f.data[0] & 0xE0) == 0x20 && (f.data[0] & 0x02) != 0 &&
            get_le<std::uint16_t>(&f.data[1]) == 0x6040 && f.data[3] == 0) {
            // CiA 301 §7.2.4.3.3: initiate download, expedited (ccs 1, e = 1).
            fold(cw_[node], get_le<std::uint16_t>(&f.data[4]));
            note(node, true, get_le<std::uint16_t>(&f.data[4]));
        }
    }

    std::unique_ptr<EventLoop> loop_;
    std::unique_ptr<SocketCanBus> bus_;
    std::unique_ptr<sdo::SdoClient> client_;
    std::array<std::vector<std::uint16_t>, 128> emcy_{};
    std::array<std::optional<std::uint8_t>, 128> hb_{};
    std::array<std::uint64_t, 128> tpdo_{};
    std::array<std::vector<std::uint16_t>, 128> cw_{};
    std::array<std::vector<std::uint16_t>, 128> sw_{};
    std::array<std::vector<WordEvent>, 128> timeline_{};
    std::array<std::uint64_t, 128> sdo_rx_{};
    std::vector<std::pair<std::uint8_t, std::uint8_t>> nmt_;
    std::uint64_t syncs_ = 0;
};

} // namespace codrive::testing
