// SPDX-License-Identifier: Apache-2.0
// Lock-free hand-off of an axis's object accesses between the cyclic and the acyclic thread.
#include "handoff_transport.hpp"

namespace codrive::controller {

HandoffTransport::HandoffTransport(drives::DriveTransport& inner)
    : inner_(inner), name_(inner.name()) {}

void HandoffTransport::read(std::uint16_t index, std::uint8_t subindex, ReadDone done) {
    Request r = Request::read(index, subindex, std::move(done));
    if (!requests_.push(r)) {
        r.read_done(drives::drive_fail(drives::DriveErrc::Transport,
                                       name_ + ": too many object accesses waiting for the "
                                               "acyclic thread (64)"));
    }
}

void HandoffTransport::write(std::uint16_t index, std::uint8_t subindex, drives::Bytes data,
                             WriteDone done) {
    Request r = Request::write(index, subindex, std::move(data), std::move(done));
    if (!requests_.push(r)) {
        r.write_done(drives::drive_fail(drives::DriveErrc::Transport,
                                        name_ + ": too many object accesses waiting for the "
                                                "acyclic thread (64)"));
    }
}

std::size_t HandoffTransport::deliver_completions() {
    std::size_t n = 0;
    Completion c;
    while (completions_.pop(c)) {
        if (c.read_done) {
            c.read_done(std::move(c.read_result));
        } else if (c.write_done) {
            c.write_done(c.write_result);
        }
        c = Completion{};
        ++n;
    }
    return n;
}

void HandoffTransport::complete(Completion c) {
    backlog_.push_back(std::move(c));
    while (!backlog_.empty() && completions_.push(backlog_.front())) {
        backlog_.pop_front();
    }
}

std::size_t HandoffTransport::pump_requests() {
    while (!backlog_.empty() && completions_.push(backlog_.front())) {
        backlog_.pop_front();
    }
    std::size_t n = 0;
    Request r;
    while (requests_.pop(r)) {
        if (r.is_write) {
            inner_.write(r.index, r.subindex, std::move(r.data),
                         [this, done = std::move(r.write_done)](drives::DriveVoid res) mutable {
                             Completion c;
                             c.write_done = std::move(done);
                             c.write_result = std::move(res);
                             complete(std::move(c));
                         });
        } else {
            inner_.read(r.index, r.subindex,
                        [this, done = std::move(r.read_done)](
                            drives::DriveResult<drives::Bytes> res) mutable {
                            Completion c;
                            c.read_done = std::move(done);
                            c.read_result = std::move(res);
                            complete(std::move(c));
                        });
        }
        r = Request{};
        ++n;
    }
    return n;
}

} // namespace codrive::controller
