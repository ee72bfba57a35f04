// SPDX-License-Identifier: Apache-2.0
// Conformance facts (object, sub, type, access, default, manual section) checked against a
// simulated drive through the real protocol, the master's drive profile and the device files.
#pragma once

#include "../unit/sim/device_test_support.hpp"

#include <codrive/core/data_type.hpp>
#include <codrive/core/eds.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
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

/// Where a known divergence is: in the simulator or the master's profile, or only in the device
/// description files (devices/*.eds, devices/*.xml).
enum class In { SimOrProfile, DeviceFile };

/// A fact the simulator, profile or device file is known to get wrong, with the reason (listed
/// in docs/conformance.md). It is still checked and counted as failed in the summary; the test
/// fails if it is no longer wrong, so the list stays true. `last` (not 0) makes it cover every
/// sub-index of the objects index..last (the objects a device file does not hold).
struct KnownDivergence {
    std::uint16_t index = 0;
    std::uint8_t sub = 0;
    const char* reason = "";
    In in = In::SimOrProfile;
    std::uint16_t last = 0;
};

/// A drive's device description files, read the way a user's tool reads them: the EDS (CiA 306)
/// with codrive's EDS parser, the ESI (ETG.2000) with pugixml. Either may be missing (a drive
/// without that bus); a file that cannot be read is reported in every fact checked against it.
class DeviceFiles {
public:
    DeviceFiles(std::string eds_path, std::string esi_path);
    ~DeviceFiles();
    DeviceFiles(const DeviceFiles&) = delete;
    DeviceFiles& operator=(const DeviceFiles&) = delete;
    /// `devices/<stem>.eds` and `devices/<stem>.xml` of the source tree (CODRIVE_SOURCE_DIR).
    static DeviceFiles of(std::string_view stem);

    /// Checks a fact against the EDS (facts not EtherCAT only) and the ESI (facts not CAN
    /// only): the object is there (or absent where the manual says so) with the fact's type,
    /// access, default and limits as far as the file carries them. Returns one sentence per
    /// difference, naming `what` (drive, object, section), the file and the difference.
    [[nodiscard]] std::vector<std::string> check(const std::string& what, const Fact& f) const;
    /// Whether the fact is checked against a file at all (its bus has one).
    [[nodiscard]] bool applies(const Fact& f) const;

    struct Esi;

private:
    std::string eds_name_;
    std::string esi_name_;
    std::unique_ptr<DeviceDescription> eds_;
    std::string eds_error_;
    std::unique_ptr<Esi> esi_;
    std::string esi_error_;
};

/// The smallest and largest value of an integer type.
std::pair<std::int64_t, std::int64_t> type_range(DataType t);
/// Little-endian bytes as a value of the type (sign-extended for signed types).
std::int64_t decode(DataType t, const std::vector<std::uint8_t>& d);

/// The fact tables, one per drive (akd2g_facts.cpp, ds_bvs_facts.cpp, fio_facts.cpp).
std::span<const Fact> akd2g_facts();
std::span<const Fact> ds_bvs_facts();
std::span<const Fact> fio_facts();
std::span<const KnownDivergence> akd2g_known();
std::span<const KnownDivergence> ds_bvs_known();
std::span<const KnownDivergence> fio_known();

/// Checks every fact against the simulator through the protocol of each bus the fact names
/// (`can`: SDO over the virtual CAN bus, `ecat`: CoE over the in-process EtherCAT segment; a
/// null probe skips that bus), against the master's profile and against the drive's device
/// description files; reports each failure as a test failure naming the fact, its section and
/// manual line, and tallies them for the summary line `conformance: N facts checked per drive,
/// M failed; device files (EDS, ESI): N checked, F failed`.
void check_facts(std::string_view drive, const drives::Profile& profile, Probe* can, Probe* ecat,
                 const DeviceFiles& files, std::span<const Fact> facts,
                 std::span<const KnownDivergence> known = {});

} // namespace codrive::conformance
