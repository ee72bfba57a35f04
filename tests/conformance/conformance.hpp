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

/// The buses on which the manual says the object exists (DS-BVS "Fieldbus Type", AKD2G "CAN
/// bus only" / "EtherCAT only" notes; the FIO is EtherCAT only).
enum class Bus { Both, Can, Ecat };

/// One fact from a manual's object table: object, sub-index, data type, access, the default the
/// manual gives, the range it gives, and where it says so (section and line of the text in
/// ../shared/seeds/).
struct Fact {
    constexpr Fact(std::uint16_t index_, std::uint8_t sub_, DataType type_, Acc access_,
                   std::optional<std::int64_t> value_, const char* section_, unsigned line_,
                   std::optional<std::int64_t> low_ = {}, std::optional<std::int64_t> high_ = {},
                   Bus bus_ = Bus::Both)
        : index(index_), sub(sub_), type(type_), access(access_), value(value_), section(section_),
          line(line_), low(low_), high(high_), bus(bus_) {}
    std::uint16_t index = 0;
    std::uint8_t sub = 0;
    DataType type = DataType::Unsigned8;
    Acc access = Acc::Ro;
    std::optional<std::int64_t> value; ///< the manual's default, if it gives one
    const char* section = "";          ///< manual section, e.g. "§6.2.104"
    unsigned line = 0;                 ///< line of the object's table in the manual text
    std::optional<std::int64_t> low;   ///< the manual's lowest value, where it narrows the type
    std::optional<std::int64_t> high;  ///< the manual's highest value, where it narrows the type
    Bus bus = Bus::Both;
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

/// A fact the simulator or profile is known to get wrong, with the reason (listed in
/// docs/conformance.md). It is still checked and counted as failed in the summary; the test
/// fails if it is no longer wrong, so the list stays true.
struct KnownDivergence {
    std::uint16_t index = 0;
    std::uint8_t sub = 0;
    const char* reason = "";
};

/// The fact tables, one per drive (akd2g_facts.cpp, ds_bvs_facts.cpp, fio_facts.cpp).
std::span<const Fact> akd2g_facts();
std::span<const Fact> ds_bvs_facts();
std::span<const Fact> fio_facts();
std::span<const KnownDivergence> akd2g_known();
std::span<const KnownDivergence> ds_bvs_known();
std::span<const KnownDivergence> fio_known();

/// Checks every fact against the simulator through the protocol of each bus the fact names
/// (`can`: SDO over the virtual CAN bus, `ecat`: CoE over the in-process EtherCAT segment; a
/// null probe skips that bus) and against the master's profile; reports each failure as a test
/// failure naming the fact, its section and manual line, and tallies them for the summary line
/// `conformance: N facts checked per drive, M failed`.
void check_facts(std::string_view drive, const drives::Profile& profile, Probe* can, Probe* ecat,
                 std::span<const Fact> facts, std::span<const KnownDivergence> known = {});

} // namespace codrive::conformance
