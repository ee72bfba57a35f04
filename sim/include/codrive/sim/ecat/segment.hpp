// SPDX-License-Identifier: Apache-2.0
// A chain of simulated EtherCAT slaves and an in-process link to it (unit tests, no sockets).
#pragma once

#include <codrive/sim/ecat/esc_slave.hpp>

#include <codrive/ethercat/link.hpp>

#include <deque>
#include <memory>
#include <random>
#include <vector>

namespace codrive::sim::ecat {

/// Slaves in line: every slave processes each datagram in turn; the last one returns the frame
/// (the way back through the ports does no processing), with the source MAC's locally
/// administered bit set as an ESC's port 0 does.
class EcatSegment {
public:
    EscSlave& add(std::unique_ptr<EscSlave> slave);
    [[nodiscard]] std::size_t size() const { return slaves_.size(); }
    [[nodiscard]] EscSlave& slave(std::size_t i) { return *slaves_[i]; }

    /// Processes a frame in place; returns false if it is not a well-formed EtherCAT frame
    /// (a real segment would drop it).
    bool process(std::span<std::uint8_t> frame, TimePoint now);
    [[nodiscard]] std::uint64_t frames() const { return frames_; }
    /// True if a processed frame carries a mailbox read that emptied slave `slave`'s SM1 (an
    /// FPRD of its send mailbox with working counter 1): losing that frame loses the answer.
    [[nodiscard]] bool carries_mailbox_answer(std::span<std::uint8_t> frame,
                                              std::size_t slave) const;
    [[nodiscard]] std::uint64_t dropped() const { return dropped_; }

private:
    std::vector<std::unique_ptr<EscSlave>> slaves_;
    std::uint64_t frames_ = 0;
    std::uint64_t dropped_ = 0;
};

/// Loses frames that carry one slave's mailbox answer on their way back to the master: every
/// other one (so the repeat that follows a loss gets through, ETG.1000.4 §6.7.2), until `count`
/// are lost. Used by SegmentLink and codrive-ecat-sim --lose-mailbox-answers.
class MailboxAnswerLoss {
public:
    void arm(std::size_t slave, std::uint64_t count) {
        slave_ = slave;
        left_ = count;
        spare_next_ = false;
    }
    /// True if `frame`, just processed by `segment`, is to be lost.
    bool lose(const EcatSegment& segment, std::span<std::uint8_t> frame) {
        if (left_ == 0 || !segment.carries_mailbox_answer(frame, slave_)) {
            return false;
        }
        spare_next_ = !spare_next_;
        if (!spare_next_) {
            return false;
        }
        --left_;
        ++lost_;
        return true;
    }
    [[nodiscard]] std::size_t slave() const { return slave_; }
    [[nodiscard]] std::uint64_t lost() const { return lost_; }

private:
    std::size_t slave_ = 0;
    std::uint64_t left_ = 0;
    std::uint64_t lost_ = 0;
    bool spare_next_ = false;
};

/// An IEcatLink that hands frames to an EcatSegment synchronously, on a FakeClock: receive()
/// with nothing pending advances the clock to the deadline and times out; idle() advances it.
class SegmentLink final : public ethercat::IEcatLink {
public:
    SegmentLink(EcatSegment& segment, FakeClock& clock) : segment_(segment), clock_(clock) {}
    VoidResult send(std::span<const std::uint8_t> frame) override;
    Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) override;
    void idle(Duration d) override { clock_.advance(d); }
    [[nodiscard]] std::string name() const override { return "in-process segment"; }

    /// Drops the next `n` frames (lost on the wire).
    void drop_next(int n) { drop_ = n; }
    /// Loses the next `n` frames that carry a mailbox answer of slave `slave` on their way back
    /// (processed by the slaves, never received); after each loss the next answer (the repeated
    /// copy) gets through.
    void lose_mailbox_answers(std::size_t slave, int n) {
        loss_.arm(slave, static_cast<std::uint64_t>(n));
    }
    /// Returns `per_thousand` of the processed frames late, chosen by a generator seeded with
    /// `seed`: the receive() that waits for such a frame times out at its deadline, and the
    /// frame comes with the next receive() (as on a host that stalls: the slaves took the
    /// frame's reads and writes, the master never sees them in time). 0 turns it off.
    void delay_returns(unsigned per_thousand, unsigned seed) {
        late_per_thousand_ = per_thousand;
        late_rng_.seed(seed);
    }
    [[nodiscard]] std::uint64_t delayed() const { return delayed_; }
    [[nodiscard]] const std::vector<std::vector<std::uint8_t>>& sent() const { return sent_; }
    void record(bool on) { record_ = on; }
    /// Per-frame wire time the clock advances by.
    void set_latency(Duration d) { latency_ = d; }

private:
    EcatSegment& segment_;
    FakeClock& clock_;
    struct Returning {
        std::vector<std::uint8_t> frame;
        bool late = false; ///< the next receive() times out before it
    };
    std::deque<Returning> pending_;
    std::vector<std::vector<std::uint8_t>> sent_;
    int drop_ = 0;
    MailboxAnswerLoss loss_;
    bool record_ = false;
    Duration latency_ = microseconds(20);
    unsigned late_per_thousand_ = 0;
    std::minstd_rand late_rng_;
    std::uint64_t delayed_ = 0;
};

} // namespace codrive::sim::ecat
