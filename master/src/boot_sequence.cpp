// SPDX-License-Identifier: Apache-2.0
// Boot-up steps of one node (CiA 302-2 §4: check device type and identity, configure, start).
#include <codrive/master/boot_sequence.hpp>

#include <codrive/core/value.hpp>
#include <codrive/nmt/master.hpp>
#include <codrive/sdo/client.hpp>

#include <fmt/format.h>

namespace codrive::master {
namespace {

constexpr std::uint16_t kDeviceType = 0x1000;
constexpr std::uint16_t kIdentity = 0x1018;
constexpr std::uint16_t kGuardTime = 0x100C;
constexpr std::uint16_t kLifeTimeFactor = 0x100D;
constexpr std::uint16_t kHeartbeatProducer = 0x1017;

constexpr const char* kIdentityNames[] = {"", "vendor-ID", "product code", "revision number",
                                          "serial number"};

std::optional<std::uint32_t> expected_sub(const ExpectedIdentity& id, std::size_t sub) {
    switch (sub) {
    case 1:
        return id.vendor_id;
    case 2:
        return id.product_code;
    case 3:
        return id.revision;
    case 4:
        return id.serial;
    default:
        return std::nullopt;
    }
}

} // namespace

BootSequence::BootSequence(const NodeConfig& config, sdo::SdoClient& sdo, nmt::NmtMaster& nmt,
                           const IClock& clock)
    : config_(config), sdo_(sdo), nmt_(nmt), clock_(clock), alive_(std::make_shared<bool>(true)) {}

BootSequence::~BootSequence() {
    *alive_ = false;
}

void BootSequence::run(Done done, bool start_node, bool recovery) {
    done_ = std::move(done);
    start_node_ = start_node;
    report_ = BootReport{};
    report_.node = config_.id;
    report_.name = config_.name;
    report_.recovery = recovery;
    report_.started = clock_.now();
    running_ = true;
    step_started_ = clock_.now();
    start_deadline_ = kNever;
    start_sends_ = 0;
    restarts_ = 0;
    reboot_seen_ = false;
    reported_.reset();
    probe(0);
}

void BootSequence::restart(std::string why) {
    ++restarts_;
    reboot_seen_ = false;
    start_deadline_ = kNever;
    start_sends_ = 0;
    reported_.reset();
    step_ok("restart", std::move(why));
    probe(0);
}

void BootSequence::on_node_state(nmt::NmtState state, TimePoint now) {
    if (!running_) {
        return;
    }
    if (state == nmt::NmtState::BootUp) {
        // With an SDO request in flight, it fails with "node rebooted" right after this call and
        // the failing step restarts the sequence (step_failed()). While waiting for operational
        // nothing is in flight: on_tick() restarts.
        reboot_seen_ = true;
        if (start_deadline_ != kNever) {
            start_deadline_ = now;
        }
        return;
    }
    reported_ = state;
    if (start_deadline_ != kNever && state == nmt::NmtState::Operational) {
        start_deadline_ = kNever;
        step_ok("NMT start",
                start_sends_ == 1
                    ? std::string("operational (confirmed by heartbeat)")
                    : fmt::format("operational (confirmed by heartbeat after {} NMT start "
                                  "commands)",
                                  start_sends_));
        complete();
    }
}

void BootSequence::on_tick(TimePoint now) {
    if (!running_ || start_deadline_ == kNever || now < start_deadline_) {
        return;
    }
    if (reboot_seen_) {
        start_deadline_ = kNever;
        step_failed("NMT start", fmt::format("node {}: rebooted while boot-up waited for "
                                             "operational, {} times",
                                             config_.id, restarts_ + 1));
        return;
    }
    if (start_sends_ <= config_.start_retries) {
        // The start command (or the heartbeat reporting the new state) was lost: repeat it.
        // NMT start to an operational node changes nothing (CiA 301 Figure 48).
        (void)send_start(now);
        return;
    }
    start_deadline_ = kNever;
    step_failed(
        "NMT start",
        fmt::format("node {}: did not reach operational after {} NMT start commands "
                    "({} ms apart): {}",
                    config_.id, start_sends_, config_.consumer_time().count(),
                    reported_ ? fmt::format("its heartbeat reports {}", nmt::to_string(*reported_))
                              : std::string("no heartbeat received")));
}

bool BootSequence::send_start(TimePoint now) {
    ++start_sends_;
    if (auto r = nmt_.start(config_.id); !r) {
        start_deadline_ = kNever;
        step_failed("NMT start", fmt::format("node {}: cannot send NMT start: {}", config_.id,
                                             r.error().message()));
        return false;
    }
    start_deadline_ = now + config_.consumer_time();
    return true;
}

void BootSequence::step_ok(std::string name, std::string detail) {
    const TimePoint now = clock_.now();
    report_.steps.push_back(
        BootStep{std::move(name), true, std::move(detail), now - step_started_});
    step_started_ = now;
}

void BootSequence::step_failed(std::string name, std::string detail) {
    if (reboot_seen_ && restarts_ < config_.reboot_restarts) {
        // CiA 301 §7.3.2.1: the node reset and lost what boot-up had configured so far.
        restart(fmt::format("node {} rebooted (boot-up message) during step \"{}\"; boot-up "
                            "restarted",
                            config_.id, name));
        return;
    }
    const TimePoint now = clock_.now();
    report_.steps.push_back(
        BootStep{std::move(name), false, std::move(detail), now - step_started_});
    report_.ok = false;
    report_.duration = now - report_.started;
    running_ = false;
    if (done_) {
        auto done = std::move(done_);
        done(report_);
    }
}

void BootSequence::probe(int attempt) {
    sdo::TransferOptions opts;
    opts.timeout = config_.sdo_timeout;
    sdo_.read<std::uint32_t>(
        kDeviceType, 0,
        [this, alive = alive_, attempt](sdo::SdoResult<std::uint32_t> r) {
            if (!*alive) {
                return;
            }
            if (!r) {
                const bool timed_out = r.error().cause == sdo::SdoErrc::Timeout ||
                                       r.error().cause == sdo::SdoErrc::NodeRebooted;
                if (timed_out && attempt < config_.probe_retries) {
                    probe(attempt + 1);
                    return;
                }
                step_failed("device type 1000h",
                            timed_out ? fmt::format("node {}: does not answer: {} ({} attempts)",
                                                    config_.id, r.error().to_string(), attempt + 1)
                                      : r.error().to_string());
                return;
            }
            if (config_.identity.device_type && *config_.identity.device_type != *r) {
                step_failed("device type 1000h",
                            fmt::format("node {}: wrong device: device type 1000h expected "
                                        "0x{:08X}, actual 0x{:08X}",
                                        config_.id, *config_.identity.device_type, *r));
                return;
            }
            step_ok("device type 1000h", fmt::format("0x{:08X}", *r));
            check_identity(1);
        },
        opts);
}

void BootSequence::check_identity(std::size_t sub) {
    // Read every identity entry that is checked; vendor-ID (mandatory in CiA 301) always.
    while (sub <= 4 && sub != 1 && !expected_sub(config_.identity, sub)) {
        ++sub;
    }
    if (sub > 4) {
        write(0);
        return;
    }
    sdo::TransferOptions opts;
    opts.timeout = config_.sdo_timeout;
    sdo_.read<std::uint32_t>(
        kIdentity, static_cast<std::uint8_t>(sub),
        [this, alive = alive_, sub](sdo::SdoResult<std::uint32_t> r) {
            if (!*alive) {
                return;
            }
            const std::string name =
                fmt::format("identity 1018h:{:02X} {}", sub, kIdentityNames[sub]);
            if (!r) {
                step_failed(name, r.error().to_string());
                return;
            }
            const auto expected = expected_sub(config_.identity, sub);
            if (expected && *expected != *r) {
                step_failed(name, fmt::format("node {}: identity mismatch: {} (1018h:{:02X}) "
                                              "expected 0x{:08X}, actual 0x{:08X}",
                                              config_.id, kIdentityNames[sub], sub, *expected, *r));
                return;
            }
            step_ok(name, fmt::format("0x{:08X}", *r));
            check_identity(sub + 1);
        },
        opts);
}

void BootSequence::write(std::size_t i) {
    if (i >= config_.writes.size()) {
        extra(0);
        return;
    }
    const ObjectWrite& w = config_.writes[i];
    sdo::TransferOptions opts;
    opts.timeout = config_.sdo_timeout;
    sdo_.download(
        w.index, w.subindex, w.data,
        [this, alive = alive_, i](sdo::SdoResult<void> r) {
            if (!*alive) {
                return;
            }
            const ObjectWrite& wr = config_.writes[i];
            const std::string name = fmt::format("write 0x{:04X}:{:02X}", wr.index, wr.subindex);
            if (!r) {
                step_failed(name, r.error().to_string());
                return;
            }
            step_ok(name, wr.what.empty() ? hex_bytes(wr.data) : wr.what);
            write(i + 1);
        },
        opts);
}

void BootSequence::extra(std::size_t i) {
    if (i >= config_.steps.size()) {
        error_control();
        return;
    }
    config_.steps[i].run(sdo_, [this, alive = alive_, i](std::optional<std::string> error) {
        if (!*alive) {
            return;
        }
        if (error) {
            step_failed(config_.steps[i].name, *error);
            return;
        }
        step_ok(config_.steps[i].name, "done");
        extra(i + 1);
    });
}

void BootSequence::error_control() {
    sdo::TransferOptions opts;
    opts.timeout = config_.sdo_timeout;
    if (config_.heartbeat_producer.count() > 0) {
        const auto ms = static_cast<std::uint16_t>(config_.heartbeat_producer.count());
        sdo_.write<std::uint16_t>(
            kHeartbeatProducer, 0, ms,
            [this, alive = alive_, ms](sdo::SdoResult<void> r) {
                if (!*alive) {
                    return;
                }
                if (!r) {
                    step_failed("heartbeat producer 1017h", r.error().to_string());
                    return;
                }
                step_ok("heartbeat producer 1017h", fmt::format("{} ms", ms));
                finish();
            },
            opts);
        return;
    }
    if (config_.guard_time.count() > 0 && config_.life_time_factor > 0) {
        const auto gt = static_cast<std::uint16_t>(config_.guard_time.count());
        sdo_.write<std::uint16_t>(
            kGuardTime, 0, gt,
            [this, alive = alive_, gt](sdo::SdoResult<void> r) {
                if (!*alive) {
                    return;
                }
                if (!r) {
                    step_failed("guard time 100Ch", r.error().to_string());
                    return;
                }
                step_ok("guard time 100Ch", fmt::format("{} ms", gt));
                sdo::TransferOptions o;
                o.timeout = config_.sdo_timeout;
                sdo_.write<std::uint8_t>(
                    kLifeTimeFactor, 0, config_.life_time_factor,
                    [this, alive2 = alive_](sdo::SdoResult<void> r2) {
                        if (!*alive2) {
                            return;
                        }
                        if (!r2) {
                            step_failed("life time factor 100Dh", r2.error().to_string());
                            return;
                        }
                        step_ok("life time factor 100Dh",
                                fmt::format("{}", config_.life_time_factor));
                        finish();
                    },
                    o);
            },
            opts);
        return;
    }
    finish();
}

void BootSequence::finish() {
    if (start_node_) {
        if (!send_start(clock_.now())) {
            return;
        }
        if (config_.heartbeat_producer.count() > 0) {
            return; // on_node_state() completes when a heartbeat reports operational
        }
        start_deadline_ = kNever;
        // Without a heartbeat nothing reports the state during boot-up; node guarding, when
        // configured, reports it once the master guards the node.
        step_ok("NMT start", "sent (not confirmed: no heartbeat configured)");
    }
    complete();
}

void BootSequence::complete() {
    report_.ok = true;
    report_.duration = clock_.now() - report_.started;
    running_ = false;
    if (done_) {
        auto done = std::move(done_);
        done(report_);
    }
}

} // namespace codrive::master
