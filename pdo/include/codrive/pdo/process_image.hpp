// SPDX-License-Identifier: Apache-2.0
// A node's typed process image: the PDO payloads, addressed by slot handles resolved at setup.
#pragma once

#include <codrive/core/endian.hpp>
#include <codrive/core/time.hpp>
#include <codrive/pdo/error.hpp>
#include <codrive/pdo/types.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace codrive::pdo {

/// A mapped object's place in a node's process image: which PDO, where, how long. Resolve it
/// once with ProcessImage::slot(); then set/get are a few instructions with no lookup.
struct Slot {
    static constexpr std::uint16_t kNone = 0xFFFF;
    std::uint16_t pdo = kNone; ///< index into the image's PDO table
    std::uint8_t bit_offset = 0;
    std::uint8_t bits = 0;
    [[nodiscard]] bool valid() const { return pdo != kNone; }
};

namespace detail {

/// Runtime state of one PDO on the master side. Fixed size, so the cyclic path never allocates.
struct PdoChannel {
    PdoConfig config; ///< as configured (setup only; the cyclic path uses the fields below)
    NodeId node = 0;
    PdoDir dir = PdoDir::Tpdo;
    std::uint8_t number = 0;
    std::uint8_t type = 0;  ///< transmission type
    std::uint8_t every = 1; ///< 1..240 for cyclic synchronous types
    std::uint8_t len = 0;   ///< payload bytes
    bool extended = false;
    std::uint32_t can_id = 0;
    std::array<std::uint8_t, 8> data{};
    bool dirty = false; ///< RPDO: changed since it was last sent

    // Sending (RPDO) / receiving (TPDO) state.
    std::uint8_t sync_div = 0; ///< RPDO: SYNCs since last send
    Duration inhibit{0};
    Duration event_period{0};
    TimePoint last_tx{};
    bool sent_once = false;
    TimePoint last_rx{};
    std::uint64_t window_start = 0; ///< TPDO: first SYNC of the current expectation window
    bool window_open = false;
    bool received_in_window = false;
    std::uint32_t owed = 0; ///< TPDO: closed windows still waiting for a (late) frame
    bool silent = false;    ///< TPDO: reported missing or silent, not received since
    TimePoint watch_from{}; ///< TPDO: event-timer monitoring reference before the first frame

    std::uint64_t tx_count = 0;
    std::uint64_t rx_count = 0;
    std::uint64_t missing = 0;
    std::uint64_t length_errors = 0;
    std::uint64_t send_errors = 0;
};

[[nodiscard]] inline std::uint64_t read_bits(const std::uint8_t* data, unsigned offset,
                                             unsigned bits) {
    std::uint64_t v = 0;
    for (unsigned i = 0; i < bits; ++i) {
        const unsigned b = offset + i;
        v |= static_cast<std::uint64_t>((data[b / 8] >> (b % 8)) & 1U) << i;
    }
    return v;
}

inline void write_bits(std::uint8_t* data, unsigned offset, unsigned bits, std::uint64_t v) {
    for (unsigned i = 0; i < bits; ++i) {
        const unsigned b = offset + i;
        const auto mask = static_cast<std::uint8_t>(1U << (b % 8));
        if (((v >> i) & 1U) != 0) {
            data[b / 8] = static_cast<std::uint8_t>(data[b / 8] | mask);
        } else {
            data[b / 8] = static_cast<std::uint8_t>(data[b / 8] & ~mask);
        }
    }
}

} // namespace detail

/// The process image of one node: outputs (RPDO payloads, written by the application) and
/// inputs (TPDO payloads, written by received frames). Owned by PdoMaster.
class ProcessImage {
public:
    [[nodiscard]] NodeId node() const { return node_; }

    /// Resolves (index, sub) to its slot. Errors: UnknownObject ("node 2: 0x6064:00 is not
    /// mapped in any PDO") — call at setup, not on the cyclic path (the error allocates).
    [[nodiscard]] PdoResult<Slot> slot(std::uint16_t index, std::uint8_t subindex) const;
    /// Same, restricted to one direction (an object may be in an RPDO and a TPDO).
    [[nodiscard]] PdoResult<Slot> slot(std::uint16_t index, std::uint8_t subindex,
                                       PdoDir dir) const;

    /// Writes an output. T is the object's C++ type (int32_t for INTEGER32, ...). For a slot
    /// of another length the value is truncated to the slot's bits. Marks the RPDO changed
    /// (acyclic and event-driven RPDOs go out because of it).
    template <typename T>
    void set(Slot s, T v) {
        static_assert(std::is_arithmetic_v<T>);
        if constexpr (std::is_same_v<T, bool>) {
            set<std::uint8_t>(s, v ? std::uint8_t{1} : std::uint8_t{0});
        } else {
            set_value<T>(s, v);
        }
    }

    /// Reads an input (or the current output value). Signed types are sign-extended from the
    /// slot's length.
    template <typename T>
    [[nodiscard]] T get(Slot s) const {
        static_assert(std::is_arithmetic_v<T>);
        if constexpr (std::is_same_v<T, bool>) {
            return get<std::uint8_t>(s) != 0;
        } else {
            return get_value<T>(s);
        }
    }

private:
    template <typename T>
    void set_value(Slot s, T v) {
        detail::PdoChannel& p = pdos_[s.pdo];
        std::uint8_t* at = p.data.data() + s.bit_offset / 8;
        if (s.bits == sizeof(T) * 8 && s.bit_offset % 8 == 0) {
            std::uint8_t bytes[sizeof(T)];
            put_le<T>(bytes, v);
            if (std::memcmp(at, bytes, sizeof(T)) == 0) {
                return;
            }
            std::memcpy(at, bytes, sizeof(T));
        } else {
            std::uint64_t raw = 0;
            if constexpr (std::is_floating_point_v<T>) {
                using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
                raw = std::bit_cast<U>(v);
            } else {
                raw = static_cast<std::uint64_t>(v);
            }
            if (detail::read_bits(p.data.data(), s.bit_offset, s.bits) ==
                (s.bits >= 64 ? raw : (raw & ((std::uint64_t{1} << s.bits) - 1)))) {
                return;
            }
            detail::write_bits(p.data.data(), s.bit_offset, s.bits, raw);
        }
        p.dirty = true;
        *changed_ = true;
    }

    template <typename T>
    [[nodiscard]] T get_value(Slot s) const {
        const detail::PdoChannel& p = pdos_[s.pdo];
        if (s.bits == sizeof(T) * 8 && s.bit_offset % 8 == 0) {
            return get_le<T>(p.data.data() + s.bit_offset / 8);
        }
        const std::uint64_t raw = detail::read_bits(p.data.data(), s.bit_offset, s.bits);
        if constexpr (std::is_floating_point_v<T>) {
            using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
            return std::bit_cast<T>(static_cast<U>(raw));
        } else if constexpr (std::is_signed_v<T>) {
            if (s.bits > 0 && s.bits < 64 && ((raw >> (s.bits - 1)) & 1U) != 0) {
                return static_cast<T>(raw | (~std::uint64_t{0} << s.bits));
            }
            return static_cast<T>(raw);
        } else {
            return static_cast<T>(raw);
        }
    }

public:
    /// When the TPDO holding the slot was last received (TimePoint{} if never).
    [[nodiscard]] TimePoint rx_time(Slot s) const { return pdos_[s.pdo].last_rx; }
    /// How many times the PDO holding the slot was received (TPDO) or sent (RPDO).
    [[nodiscard]] std::uint64_t count(Slot s) const {
        const auto& p = pdos_[s.pdo];
        return p.dir == PdoDir::Tpdo ? p.rx_count : p.tx_count;
    }
    /// Marks an RPDO for sending at the next opportunity even if nothing changed.
    void touch(Slot s) {
        pdos_[s.pdo].dirty = true;
        *changed_ = true;
    }

    /// The PDOs of this node (configuration and counters).
    [[nodiscard]] const std::vector<detail::PdoChannel>& pdos() const { return pdos_; }

private:
    friend class PdoMaster;
    NodeId node_ = 0;
    std::vector<detail::PdoChannel> pdos_;
    bool* changed_ = nullptr;
};

} // namespace codrive::pdo
