// SPDX-License-Identifier: Apache-2.0
// DriveTransport: the transport-neutral access a CiA 402 axis needs — acyclic object access and
// a cyclic process image — implemented over CANopen (SDO + PDO) and EtherCAT CoE.
#pragma once

#include <codrive/core/endian.hpp>
#include <codrive/drives/error.hpp>

#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace codrive::drives {

using Bytes = std::vector<std::uint8_t>;

/// A pre-resolved entry of the cyclic process image (an object mapped into a PDO). Resolving
/// once keeps look-ups off the cyclic path.
struct CyclicHandle {
    std::int32_t slot = -1;
    [[nodiscard]] bool valid() const { return slot >= 0; }
};

/// Object access and process data of one device (node / slave). Objects are named by index and
/// sub-index only — no COB-IDs, no EtherCAT addresses — so the axis model runs unchanged on
/// both wires. Completion callbacks run from the transport's event processing, never from
/// inside the submitting call... unless the transport fails immediately (then they may).
class DriveTransport {
public:
    using ReadDone = std::function<void(DriveResult<Bytes>)>;
    using WriteDone = std::function<void(DriveVoid)>;

    virtual ~DriveTransport() = default;

    /// "node 3", "slave 2": how messages name the device.
    [[nodiscard]] virtual std::string name() const = 0;

    /// Reads an object. Errors: DriveErrc::Transport with the SDO/CoE sentence as message.
    virtual void read(std::uint16_t index, std::uint8_t subindex, ReadDone done) = 0;
    /// Writes an object. Errors as read().
    virtual void write(std::uint16_t index, std::uint8_t subindex, Bytes data, WriteDone done) = 0;

    /// The process-image entry of an object the master sends cyclically (RPDO / RxPDO), or an
    /// invalid handle if it is not mapped.
    [[nodiscard]] virtual CyclicHandle output(std::uint16_t index, std::uint8_t subindex) const = 0;
    /// The entry of an object the drive sends cyclically (TPDO / TxPDO), or invalid.
    [[nodiscard]] virtual CyclicHandle input(std::uint16_t index, std::uint8_t subindex) const = 0;
    /// Sets an output for the next cycle (the low bits of `raw`, little-endian as mapped).
    virtual void set_raw(CyclicHandle h, std::uint64_t raw) = 0;
    /// The last value received for an input; nullopt before the first reception or for an
    /// invalid handle.
    [[nodiscard]] virtual std::optional<std::uint64_t> get_raw(CyclicHandle h) const = 0;
    /// How many times the frame carrying an input has been received, or nullopt if the
    /// transport cannot tell (then every cycle counts as a new sample). Lets the axis tell a
    /// fresh statusword from a repeated one when a TPDO comes late.
    [[nodiscard]] virtual std::optional<std::uint64_t> input_count(CyclicHandle /*h*/) const {
        return std::nullopt;
    }

    /// One object access as a transport queues it until it can be carried out (the CoE
    /// transport's mailbox queue, the controller's hand-off between threads).
    struct ObjectRequest {
        std::uint16_t index = 0;
        std::uint8_t subindex = 0;
        bool is_write = false;
        Bytes data;
        ReadDone read_done;
        WriteDone write_done;

        static ObjectRequest read(std::uint16_t index, std::uint8_t subindex, ReadDone done) {
            ObjectRequest r;
            r.index = index;
            r.subindex = subindex;
            r.read_done = std::move(done);
            return r;
        }
        static ObjectRequest write(std::uint16_t index, std::uint8_t subindex, Bytes data,
                                   WriteDone done) {
            ObjectRequest r;
            r.index = index;
            r.subindex = subindex;
            r.is_write = true;
            r.data = std::move(data);
            r.write_done = std::move(done);
            return r;
        }
    };

    // ---- typed helpers ------------------------------------------------------------------

    template <typename T>
    void read_as(std::uint16_t index, std::uint8_t subindex,
                 std::function<void(DriveResult<T>)> done) {
        static_assert(std::is_arithmetic_v<T>);
        const std::string who = name();
        read(index, subindex, [done = std::move(done), who, index, subindex](DriveResult<Bytes> r) {
            if (!r) {
                done(tl::unexpected(r.error()));
                return;
            }
            if (r->size() < sizeof(T)) {
                done(drive_fail(DriveErrc::Transport,
                                who + ": object " + hex_index(index, subindex) + " has " +
                                    std::to_string(r->size()) + " bytes, expected " +
                                    std::to_string(sizeof(T))));
                return;
            }
            done(get_le<T>(r->data()));
        });
    }

    template <typename T>
    void write_as(std::uint16_t index, std::uint8_t subindex, T value, WriteDone done) {
        static_assert(std::is_arithmetic_v<T>);
        Bytes b(sizeof(T));
        put_le<T>(b.data(), value);
        write(index, subindex, std::move(b), std::move(done));
    }

    template <typename T>
    void set(CyclicHandle h, T value) {
        static_assert(std::is_integral_v<T>);
        set_raw(h, static_cast<std::uint64_t>(static_cast<std::make_unsigned_t<T>>(value)));
    }

    template <typename T>
    [[nodiscard]] std::optional<T> get(CyclicHandle h) const {
        static_assert(std::is_integral_v<T>);
        auto raw = get_raw(h);
        if (!raw) {
            return std::nullopt;
        }
        // Modular conversion keeps the two's complement sign of narrower signed types.
        return static_cast<T>(static_cast<std::make_unsigned_t<T>>(*raw));
    }

    /// "0x6041:00"
    [[nodiscard]] static std::string hex_index(std::uint16_t index, std::uint8_t subindex);
};

} // namespace codrive::drives
