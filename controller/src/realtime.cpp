// SPDX-License-Identifier: Apache-2.0
// SCHED_FIFO, affinity and memory locking for the cyclic thread, with warnings that say why.
#include <codrive/controller/realtime.hpp>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <fmt/format.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

namespace codrive::controller {

std::vector<std::string> apply_realtime(const RealtimeOptions& options) {
    std::vector<std::string> warnings;
    if (options.lock_memory && ::mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
        warnings.push_back(fmt::format(
            "cannot lock memory (mlockall): {} (run as root, grant CAP_IPC_LOCK or raise memlock "
            "in /etc/security/limits.conf); page faults may delay cycles",
            std::strerror(errno)));
    }
    if (options.cpu >= 0) {
        const long cpus = ::sysconf(_SC_NPROCESSORS_ONLN);
        if (options.cpu >= cpus) {
            warnings.push_back(fmt::format("cannot pin to CPU {}: this machine has {} CPUs; "
                                           "running unpinned",
                                           options.cpu, cpus));
        } else {
            cpu_set_t set;
            CPU_ZERO(&set);
            CPU_SET(static_cast<unsigned>(options.cpu), &set);
            const int rc = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
            if (rc != 0) {
                warnings.push_back(fmt::format("cannot pin to CPU {}: {}; running unpinned",
                                               options.cpu, std::strerror(rc)));
            }
        }
    }
    if (options.fifo) {
        sched_param sp{};
        sp.sched_priority = options.priority;
        const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
        if (rc == EPERM) {
            warnings.push_back(fmt::format(
                "cannot use SCHED_FIFO priority {}: not permitted (run as root, grant "
                "CAP_SYS_NICE, or raise rtprio in /etc/security/limits.conf); running with normal "
                "scheduling",
                options.priority));
        } else if (rc != 0) {
            warnings.push_back(fmt::format("cannot use SCHED_FIFO priority {}: {}; running with "
                                           "normal scheduling",
                                           options.priority, std::strerror(rc)));
        }
    }
    return warnings;
}

void sleep_until(TimePoint t) {
    const auto ns = t.time_since_epoch().count();
    const timespec ts{static_cast<time_t>(ns / 1'000'000'000),
                      static_cast<long>(ns % 1'000'000'000)};
    while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

SavedThreadSchedule::SavedThreadSchedule() {
    sched_param sp{};
    if (pthread_getschedparam(pthread_self(), &policy_, &sp) == 0) {
        priority_ = sp.sched_priority;
        have_policy_ = true;
    }
    cpu_set_t set;
    CPU_ZERO(&set);
    if (pthread_getaffinity_np(pthread_self(), sizeof(set), &set) == 0) {
        cpus_.resize(sizeof(set));
        std::memcpy(cpus_.data(), &set, sizeof(set));
    }
}

void SavedThreadSchedule::restore() const {
    if (have_policy_) {
        sched_param sp{};
        sp.sched_priority = priority_;
        (void)pthread_setschedparam(pthread_self(), policy_, &sp);
    }
    if (cpus_.size() == sizeof(cpu_set_t)) {
        cpu_set_t set;
        std::memcpy(&set, cpus_.data(), sizeof(set));
        (void)pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    }
}

} // namespace codrive::controller
