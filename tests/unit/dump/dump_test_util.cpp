// SPDX-License-Identifier: Apache-2.0
// Helpers for codrive-dump tests.
#include "dump_test_util.hpp"

#include <codrive/core/eds.hpp>
#include <codrive/dump/drive_profiles.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <sstream>

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

std::vector<ReadItem> read_trace(std::string_view bytes, TraceFormat* format) {
    auto in = BufferedInput::from_memory(bytes);
    return read_input(*in, format);
}

std::vector<ReadItem> read_input(BufferedInput& in, TraceFormat* format) {
    auto reader = open_trace_reader(in, format);
    std::vector<ReadItem> items;
    TraceRecord r;
    for (int i = 0; i < 10000; ++i) {
        ReadItem item;
        item.status = reader->next(r);
        if (item.status == ReadStatus::End) {
            break;
        }
        if (item.status == ReadStatus::Frame) {
            item.frame = r.frame;
            item.ts_ns = r.ts_ns;
            item.has_ts = r.has_ts;
            item.iface = std::string(r.iface);
        } else {
            item.error = std::string(reader->error());
        }
        items.push_back(item);
        if (item.status == ReadStatus::Fatal) {
            break;
        }
    }
    return items;
}

std::vector<ReadItem> frames_of(const std::vector<ReadItem>& items) {
    std::vector<ReadItem> out;
    for (const auto& i : items) {
        if (i.status == ReadStatus::Frame) {
            out.push_back(i);
        }
    }
    return out;
}

TraceRecord rec(std::int64_t ts_ns, const Frame& f) {
    TraceRecord r;
    r.frame = f;
    r.ts_ns = ts_ns;
    r.has_ts = true;
    r.iface = "can0";
    return r;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

} // namespace codrive::dump::testing
