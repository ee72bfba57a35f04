# SPDX-License-Identifier: Apache-2.0
"""codrive.measure_timer_latency(): the controller's timer probe from Python (real sleeps, on
the host). Whether this machine is sound is not for the tests to say; that the figures are
there, that windows arrive in order, and that the run ends when asked, is."""
import os
import signal
import subprocess
import sys
import time

import pytest

import codrive


def test_figures_windows_and_the_worst_window():
    seen = []
    r = codrive.measure_timer_latency(0.002, 0.3, window=0.1, on_window=seen.append)
    assert [w["number"] for w in seen] == [1, 2, 3], "each window once, in order"
    assert [w["number"] for w in r["windows"]] == [1, 2, 3]
    assert seen[2]["start"] == pytest.approx(0.2) and seen[2]["end"] == pytest.approx(0.3)
    # 150 slots of 2 ms: each one a wake-up or skipped by a late one.
    assert r["wakeups"] >= 1 and r["wakeups"] + r["skipped_slots"] >= 150
    assert r["verdict"] in ("sound", "jittery", "not sound")
    assert 0 <= r["p50"] <= r["p99"] <= r["p999"] <= r["max"]
    assert r["worst_window"]["number"] in (1, 2, 3)
    assert r["text"].startswith("timer latency: ")
    assert "worst of 3 windows: window " in r["text"]


def test_an_exception_in_on_window_ends_the_run_and_is_raised():
    def stop(_window):
        raise RuntimeError("enough")

    t0 = time.monotonic()
    with pytest.raises(RuntimeError, match="enough"):
        codrive.measure_timer_latency(0.002, 60.0, window=0.1, on_window=stop)
    assert time.monotonic() - t0 < 5.0, "the minute's run went on after the exception"


def test_arguments_out_of_range_are_refused_with_a_sentence():
    with pytest.raises(ValueError, match="cycle must be 50e-6..1 seconds"):
        codrive.measure_timer_latency(1e-6, 1.0)
    with pytest.raises(ValueError, match="fifo must be a SCHED_FIFO priority"):
        codrive.measure_timer_latency(0.001, 0.1, fifo=120)
    with pytest.raises(ValueError, match="seconds must be 0..86400"):
        codrive.measure_timer_latency(0.001, float("nan"))


SCRIPT = """
import sys, time
import codrive
t0 = time.monotonic()
try:
    codrive.measure_timer_latency(0.002, 3600.0, window=0.1,
                                  on_window=lambda w: print("window", w["number"], flush=True))
except KeyboardInterrupt:
    print("KeyboardInterrupt after %.3f s" % (time.monotonic() - t0), flush=True)
    sys.exit(7)
print("the hour ended without the interrupt", flush=True)
"""


def _sigint_as_at_a_terminal():
    # A test run started in the background (`cmd &` in a script, nohup) ignores SIGINT, and a
    # child inherits that: Python then leaves Ctrl-C ignored. At a terminal it is the default,
    # for which Python installs its KeyboardInterrupt handler.
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_ctrl_c_ends_an_hours_run_with_keyboard_interrupt():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    p = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE, text=True,
                         env=env, preexec_fn=_sigint_as_at_a_terminal)
    try:
        assert p.stdout.readline().strip() == "window 1"
        p.send_signal(signal.SIGINT)
        out, _ = p.communicate(timeout=10)
    finally:
        p.kill()
    assert p.returncode == 7, out
    assert "KeyboardInterrupt after" in out
