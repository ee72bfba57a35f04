// SPDX-License-Identifier: Apache-2.0
// A wire with faults the in-process SegmentLink does not make itself, for the master's unit
// tests: frames that come back garbled or twice, blocking reads whose frame comes back late,
// frames whose receive fails, and sends that fail.
#pragma once

#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/link.hpp>
#include <codrive/sim/ecat/segment.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/core/time.hpp>

#include <algorithm>
#include <deque>
#include <string>
#include <system_error>
#include <vector>

namespace codrive::ethercat::test {

/// Wraps a SegmentLink. The slaves process every frame as sent; the faults happen on the way
/// back.
class FaultyWire final : public IEcatLink {
public:
    FaultyWire(sim::ecat::SegmentLink& inner, FakeClock& clock) : inner_(inner), clock_(clock) {}
    VoidResult send(std::span<const std::uint8_t> frame) override {
        if (send_error_ && sends_to_fail_ != 0) {
            sends_to_fail_ -= sends_to_fail_ > 0 ? 1 : 0;
            return fail(send_error_); // the frame does not leave
        }
        if (late_reads_ > 0 && reads_offset(frame, read_offset_)) {
            // Every other read of the mailbox: the first attempt of each blocking read.
            hold_next_ = (++reads_seen_ % 2) == 1;
            late_reads_ -= hold_next_ ? 1 : 0;
        }
        return inner_.send(frame);
    }
    Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) override {
        if (!back_.empty() && !hold_next_) {
            const auto f = std::move(back_.front());
            back_.pop_front();
            std::copy(f.begin(), f.end(), buffer.begin());
            return f.size();
        }
        auto got = inner_.receive(buffer, deadline);
        if (!got) {
            return got;
        }
        if (hold_next_) { // the slaves took its reads; the master sees it only after its deadline
            hold_next_ = false;
            back_.emplace_back(buffer.begin(), buffer.begin() + static_cast<long>(*got));
            ++held_;
            clock_.set(std::max(clock_.now(), deadline));
            return fail(CoreErrc::Timeout);
        }
        if (fail_reads_ > 0 && carries_answered_read(buffer.first(*got), fail_offset_)) {
            --fail_reads_; // the slave took the read; the master's socket reports an error
            return fail(fail_error_);
        }
        if (garble_ > 0) {
            --garble_;
            buffer[kFirstCommand] ^= 0x0F; // LRW (0x0C) becomes 0x03 (BWR)
        } else if (repeat_ > 0) {
            --repeat_;
            back_.emplace_back(buffer.begin(), buffer.begin() + static_cast<long>(*got));
        }
        return got;
    }
    void idle(Duration d) override { clock_.advance(d); }
    [[nodiscard]] std::string name() const override { return "faulty wire"; }

    /// The next `n` frames that come back have their first datagram's command changed (index
    /// intact, the datagrams no longer match what was sent).
    void garble_next(int n) { garble_ = n; }
    /// The next `n` frames that come back come back twice.
    void repeat_next(int n) { repeat_ = n; }
    /// Of the next 2n frames whose first datagram is an FPRD of `offset`, every other one comes
    /// back after its deadline: the first attempt of n blocking reads in a row. For a slave's
    /// SM1 mailbox, n reads empty SM1 and their answer reaches the master too late.
    void delay_reads(std::uint16_t offset, int n) {
        read_offset_ = offset;
        late_reads_ = n;
        reads_seen_ = 0;
    }
    /// The next `n` frames that come back with an answered FPRD of `offset` anywhere in them
    /// (an SM1 read that emptied the mailbox, say) are not seen: the receive fails with `ec`,
    /// as a socket does when its interface goes down.
    void fail_reads(std::uint16_t offset, int n, std::error_code ec) {
        fail_offset_ = offset;
        fail_reads_ = n;
        fail_error_ = ec;
    }
    [[nodiscard]] int fail_reads_left() const { return fail_reads_; }
    /// Every send fails with `ec` until called again with no error (an interface that is down),
    /// or only the next `n` sends (a transmit queue that is full for a while).
    void fail_sends(std::error_code ec, int n = -1) {
        send_error_ = ec;
        sends_to_fail_ = n;
    }
    [[nodiscard]] int held() const { return held_; }

private:
    /// Where the first datagram's header starts.
    static constexpr std::size_t kFirstDatagram = kEthernetHeaderSize + kEcatHeaderSize;
    static constexpr std::size_t kFirstCommand = kFirstDatagram;
    static bool reads_offset(std::span<const std::uint8_t> frame, std::uint16_t offset) {
        return frame.size() >= kFirstDatagram + 10 && // a datagram header
               frame[kFirstCommand] == static_cast<std::uint8_t>(Command::Fprd) &&
               get_le<std::uint16_t>(frame.data() + kFirstDatagram + 4) == offset;
    }

    static bool carries_answered_read(std::span<std::uint8_t> frame, std::uint16_t offset) {
        bool found = false;
        (void)for_each_datagram(frame, [&](DatagramRef& d) {
            found = found || (d.command == Command::Fprd && d.ado() == offset && d.wkc() == 1);
        });
        return found;
    }

    sim::ecat::SegmentLink& inner_;
    FakeClock& clock_;
    int garble_ = 0;
    int repeat_ = 0;
    std::uint16_t read_offset_ = 0;
    int late_reads_ = 0;
    int reads_seen_ = 0;
    bool hold_next_ = false;
    int held_ = 0;
    std::uint16_t fail_offset_ = 0;
    int fail_reads_ = 0;
    std::error_code fail_error_;
    std::error_code send_error_;
    int sends_to_fail_ = -1; ///< -1: every send while send_error_ is set
    std::deque<std::vector<std::uint8_t>> back_;
};

} // namespace codrive::ethercat::test
