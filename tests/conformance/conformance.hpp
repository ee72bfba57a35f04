// SPDX-License-Identifier: Apache-2.0
// Conformance facts (object, sub, type, access, default, manual section) checked against a
// simulated drive through the real protocol and against the master's drive profile.
#pragma once

#include "../unit/sim/device_test_support.hpp"

#include <codrive/core/data_type.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace codrive::conformance {

/// How a fact says the object is accessed: read only (ro/const), read-write, or not there.
enum class Acc { Ro, Rw, Absent };

/// One fact from a manual's object table.
struct Fact {
    std::uint16_t index = 0;
    std::uint8_t sub = 0;
    DataType type = DataType::Unsigned8;
    Acc access = Acc::Ro;
    std::optional<std::int64_t> value; ///< the manual's default, if it gives one
    const char* section = "";          ///< manual section, e.g. "DS-BVS §6.2.104"
    /// The master's profile describes the object (CiA 402 objects: checked there too).
    bool in_profile = true;
};

/// The answer of an SDO transfer, whatever the transport: data, or the abort code.
struct Reply {
    bool ok = false;
    std::vector<std::uint8_t> data;
    std::uint32_t abort = 0;
};

/// A simulated drive reached through a protocol.
class Probe {
public:
    virtual ~Probe() = default;
    virtual Reply upload(std::uint16_t index, std::uint8_t sub) = 0;
    virtual Reply download(std::uint16_t index, std::uint8_t sub,
                           std::vector<std::uint8_t> data) = 0;
    template <typename T>
    Reply write(std::uint16_t index, std::uint8_t sub, T value) {
        std::vector<std::uint8_t> b(sizeof(T));
        put_le<T>(b.data(), value);
        return download(index, sub, std::move(b));
    }
};

/// The CAN simulator (SimDevice) on the in-process virtual bus, read by a real SDO client.
class CanProbe final : public Probe {
public:
    explicit CanProbe(const char* profile, NodeId node = 1) : fixture_(profile, node) {
        fixture_.start();
    }
    Reply upload(std::uint16_t index, std::uint8_t sub) override;
    Reply download(std::uint16_t index, std::uint8_t sub, std::vector<std::uint8_t> data) override;
    sim::testing::DeviceFixture& fixture() { return fixture_; }

private:
    sim::testing::DeviceFixture fixture_;
};

/// The EtherCAT simulator on the in-process segment, read by the master's CoE SDO client in
/// PRE-OP (mailbox up).
class EcatProbe final : public Probe {
public:
    explicit EcatProbe(std::string_view profile);
    Reply upload(std::uint16_t index, std::uint8_t sub) override;
    Reply download(std::uint16_t index, std::uint8_t sub, std::vector<std::uint8_t> data) override;
    ethercat::Master& master() { return master_; }
    sim::ecat::EcatSegment& segment() { return segment_; }
    FakeClock& clock() { return clock_; }

private:
    FakeClock clock_;
    sim::ecat::EcatSegment segment_;
    sim::ecat::SegmentLink link_{segment_, clock_};
    ethercat::Master master_{link_, clock_};
};

/// Checks every fact against the simulator (through `probe`) and the master's profile; reports
/// each failure as a test failure naming the fact and its section, and tallies them for the
/// summary line `conformance: N facts checked per drive, M failed`.
void check_facts(std::string_view drive, const drives::Profile& profile, Probe& probe,
                 std::span<const Fact> facts);

} // namespace codrive::conformance
