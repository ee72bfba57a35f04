// SPDX-License-Identifier: Apache-2.0
// What the master needs to know to boot one node: expected identity, object writes, error
// control settings and extra asynchronous configuration steps.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/time.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace codrive::sdo {
class SdoClient;
}

namespace codrive::master {

/// Values 1000h and 1018h must have; unset fields are not checked (CiA 302-2 §4.3 allows 0 =
/// "do not check" for each).
struct ExpectedIdentity {
    std::optional<std::uint32_t> device_type;  ///< 1000h
    std::optional<std::uint32_t> vendor_id;    ///< 1018h:01
    std::optional<std::uint32_t> product_code; ///< 1018h:02
    std::optional<std::uint32_t> revision;     ///< 1018h:03
    std::optional<std::uint32_t> serial;       ///< 1018h:04
};

/// One object written during boot-up.
struct ObjectWrite {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::vector<std::uint8_t> data;
    std::string what; ///< shown in the boot report, e.g. "modes of operation = CSP"

    template <typename T>
    static ObjectWrite of(std::uint16_t index, std::uint8_t subindex, T value,
                          std::string what = {}) {
        ObjectWrite w;
        w.index = index;
        w.subindex = subindex;
        w.data.resize(sizeof(T));
        for (std::size_t i = 0; i < sizeof(T); ++i) {
            w.data[i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i));
        }
        w.what = std::move(what);
        return w;
    }
};

/// An extra asynchronous step (e.g. PDO configuration). It calls `done` with nothing on success
/// or with a sentence explaining the failure.
using StepDone = std::function<void(std::optional<std::string> error)>;
using ConfigureStep = std::function<void(sdo::SdoClient& sdo, StepDone done)>;

struct NamedStep {
    std::string name;
    ConfigureStep run;
};

/// How boot-up brings a node into a state in which it accepts configuration writes before the
/// first one (CiA 302-2 §4 boot slave; CiA 301 §7.5.2.36: drives accept PDO mapping changes only
/// in NMT pre-operational). Bus-file key `boot_reset` (docs/bus-file.md).
enum class BootReset {
    /// NMT enter pre-operational before the device type probe, confirmed by the node's heartbeat
    /// (if it produces one) before the first write. A node already pre-operational is fine.
    PreOperational,
    /// NMT reset communication, then wait for the boot-up message (the node is pre-operational
    /// with its communication objects at their stored values: CiA 301 §7.3.2.2.2).
    Communication,
    /// Leave the NMT state alone (the node must already be pre-operational).
    None,
};

/// "pre-operational", "communication", "none".
[[nodiscard]] const char* to_string(BootReset r);

/// The boot-up configuration of one remote node.
struct NodeConfig {
    NodeId id = 0;
    std::string name;
    ExpectedIdentity identity;
    std::vector<ObjectWrite> writes; ///< in order, after the identity check
    std::vector<NamedStep> steps;    ///< after the writes
    /// Heartbeat producer time written to the node's 1017h (0 = leave it alone).
    milliseconds heartbeat_producer{0};
    /// Master-side consumer time; 0 = 1.5 × heartbeat_producer (if that is set).
    milliseconds heartbeat_consumer{0};
    /// Node guarding (used only when heartbeat_producer is 0): 100Ch and 100Dh.
    milliseconds guard_time{0};
    std::uint8_t life_time_factor = 0;
    /// The NMT state step before any configuration write.
    BootReset boot_reset = BootReset::PreOperational;
    /// With BootReset::Communication: how long to wait for the boot-up message.
    milliseconds boot_up_timeout{2000};
    /// Send NMT start at the end of boot-up (otherwise the node stays pre-operational).
    bool start = true;
    /// Timeout of each SDO request during boot-up.
    milliseconds sdo_timeout{500};
    /// Repeats of the device type probe before the node is declared missing.
    int probe_retries = 2;
    /// NMT start is unconfirmed (CiA 301 §7.2.8.3.1). With a heartbeat configured, boot-up waits
    /// for a heartbeat reporting operational and repeats NMT start this many times if none comes
    /// within the consumer time, then fails with a sentence. NMT enter pre-operational is repeated
    /// the same way while the node's heartbeat does not report pre-operational.
    int start_retries = 3;
    /// A boot-up message (the node reset) during boot-up restarts the sequence from the device
    /// type probe, at most this many times.
    int reboot_restarts = 3;

    /// The consumer time the master uses for this node.
    [[nodiscard]] milliseconds consumer_time() const {
        if (heartbeat_consumer.count() > 0) {
            return heartbeat_consumer;
        }
        return milliseconds(heartbeat_producer.count() * 3 / 2);
    }
};

} // namespace codrive::master
