#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Long fuzzing campaign: every libFuzzer target for SECONDS (default 300 s) each, with the same
# per-target table as tests/fuzz/run.sh. The corpus grows in <build>/fuzz-corpus/ across runs.
# Usage: bench/fuzz_long.sh [SECONDS_PER_TARGET] [TARGET...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-300}
shift || true
exec "$root/tests/fuzz/run.sh" "$seconds" "$@"
