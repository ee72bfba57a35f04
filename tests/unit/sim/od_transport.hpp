// SPDX-License-Identifier: Apache-2.0
// A DriveTransport on a simulator's own dictionary, for master-side APIs in the sim unit tests.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/drives/transport.hpp>
#include <codrive/testing/no_cyclic_transport.hpp>

#include <deque>
#include <functional>
#include <optional>

#include <gtest/gtest.h>

namespace codrive::sim::testing {

/// Object access on the simulator's dictionary, as an SDO server answers it: queued, answered
/// on process() (between simulation steps).
class OdTransport final : public codrive::testing::NoCyclicTransport {
public:
    explicit OdTransport(ObjectDictionary& od) : od_(od) {}
    [[nodiscard]] std::string name() const override { return "node 7"; }
    void read(std::uint16_t index, std::uint8_t sub, ReadDone done) override {
        queue_.emplace_back([this, index, sub, done = std::move(done)] {
            auto r = od_.read(index, sub);
            if (!r) {
                done(drives::drive_fail(drives::DriveErrc::Transport,
                                        "upload " + hex_index(index, sub) + " aborted"));
                return;
            }
            done(drives::Bytes(r->begin(), r->end()));
        });
    }
    void write(std::uint16_t index, std::uint8_t sub, drives::Bytes data, WriteDone done) override {
        queue_.emplace_back([this, index, sub, data = std::move(data), done = std::move(done)] {
            auto r = od_.write(index, sub, data);
            if (!r) {
                done(drives::drive_fail(drives::DriveErrc::Transport,
                                        "download " + hex_index(index, sub) + " aborted"));
                return;
            }
            done({});
        });
    }
    void process() {
        while (!queue_.empty()) {
            auto job = std::move(queue_.front());
            queue_.pop_front();
            job();
        }
    }

private:
    ObjectDictionary& od_;
    std::deque<std::function<void()>> queue_;
};

/// Starts `call(done)` and answers the queued accesses until `done` has run (a few rounds: one
/// call may chain reads); the result, or a default T with a test failure if it never came.
template <typename T, typename Call>
T await(OdTransport& t, Call call) {
    std::optional<T> out;
    call([&out](T r) { out = std::move(r); });
    for (int i = 0; i < 10 && !out; ++i) {
        t.process();
    }
    EXPECT_TRUE(out.has_value());
    return out.value_or(T{});
}

} // namespace codrive::sim::testing
