// SPDX-License-Identifier: Apache-2.0
// Why the process data did not work over a stretch of cyclic operation, in words.
#pragma once

#include <codrive/ethercat/master.hpp>

#include <codrive/core/time.hpp>

#include <string>

namespace codrive::ethercat {

/// What became of the cyclic frames between `at_op` and `now` (the master's counts then and
/// now) at cycle `cycle`, as a clause to append to the sentence that says what failed (no
/// statusword, an enable that timed out): ": none of the 2993 cyclic frames since OP brought
/// the inputs in (2991 came back after their 1000 µs cycle, 2 did not come back); the frames
/// take longer than the 1000 µs cycle to come back (...): a longer cycle gives them time".
/// Empty when at least half of the frames brought the inputs in, or none was sent.
std::string cyclic_shortfall(const ProcessDataStats& at_op, const ProcessDataStats& now,
                             Duration cycle);

} // namespace codrive::ethercat
