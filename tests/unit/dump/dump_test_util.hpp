// SPDX-License-Identifier: Apache-2.0
// Helpers for codrive-dump tests: run the pipeline on a trace file into a string.
#pragma once

#include <codrive/dump/dumper.hpp>
#include <codrive/dump/trace_format.hpp>

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

/// One step of a reader, kept (the record's interface copied).
struct ReadItem {
    ReadStatus status = ReadStatus::End;
    Frame frame;
    std::int64_t ts_ns = 0;
    bool has_ts = false;
    std::string iface;
    std::string error; ///< for Malformed and Fatal
};

/// Reads `bytes` with the reader open_trace_reader() picks (its format in `format`) until End
/// or Fatal; every Frame and Malformed step in order (at most 10000).
std::vector<ReadItem> read_trace(std::string_view bytes, TraceFormat* format = nullptr);

/// read_trace() of an input already open (a file, to read it through BufferedInput::open).
std::vector<ReadItem> read_input(BufferedInput& in, TraceFormat* format = nullptr);

/// Only the frames of read_trace().
std::vector<ReadItem> frames_of(const std::vector<ReadItem>& items);

/// The contents of a file.
std::string slurp(const std::string& path);

inline constexpr std::int64_t kUs = 1'000;
inline constexpr std::int64_t kMs = 1'000'000;
/// Where synthetic traces start (2023-11-14 22:13:20 UTC).
inline constexpr std::int64_t kStart = 1'700'000'000'000 * kMs;

/// A timestamped record of `f` on can0.
TraceRecord rec(std::int64_t ts_ns, const Frame& f);

} // namespace codrive::dump::testing
