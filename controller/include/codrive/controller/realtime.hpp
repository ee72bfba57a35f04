// SPDX-License-Identifier: Apache-2.0
// Real-time settings for the thread that runs the cyclic path: SCHED_FIFO, CPU affinity,
// mlockall. Each one that cannot be applied gives a warning sentence, never a silent no-op.
#pragma once

#include <codrive/core/time.hpp>

#include <string>
#include <vector>

namespace codrive::controller {

struct RealtimeOptions {
    bool fifo = false;        ///< SCHED_FIFO
    int priority = 80;        ///< 1..99
    int cpu = -1;             ///< pin to this CPU; -1 = no affinity
    bool lock_memory = false; ///< mlockall(MCL_CURRENT | MCL_FUTURE)
};

/// Applies the options to the calling thread. Returns one warning per setting that could not
/// be applied, e.g. "cannot use SCHED_FIFO priority 80: not permitted (run as root, grant
/// CAP_SYS_NICE, or raise rtprio in /etc/security/limits.conf); running with normal scheduling".
std::vector<std::string> apply_realtime(const RealtimeOptions& options);

/// Sleeps until `t` on CLOCK_MONOTONIC (clock_nanosleep with TIMER_ABSTIME; a signal does not
/// cut it short): how the dedicated cyclic thread waits for its next slot, and what
/// measure_timer_latency() measures. No allocation, no lock.
void sleep_until(TimePoint t);

/// The calling thread's scheduling policy, priority and CPU affinity, saved before
/// apply_realtime() changes them on a thread the controller does not own (Threading::Single runs
/// on the caller's thread), and restored when the controller stops: a library must not leave
/// its caller's thread at SCHED_FIFO, where it would starve every other task on the CPU.
class SavedThreadSchedule {
public:
    /// Saves the calling thread's settings.
    SavedThreadSchedule();
    /// Restores them on the calling thread (call it on the thread that saved them).
    void restore() const;

private:
    int policy_ = 0;
    int priority_ = 0;
    bool have_policy_ = false;
    std::vector<unsigned char> cpus_; ///< cpu_set_t bytes; empty: affinity not saved
};

} // namespace codrive::controller
