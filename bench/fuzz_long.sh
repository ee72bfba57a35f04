#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Long fuzzing campaign for the record: every libFuzzer target, one at a time, to RUNS executions
# (default 10,000,000) at the lowest CPU priority, with tests/fuzz/run.sh's per-target table
# (executions, exec/s, cov, ft, corpus size, result) and its "fuzz: N passed, M failed" line.
# The corpus grows in <build>/fuzz-corpus/ across runs.
# Usage: bench/fuzz_long.sh [TARGET...]
# Environment: RUNS (executions per target), FUZZ_TIMEOUT (default 60 s, below), DEADLINE (a
#              time `date -d` understands, e.g. 11:30 UTC: the running target is stopped then
#              and counted as failed, no new one starts),
#              plus tests/fuzz/run.sh's (CODRIVE_FUZZ_BUILD, JOBS, ...).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export FUZZ_RUNS=${RUNS:-10000000}
# libFuzzer's -timeout counts wall time. At nice 19 a campaign gets almost no CPU while a build
# runs beside it at normal priority: a 0.2 s fuzz_eds input once "timed out" after 11 s that way
# (session 18). 60 s still catches a real hang (on the fake clock nothing waits) and rides out
# such stalls; build at nice 19 too and the campaign keeps its share.
export FUZZ_TIMEOUT=${FUZZ_TIMEOUT:-60}
if [[ -n ${DEADLINE:-} ]]; then
    FUZZ_DEADLINE=$(date -d "$DEADLINE" +%s)
    export FUZZ_DEADLINE
fi
# Under autogroup scheduling (CONFIG_SCHED_AUTOGROUP, sched(7)) nice ranks processes only
# within one session; between sessions the kernel shares the CPUs by each session's autogroup
# nice. A campaign started with setsid (a session of its own, as a long unattended run is) took
# 70 % of each CPU at nice 19 against a CI run (session 27): its session's autogroup was at 0.
# When this script leads its own session, the whole session is the campaign: give it nice 19
# there too. Started from a terminal's session it leaves that session's autogroup alone.
if [[ $(ps -o sid= -p $$ | tr -d ' ') == "$$" && -w /proc/self/autogroup ]]; then
    echo 19 >/proc/self/autogroup || true
fi
# The seconds argument is unused when FUZZ_RUNS is set.
exec nice -n 19 "$root/tests/fuzz/run.sh" 0 "$@"
