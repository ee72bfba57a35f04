// SPDX-License-Identifier: Apache-2.0
// Streaming a coordinated trajectory as cyclic synchronous position set-points.
#include <codrive/drives/coordinated.hpp>

#include <cmath>
#include <fmt/format.h>

namespace codrive::drives {

CoordinatedMotion::CoordinatedMotion(std::vector<Axis*> axes, Duration period)
    : axes_(std::move(axes)), period_s_(std::chrono::duration<double>(period).count()) {}

DriveVoid CoordinatedMotion::start(const Eigen::VectorXd& end, const Eigen::VectorXd& vmax,
                                   const Eigen::VectorXd& amax, const Eigen::VectorXd& jmax,
                                   ProfileShape shape, Done done) {
    const auto n = static_cast<Eigen::Index>(axes_.size());
    if (end.size() != n || vmax.size() != n || amax.size() != n ||
        (shape == ProfileShape::JerkLimited && jmax.size() != n)) {
        return drive_fail(DriveErrc::InvalidArgument,
                          fmt::format("coordinated move: {} axes but vectors of sizes {}/{}/{}/{}",
                                      n, end.size(), vmax.size(), amax.size(), jmax.size()));
    }
    Eigen::VectorXd from(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        Axis& a = *axes_[static_cast<std::size_t>(i)];
        if (a.state() != cia402::State::OperationEnabled) {
            return drive_fail(DriveErrc::WrongState,
                              fmt::format("{}: coordinated move needs OPERATION ENABLED, the axis "
                                          "is in {}",
                                          a.name(), cia402::to_string(a.state())));
        }
        if (a.mode_display() &&
            *a.mode_display() != static_cast<std::int8_t>(cia402::Mode::CyclicSyncPosition)) {
            return drive_fail(DriveErrc::WrongMode,
                              fmt::format("{}: coordinated move needs mode {}, 6061h reports {}",
                                          a.name(), cia402::mode_name(8),
                                          cia402::mode_name(*a.mode_display())));
        }
        auto p = a.target_position() ? a.target_position() : a.position_actual();
        if (!p) {
            return drive_fail(DriveErrc::NotMapped,
                              fmt::format("{}: coordinated move: no position known (map 6064h "
                                          "into a TPDO)",
                                          a.name()));
        }
        from[i] = *p;
    }
    if (active_ && done_) {
        auto old = std::move(done_);
        old(drive_fail(DriveErrc::Cancelled, "coordinated move replaced by a new one"));
    }
    traj_ = LinearTrajectory(from, end, vmax, amax, jmax, shape);
    k_ = 0;
    t_base_ = 0;
    last_ = from;
    done_ = std::move(done);
    stop_done_ = nullptr;
    active_ = true;
    return {};
}

void CoordinatedMotion::on_sync() {
    if (!active_) {
        return;
    }
    for (Axis* a : axes_) {
        if (a->state() != cia402::State::OperationEnabled) {
            complete(drive_fail(DriveErrc::WrongState,
                                fmt::format("{}: coordinated move aborted: the axis is in {}",
                                            a->name(), cia402::to_string(a->state()))));
            return;
        }
    }
    ++k_;
    const double t = static_cast<double>(k_) * period_s_;
    last_ = traj_.position(t);
    // Every axis gets the sample of the same instant; the targets go out in the RPDOs before
    // the SYNC that makes all drives take them.
    for (std::size_t i = 0; i < axes_.size(); ++i) {
        axes_[i]->set_target_position(
            static_cast<std::int32_t>(std::llround(last_[static_cast<Eigen::Index>(i)])));
    }
    if (t >= traj_.duration()) {
        complete({});
    }
}

void CoordinatedMotion::stop(Done done) {
    if (!active_) {
        if (done) {
            done({});
        }
        return;
    }
    const double t = static_cast<double>(k_) * period_s_;
    traj_ = traj_.stopped_at(t);
    k_ = 0;
    if (done_) {
        auto old = std::move(done_);
        old(drive_fail(DriveErrc::Cancelled, "coordinated move stopped"));
    }
    done_ = std::move(done);
}

void CoordinatedMotion::complete(DriveVoid result) {
    active_ = false;
    if (done_) {
        auto d = std::move(done_);
        done_ = nullptr;
        d(std::move(result));
    }
}

} // namespace codrive::drives
