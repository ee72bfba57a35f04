// SPDX-License-Identifier: Apache-2.0
// Helpers for codrive-dump tests: run the pipeline on a trace file into a string.
#pragma once

#include <codrive/dump/dumper.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace codrive::dump::testing {

/// tests/data/traces/<name>.
std::string trace_path(const std::string& name);

/// Decodes tests/data/traces/<trace> with `options` (colours off) and returns what codrive-dump
/// would print: output lines, with input problems as "codrive-dump: ..." lines in order. `eds`
/// pairs a node with a file under tests/data/.
std::string run_dump(const std::string& trace, DumpOptions options,
                     const std::vector<std::pair<NodeId, std::string>>& eds = {});

/// Decodes bytes in memory.
std::string run_dump_bytes(std::string_view bytes, DumpOptions options);

} // namespace codrive::dump::testing
