// SPDX-License-Identifier: Apache-2.0
// Bus files with a map where a list belongs (and other shape mistakes): each one a finding with
// its line and key, and every other finding of the file still reported.
#include <codrive/master/bus_config.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace codrive;
using namespace codrive::master;

namespace {

std::vector<std::string> findings(const std::string& yaml) {
    std::vector<std::string> out;
    for (const auto& f : parse_bus_config(yaml, "bad.yml").errors) {
        out.push_back(f.to_string());
    }
    return out;
}

bool has(const std::vector<std::string>& all, const std::string& text) {
    for (const auto& f : all) {
        if (f.find(text) != std::string::npos) {
            return true;
        }
    }
    return false;
}

std::string dump(const std::vector<std::string>& all) {
    std::string s;
    for (const auto& f : all) {
        s += f + "\n";
    }
    return s;
}

} // namespace

TEST(BusConfigShapes, MapWhereAListBelongsIsAFindingAndTheRestIsStillChecked) {
    // The issue-19 file: `axes:` and `writes:` written as maps, plus unrelated mistakes after.
    const auto f = findings(R"(bus: {interface: vcan0}
nodes:
  - id: 1
    writes:
      object: 0x6060:00
      type: i8
      value: 8
    axes:
      axis: 1
      mode: csp
  - id: 2
    heartbeat_ms: fast
  - id: 1
)");
    EXPECT_TRUE(has(f, "bad.yml:5: node 1 writes must be a list")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:9: node 1 axes must be a list")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:12: node 2 heartbeat_ms must be a number, not `fast`")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:13: node 1 is configured twice")) << dump(f);
    EXPECT_EQ(f.size(), 4U) << dump(f);
    for (const auto& line : f) {
        EXPECT_EQ(line.find("invalid node"), std::string::npos) << line;
    }
}

TEST(BusConfigShapes, ListOrMapWhereOneValueBelongsNamesTheKey) {
    const auto f = findings(R"(bus: {interface: vcan0}
nodes:
  - id: 4
    name: [a, b]
    start: maybe
    eds: {file: x.eds}
    pdos:
      tpdo1:
        enabled: 3
        transmission: [1]
        map: [{a: 1}, 0x6041:00:16]
)");
    EXPECT_TRUE(has(f, "bad.yml:4: node 4 name must be a single value, but it is a list"))
        << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:5: node 4 start must be true or false, not `maybe`")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:6: node 4 eds must be a single value, but it is a map")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:9: node 4 TPDO1 enabled must be true or false, not `3`"))
        << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:10: node 4 TPDO1 transmission must be a number")) << dump(f);
    EXPECT_TRUE(
        has(f, "bad.yml:11: node 4 TPDO1 map entry must be a single value, but it is a map"))
        << dump(f);
    EXPECT_EQ(f.size(), 6U) << dump(f);
}

TEST(BusConfigShapes, WriteAndAxisFieldsOfTheWrongShape) {
    const auto f = findings(R"(bus:
  interface: vcan0
  master: [127]
nodes:
  - id: 5
    identity: 0x6A
    guarding: {guard_time_ms: 100}
    writes:
      - {object: [0x6060, 0], type: i8, value: 8}
      - {object: 0x6060:00, type: {t: i8}, value: 8}
      - {object: 0x6060:00, type: i8, value: [8]}
    axes:
      - {axis: 1, mode: [csp], units: mm}
      - {axis: 2, units: {increments_per_unit: lots, unit: mm}}
)");
    EXPECT_TRUE(has(f, "bad.yml:3: `bus.master` must be a map")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:6: node 5 identity must be a map")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:7: node 5 guarding needs both `guard_time_ms` and "
                       "`life_time_factor`"))
        << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:9: node 5 write object must be a single value, but it is a list"))
        << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:10: node 5 write type must be a single value, but it is a map"))
        << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:11: node 5 write to 0x6060:00 value must be a single value"))
        << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:13: node 5 axis 1 mode must be a single value, but it is a list"))
        << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:13: node 5 axis 1 units must be a map")) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:14: node 5 axis 2: increments_per_unit must be a number, not "
                       "`lots`"))
        << dump(f);
    EXPECT_EQ(f.size(), 9U) << dump(f);
}

TEST(BusConfigShapes, NodesAsAMapIsOneFindingWithItsLine) {
    const auto f = findings(R"(bus: {interface: vcan0}
nodes:
  id: 1
  profile: akd2g
)");
    ASSERT_EQ(f.size(), 1U) << dump(f);
    EXPECT_TRUE(has(f, "bad.yml:3: `nodes` must be a list")) << dump(f);
}
