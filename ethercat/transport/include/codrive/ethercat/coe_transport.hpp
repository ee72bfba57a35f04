// SPDX-License-Identifier: Apache-2.0
// DriveTransport over EtherCAT: object access through CoE SDO, cyclic data through the master's
// LRW process image, so drives::Axis runs unchanged on EtherCAT.
#pragma once

#include <codrive/drives/transport.hpp>
#include <codrive/ethercat/master.hpp>

#include <deque>
#include <functional>
#include <memory>
#include <vector>

namespace codrive::ethercat {

/// CoE implementation of drives::DriveTransport for one slave. Object accesses go to the
/// master's mailbox channel of the slave at once; their completions are delivered by poll(),
/// so callbacks never run inside read()/write(). Cyclic handles resolve against the slave's
/// mapped PDO layout; call them after Master::map_process_data() (SAFE-OP or OP).
class CoeTransport final : public drives::DriveTransport {
public:
    /// How the mailbox transfers advance.
    enum class Drive {
        /// poll() runs mailbox-only frames until the transfers queued so far are done
        /// (tools and tests that run no cyclic exchange).
        Blocking,
        /// The caller's cyclic exchange (send/receive_process_data) carries them; poll() only
        /// delivers completions and never touches the link (the controller's cycle).
        Cyclic,
    };
    CoeTransport(Master& master, std::size_t slave, Drive drive = Drive::Blocking);

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

    /// Delivers the completions of object accesses (Blocking: first runs mailbox frames until
    /// the accesses queued so far are done). Returns how many completed.
    std::size_t poll();
    /// Object accesses whose completion has not been delivered yet.
    [[nodiscard]] std::size_t pending() const { return in_flight_; }

private:
    struct Slot {
        std::size_t offset = 0; ///< byte offset in the slave's outputs or inputs
        std::size_t bytes = 0;
        bool output = false;
    };
    struct Completion {
        ReadDone read_done;
        WriteDone write_done;
        CoeOutcome outcome;
    };
    using Completions = std::deque<Completion>;
    drives::CyclicHandle resolve(std::uint16_t index, std::uint8_t subindex, bool output) const;
    void submitted(VoidResult r, Completion c);
    /// Starts one transfer with `launch` (the master's async upload or download), its outcome
    /// queued for poll().
    void submit(Completion c, const std::function<VoidResult(CoeDone)>& launch);

    Master& master_;
    std::size_t slave_;
    Drive drive_;
    std::size_t in_flight_ = 0;
    /// Shared with the master's callbacks, so a transport destroyed before its transfers end
    /// leaves them a valid place to write to.
    std::shared_ptr<Completions> completed_ = std::make_shared<Completions>();
    mutable std::vector<Slot> slots_;
};

} // namespace codrive::ethercat
