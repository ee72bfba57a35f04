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

const char* to_string(BootReset r) {
    switch (r) {
    case BootReset::PreOperational:
        return "pre-operational";
    case BootReset::Communication:
        return "communication";
    case BootReset::None:
        return "none";
    }
    return "?";
}

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
    wait_ = Wait::None;
    wait_deadline_ = kNever;
    start_sends_ = 0;
    pre_op_sends_ = 0;
    restarts_ = 0;
    reboot_seen_ = false;
    reported_.reset();
    enter_state();
}

void BootSequence::restart(std::string why) {
    ++restarts_;
    reboot_seen_ = false;
    wait_ = Wait::None;
    wait_deadline_ = kNever;
    start_sends_ = 0;
    pre_op_sends_ = 0;
    reported_.reset();
    step_ok("restart", std::move(why));
    // The boot-up message put the node into pre-operational (CiA 301 §7.3.2.2.2).
    probe(0);
}

void BootSequence::enter_state() {
    const TimePoint now = clock_.now();
    switch (config_.boot_reset) {
    case BootReset::None:
        break;
    case BootReset::PreOperational:
        // CiA 302-2 §4: the node may be operational or stopped from an earlier run (a stopped
        // node does not even answer SDO); pre-operational is the state in which the drives in
        // scope accept PDO mapping writes (abort 0x08000022 otherwise). Confirmed by heartbeat
        // after the identity check, before the first write (confirm_pre_operational()).
        if (!send_pre_operational(now)) {
            return;
        }
        step_ok("NMT enter pre-operational", "sent");
        break;
    case BootReset::Communication:
        // CiA 301 §7.3.2.2.2: reset communication restores 1000h..1FFFh to their stored values;
        // the node then sends its boot-up message and is pre-operational.
        if (auto r = nmt_.reset_communication(config_.id); !r) {
            step_failed("NMT reset communication",
                        fmt::format("node {}: cannot send NMT reset communication: {}", config_.id,
                                    r.error().message()));
            return;
        }
        wait_ = Wait::BootUp;
        wait_deadline_ = now + config_.boot_up_timeout;
        return; // on_node_state(BootUp) probes
    }
    probe(0);
}

void BootSequence::on_node_state(nmt::NmtState state, TimePoint now) {
    if (!running_) {
        return;
    }
    if (state == nmt::NmtState::BootUp) {
        if (wait_ == Wait::BootUp) {
            step_ok("NMT reset communication",
                    fmt::format("boot-up message after {:.1f} ms", to_ms(now - step_started_)));
            // Probe from the next tick: the SDO client sees this boot-up message right after
            // this call and would end a request sent now as "node rebooted".
            wait_ = Wait::Probe;
            wait_deadline_ = now;
            return;
        }
        // With an SDO request in flight, it fails with "node rebooted" right after this call and
        // the failing step restarts the sequence (step_failed()). While waiting for an NMT state
        // nothing is in flight: on_tick() restarts.
        reboot_seen_ = true;
        if (wait_ != Wait::None) {
            wait_deadline_ = now;
        }
        return;
    }
    reported_ = state;
    if (wait_ == Wait::PreOperational && state == nmt::NmtState::PreOperational) {
        wait_done();
        step_ok("pre-operational check",
                pre_op_sends_ == 1
                    ? std::string("pre-operational (confirmed by heartbeat)")
                    : fmt::format("pre-operational (confirmed by heartbeat after {} NMT enter "
                                  "pre-operational commands)",
                                  pre_op_sends_));
        write(0);
        return;
    }
    if (wait_ == Wait::Operational && state == nmt::NmtState::Operational) {
        wait_done();
        step_ok("NMT start",
                start_sends_ == 1
                    ? std::string("operational (confirmed by heartbeat)")
                    : fmt::format("operational (confirmed by heartbeat after {} NMT start "
                                  "commands)",
                                  start_sends_));
        complete();
    }
}

void BootSequence::wait_done() {
    wait_ = Wait::None;
    wait_deadline_ = kNever;
}

void BootSequence::on_tick(TimePoint now) {
    if (!running_ || wait_ == Wait::None || now < wait_deadline_) {
        return;
    }
    const Wait waited = wait_;
    if (waited == Wait::Probe) {
        wait_done();
        probe(0);
        return;
    }
    const char* step = waited == Wait::BootUp           ? "NMT reset communication"
                       : waited == Wait::PreOperational ? "pre-operational check"
                                                        : "NMT start";
    if (waited == Wait::BootUp) {
        wait_done();
        step_failed(step, fmt::format("node {}: no boot-up message within {} ms after NMT reset "
                                      "communication",
                                      config_.id, config_.boot_up_timeout.count()));
        return;
    }
    if (reboot_seen_) {
        wait_done();
        step_failed(
            step, fmt::format("node {}: rebooted while boot-up waited for {}, {} times", config_.id,
                              waited == Wait::Operational ? "operational" : "pre-operational",
                              restarts_ + 1));
        return;
    }
    const int sends = waited == Wait::Operational ? start_sends_ : pre_op_sends_;
    if (sends <= config_.start_retries) {
        // The command (or the heartbeat reporting the new state) was lost: repeat it. Both
        // commands are harmless to a node already in the target state (CiA 301 Figure 48).
        (void)(waited == Wait::Operational ? send_start(now) : send_pre_operational(now));
        return;
    }
    wait_done();
    step_failed(
        step,
        fmt::format("node {}: did not reach {} after {} NMT {} commands ({} ms apart): {}",
                    config_.id, waited == Wait::Operational ? "operational" : "pre-operational",
                    sends, waited == Wait::Operational ? "start" : "enter pre-operational",
                    wait_period_.count(),
                    reported_ ? fmt::format("its heartbeat reports {}", nmt::to_string(*reported_))
                              : std::string("no heartbeat received")));
}

bool BootSequence::send_pre_operational(TimePoint now) {
    ++pre_op_sends_;
    if (auto r = nmt_.enter_pre_operational(config_.id); !r) {
        wait_done();
        step_failed("NMT enter pre-operational",
                    fmt::format("node {}: cannot send NMT enter pre-operational: {}", config_.id,
                                r.error().message()));
        return false;
    }
    if (wait_ == Wait::PreOperational) {
        wait_deadline_ = now + wait_period_;
    }
    return true;
}

void BootSequence::confirm_pre_operational() {
    // The node's own heartbeat producer time (1017h) says whether and how soon a heartbeat will
    // confirm the state; it may be left over from an earlier run (CiA 301 §7.5.2.18).
    sdo::TransferOptions opts;
    opts.timeout = config_.sdo_timeout;
    sdo_.read<std::uint16_t>(
        kHeartbeatProducer, 0,
        [this, alive = alive_](sdo::SdoResult<std::uint16_t> r) {
            if (!*alive) {
                return;
            }
            const char* name = "pre-operational check";
            if (!r && r.error().origin != sdo::AbortOrigin::Server) {
                step_failed(name, r.error().to_string());
                return;
            }
            if (!r || *r == 0) {
                // NMT commands are unconfirmed without error control (CiA 301 §7.2.8.3.1); a
                // node that ignored the command refuses the mapping writes with a sentence.
                step_ok(name, r ? "not confirmed: the node produces no heartbeat (1017h = 0)"
                                : "not confirmed: heartbeat producer time 1017h not readable");
                write(0);
                return;
            }
            if (reported_ == nmt::NmtState::PreOperational) {
                step_ok(name, "pre-operational (confirmed by heartbeat)");
                write(0);
                return;
            }
            wait_ = Wait::PreOperational;
            // A heartbeat sent before the node processed the command may still report the old
            // state: allow two producer periods plus the consumer margin of CiA 301 §7.2.8.3.2.
            wait_period_ = milliseconds(*r * 5 / 2);
            wait_deadline_ = clock_.now() + wait_period_;
        },
        opts);
}

bool BootSequence::send_start(TimePoint now) {
    ++start_sends_;
    if (auto r = nmt_.start(config_.id); !r) {
        wait_done();
        step_failed("NMT start", fmt::format("node {}: cannot send NMT start: {}", config_.id,
                                             r.error().message()));
        return false;
    }
    wait_ = Wait::Operational;
    wait_period_ = config_.consumer_time();
    wait_deadline_ = now + wait_period_;
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
        if (config_.boot_reset == BootReset::PreOperational) {
            confirm_pre_operational();
        } else {
            write(0);
        }
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
    const bool guarding = config_.heartbeat_producer.count() == 0 &&
                          config_.guard_time.count() > 0 && config_.life_time_factor > 0;
    if (config_.heartbeat_producer.count() == 0 && !guarding) {
        finish(); // NodeConfig: error control left as the node has it
        return;
    }
    // With guarding, 1017h = 0 switches off a heartbeat an earlier run may have left: a node
    // with a producer time uses heartbeat, not guarding (CiA 301 §7.2.8.3.2). A node without
    // 1017h (guarding only) refuses the write; that is fine.
    const auto ms = static_cast<std::uint16_t>(config_.heartbeat_producer.count());
    sdo_.write<std::uint16_t>(
        kHeartbeatProducer, 0, ms,
        [this, alive = alive_, ms, guarding](sdo::SdoResult<void> r) {
            if (!*alive) {
                return;
            }
            const char* name = "heartbeat producer 1017h";
            if (!r && !(guarding && r.error().origin == sdo::AbortOrigin::Server)) {
                step_failed(name, r.error().to_string());
                return;
            }
            if (!guarding) {
                step_ok(name, fmt::format("{} ms", ms));
                finish();
                return;
            }
            step_ok(name, r ? "0 ms (off: node guarding is used)"
                            : "not written (" + r.error().to_string() + ")");
            guard();
        },
        opts);
}

void BootSequence::guard() {
    sdo::TransferOptions opts;
    opts.timeout = config_.sdo_timeout;
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
                    step_ok("life time factor 100Dh", fmt::format("{}", config_.life_time_factor));
                    finish();
                },
                o);
        },
        opts);
}

void BootSequence::finish() {
    if (start_node_) {
        if (!send_start(clock_.now())) {
            return;
        }
        if (config_.heartbeat_producer.count() > 0) {
            return; // on_node_state() completes when a heartbeat reports operational
        }
        wait_done();
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
