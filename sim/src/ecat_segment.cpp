// SPDX-License-Identifier: Apache-2.0
// A chain of simulated ESCs processing frames in place, and the in-process link to it.
#include <codrive/sim/ecat/segment.hpp>

#include <codrive/ethercat/datagram.hpp>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

EscSlave& EcatSegment::add(std::unique_ptr<EscSlave> slave) {
    slaves_.push_back(std::move(slave));
    return *slaves_.back();
}

bool EcatSegment::process(std::span<std::uint8_t> frame, TimePoint now) {
    std::vector<DatagramRef> refs;
    if (!for_each_datagram(frame, [&](DatagramRef& d) { refs.push_back(d); })) {
        ++dropped_;
        return false;
    }
    ++frames_;
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        EscSlave& s = *slaves_[i];
        s.before_frame(now);
        ChainContext ctx{i, slaves_.size(), now};
        for (const auto& d : refs) {
            s.process(d, ctx);
        }
        s.after_frame(now);
    }
    // Port 0 of the first ESC sets the locally-administered bit of the source MAC on the way
    // back, so a master can tell returned frames from its own (ETG.1000.4 §5.3 note).
    if (frame.size() > 6) {
        frame[6] = static_cast<std::uint8_t>(frame[6] | 0x02);
    }
    return true;
}

bool EcatSegment::carries_mailbox_answer(std::span<std::uint8_t> frame, std::size_t slave) const {
    if (slave >= slaves_.size()) {
        return false;
    }
    const EscSlave& s = *slaves_[slave];
    const std::uint16_t station = s.station_address();
    const std::uint16_t offset = s.sii().tx_mailbox_offset;
    bool found = false;
    (void)for_each_datagram(frame, [&](DatagramRef& d) {
        found = found || (d.command == Command::Fprd && d.adp() == station && d.ado() == offset &&
                          d.wkc() == 1);
    });
    return found;
}

VoidResult SegmentLink::send(std::span<const std::uint8_t> frame) {
    if (record_) {
        sent_.emplace_back(frame.begin(), frame.end());
    }
    clock_.advance(latency_);
    if (drop_ > 0) {
        --drop_;
        return {};
    }
    std::vector<std::uint8_t> f(frame.begin(), frame.end());
    if (segment_.process(f, clock_.now()) && !loss_.lose(segment_, f)) {
        const bool late = late_per_thousand_ > 0 && late_rng_() % 1000 < late_per_thousand_;
        delayed_ += late ? 1 : 0;
        pending_.push_back({std::move(f), late});
    }
    return {};
}

Result<std::size_t> SegmentLink::receive(std::span<std::uint8_t> buffer, TimePoint deadline) {
    if (pending_.empty() || pending_.front().late) {
        if (!pending_.empty()) {
            pending_.front().late = false; // it comes with the next receive()
        }
        if (clock_.now() < deadline) {
            clock_.set(deadline);
        }
        return fail(CoreErrc::Timeout);
    }
    auto f = std::move(pending_.front().frame);
    pending_.pop_front();
    const std::size_t n = std::min(f.size(), buffer.size());
    std::copy_n(f.begin(), n, buffer.begin());
    return n;
}

} // namespace codrive::sim::ecat
