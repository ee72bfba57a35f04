// SPDX-License-Identifier: Apache-2.0
// Helpers for codrive-dump tests.
#include "dump_test_util.hpp"

#include <codrive/core/eds.hpp>
#include <codrive/dump/drive_profiles.hpp>

#include <gtest/gtest.h>

#include <memory>

namespace codrive::dump::testing {

std::string trace_path(const std::string& name) {
    return std::string(CODRIVE_SOURCE_DIR) + "/tests/data/traces/" + name;
}

namespace {
std::string run_on(BufferedInput& in, const std::string& name, DumpOptions options,
                   const std::vector<std::pair<NodeId, std::string>>& eds) {
    std::string out;
    options.line.color = false;
    Dumper d(
        options, [&](std::string_view s) { out.append(s); },
        [&](std::string_view s) {
            out += "codrive-dump: ";
            out.append(s);
            out += '\n';
        });
    static const ProfileRegistry profiles = [] {
        ProfileRegistry r;
        register_drive_profiles(r);
        return r;
    }();
    d.decoder().set_profiles(&profiles);
    for (const auto& [node, file] : eds) {
        auto desc = load_eds(std::string(CODRIVE_SOURCE_DIR) + "/tests/data/" + file, node);
        EXPECT_TRUE(desc) << file;
        if (desc) {
            d.decoder().set_description(node,
                                        std::make_shared<DeviceDescription>(std::move(*desc)));
        }
    }
    (void)dump_input(in, name, d);
    d.finish();
    return out;
}
} // namespace

std::string run_dump(const std::string& trace, DumpOptions options,
                     const std::vector<std::pair<NodeId, std::string>>& eds) {
    auto in = BufferedInput::open(trace_path(trace));
    EXPECT_TRUE(in) << trace;
    if (!in) {
        return {};
    }
    return run_on(**in, trace, std::move(options), eds);
}

std::string run_dump_bytes(std::string_view bytes, DumpOptions options) {
    auto in = BufferedInput::from_memory(bytes);
    return run_on(*in, "memory", std::move(options), {});
}

} // namespace codrive::dump::testing
