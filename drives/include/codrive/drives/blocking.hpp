// SPDX-License-Identifier: Apache-2.0
// Blocking helper for tools: runs an event loop until an asynchronous drive operation ends.
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/drives/axis.hpp>

#include <functional>
#include <memory>
#include <optional>

namespace codrive::drives {

/// Starts an operation and runs `loop` until its callback ran or `limit` passed (the operation's
/// own timeout normally ends it first). Not for the cyclic thread. Errors: the operation's, or
/// Timeout if the loop never completed it.
///   auto r = run_blocking(loop, [&](Axis::Done d) { axis.enable(std::move(d)); });
inline DriveVoid run_blocking(EventLoop& loop, const std::function<void(Axis::Done)>& start,
                              Duration limit = seconds(30)) {
    // Shared: a callback that fires after we gave up must not write to a dead stack frame.
    auto result = std::make_shared<std::optional<DriveVoid>>();
    start([result](DriveVoid r) { *result = std::move(r); });
    if (!result->has_value()) {
        loop.run_until([&result] { return result->has_value(); }, limit);
    }
    if (!result->has_value()) {
        return drive_fail(DriveErrc::Timeout, "operation did not complete within the tool's limit");
    }
    return std::move(**result);
}

} // namespace codrive::drives
