// SPDX-License-Identifier: Apache-2.0
// DriveTransport over EtherCAT: object access through CoE SDO, cyclic data through the master's
// LRW process image, so drives::Axis runs unchanged on EtherCAT.
#pragma once

#include <codrive/drives/transport.hpp>
#include <codrive/ethercat/master.hpp>

#include <deque>
#include <vector>

namespace codrive::ethercat {

/// CoE implementation of drives::DriveTransport for one slave. Object accesses are queued and
/// run by poll() (the master's mailbox API is synchronous), so completion callbacks never run
/// inside read()/write(). Cyclic handles resolve against the slave's mapped PDO layout; call
/// them after Master::map_process_data() (SAFE-OP or OP).
class CoeTransport final : public drives::DriveTransport {
public:
    CoeTransport(Master& master, std::size_t slave);

    [[nodiscard]] std::string name() const override;
    void read(std::uint16_t index, std::uint8_t subindex, ReadDone done) override;
    void write(std::uint16_t index, std::uint8_t subindex, drives::Bytes data,
               WriteDone done) override;
    [[nodiscard]] drives::CyclicHandle output(std::uint16_t index,
                                              std::uint8_t subindex) const override;
    [[nodiscard]] drives::CyclicHandle input(std::uint16_t index,
                                             std::uint8_t subindex) const override;
    void set_raw(drives::CyclicHandle h, std::uint64_t raw) override;
    [[nodiscard]] std::optional<std::uint64_t> get_raw(drives::CyclicHandle h) const override;
    /// LRW frames whose inputs were taken into the image (working counter right): a lost frame
    /// leaves the inputs as they were, and the count tells the axis so.
    [[nodiscard]] std::optional<std::uint64_t> input_count(drives::CyclicHandle h) const override;

    /// Runs the queued object accesses (call from the non-cyclic part of the loop). Returns how
    /// many completed.
    std::size_t poll();
    [[nodiscard]] std::size_t pending() const { return queue_.size(); }

private:
    struct Slot {
        std::size_t offset = 0; ///< byte offset in the slave's outputs or inputs
        std::size_t bytes = 0;
        bool output = false;
    };
    using Request = ObjectRequest;
    drives::CyclicHandle resolve(std::uint16_t index, std::uint8_t subindex, bool output) const;

    Master& master_;
    std::size_t slave_;
    std::deque<Request> queue_;
    mutable std::vector<Slot> slots_;
};

} // namespace codrive::ethercat
