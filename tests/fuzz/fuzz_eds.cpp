// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the EDS/DCF parser and writer must survive any input and round-trip it.
#include <codrive/core/eds.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    // The first byte picks the node-ID, so $NODEID arithmetic is fuzzed with and without one.
    std::optional<codrive::NodeId> node;
    if (size > 0 && data[0] % 128 != 0) {
        node = static_cast<codrive::NodeId>(data[0] % 128);
    }
    const codrive::DeviceDescription first = codrive::parse_eds(text, "fuzz.eds", node);
    for (const auto& f : first.findings) {
        (void)codrive::format_finding(f);
    }
    // Whatever was loaded must be writable and read back to as many objects and sub-objects.
    const std::string written = codrive::write_eds(first);
    const codrive::DeviceDescription second = codrive::parse_eds(written, "written.eds", node);
    if (second.od.size() != first.od.size()) {
        std::abort();
    }
    for (const auto& [index, obj] : first.od.objects()) {
        const codrive::Object* again = second.od.find(index);
        if (again == nullptr || again->subs.size() != obj.subs.size()) {
            std::abort();
        }
    }
    // Writing is a fixed point after one round: nothing drifts on repeated load/save.
    if (codrive::write_eds(second) != written) {
        std::abort();
    }
    return 0;
}
