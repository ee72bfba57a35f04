// SPDX-License-Identifier: Apache-2.0
// What became of the cyclic frames when a drive's inputs did not come in, from the master's
// counts (ProcessDataStats), as a clause for the sentence that says what failed.
#include <codrive/ethercat/cyclic_shortfall.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string_view>
#include <vector>

namespace codrive::ethercat {

std::string cyclic_shortfall(const ProcessDataStats& at_op, const ProcessDataStats& now,
                             Duration cycle) {
    const auto cycle_us = std::chrono::duration_cast<microseconds>(cycle).count();
    // Each cyclic frame came back in time (cycles: with the expected working counter, bringing
    // the inputs in, or not), or its wait ended without it (lost_frames; late_frames of them
    // were read by a later wait), or on a receive error, or it could not be sent.
    const std::uint64_t inputs = now.input_frames - at_op.input_frames;
    const std::uint64_t wkc = now.wkc_errors - at_op.wkc_errors;
    const std::uint64_t lost = now.lost_frames - at_op.lost_frames;
    // A frame lost before `at_op` may be read late after it: not one of these frames.
    const std::uint64_t late = std::min(lost, now.late_frames - at_op.late_frames);
    const std::uint64_t failed = now.receive_errors - at_op.receive_errors;
    const std::uint64_t unsent = now.send_errors - at_op.send_errors;
    const std::uint64_t frames = (now.cycles - at_op.cycles) + lost + failed + unsent;
    if (frames == 0 || inputs * 2 >= frames) {
        return {}; // most frames brought the inputs in: the cause is elsewhere
    }
    std::vector<std::string> fates;
    const auto fate = [&fates](std::uint64_t n, std::string_view what) {
        if (n != 0) {
            fates.push_back(fmt::format("{} {}", n, what));
        }
    };
    fate(late, fmt::format("came back after their {} µs cycle", cycle_us));
    fate(lost - late, "did not come back");
    fate(wkc, "came back with a working counter other than expected");
    fate(failed, "were given up on a receive error");
    fate(unsent, "could not be sent");
    std::string out = inputs == 0
                          ? fmt::format(": none of the {} cyclic frames", frames)
                          : fmt::format(": only {} of the {} cyclic frames", inputs, frames);
    out += fmt::format(" since OP brought the inputs in ({})", fmt::join(fates, ", "));
    if (late != 0) {
        out += fmt::format("; the frames take longer than the {} µs cycle to come back (a "
                           "loaded host or a long segment): a longer cycle gives them time",
                           cycle_us);
    }
    return out;
}

} // namespace codrive::ethercat
