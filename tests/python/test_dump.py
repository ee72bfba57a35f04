# SPDX-License-Identifier: Apache-2.0
"""codrive.dump.read against the repository's traces and codrive-dump --json itself (host)."""
import gzip
import json
import os
import subprocess
import threading

import pytest

import codrive

TRACES = ["pdo.log", "sdo.log", "sdo_block.log", "services.log", "screen.log", "profile.log",
          "formats/conversation.blf", "formats/conversation-ixxat.csv"]


@pytest.mark.parametrize("name", TRACES)
def test_records_are_what_codrive_dump_json_prints(root, build_dir, name):
    trace = root / "tests/data/traces" / name
    out = subprocess.run([str(build_dir / "tools/codrive-dump"), "-r", str(trace), "--json"],
                         check=True, capture_output=True, text=True).stdout
    expected = [json.loads(line) for line in out.splitlines() if line]
    records = list(codrive.dump.read(trace))
    assert records == expected
    assert len(records) > 5


def test_the_golden_json_file_matches(root):
    records = [r for r in codrive.dump.read(root / "tests/data/traces/pdo.log")
               if r.get("service") in ("sdo", "pdo")]
    golden = [json.loads(line) for line in open(root / "tests/data/traces/pdo.json.expected")]
    assert records == golden


def test_an_eds_names_the_objects(root):
    trace = root / "tests/data/traces/eds.log"
    plain = list(codrive.dump.read(trace))
    named = list(codrive.dump.read(trace, eds={10: root / "tests/data/eds/real/canopendemo-demodevice.eds"}))
    assert len(plain) == len(named)
    assert [r["text"] for r in plain] != [r["text"] for r in named]


def test_bad_lines_are_problems_not_exceptions(tmp_path):
    log = tmp_path / "bad.log"
    log.write_text("(1700000000.000000) can0 704#05\n"
                   "(1700000000.100000) can0 7G4#05\n"
                   "(1700000000.200000) can0 704#05\n")
    trace = codrive.dump.read(log)
    records = list(trace)
    assert [r["id"] for r in records] == [0x704, 0x704]
    # codrive-dump names a bad line as FILE:LINE: cause.
    assert len(trace.problems) == 1 and "bad.log:2: bad CAN identifier" in trace.problems[0]


def test_a_gzip_compressed_trace_reads_like_the_plain_one(root, tmp_path):
    plain = root / "tests/data/traces/sdo.log"
    packed = tmp_path / "sdo.log.gz"
    packed.write_bytes(gzip.compress(plain.read_bytes()))
    assert list(codrive.dump.read(packed)) == list(codrive.dump.read(plain))
    cut = tmp_path / "cut.log.gz"
    cut.write_bytes(packed.read_bytes()[:-20])
    records = []
    with pytest.raises(codrive.Error, match="gzip: the compressed stream is cut short"):
        for rec in codrive.dump.read(cut):
            records.append(rec)
    assert 0 < len(records) <= len(list(codrive.dump.read(plain)))


def test_a_fifo_is_read_while_other_threads_run(tmp_path):
    # Opening a FIFO waits for its writer, and codrive-dump then reads its first bytes (gzip or
    # not): both without the GIL, or the writer below could never run.
    fifo = tmp_path / "live.log"
    os.mkfifo(fifo)
    result = {}
    reader = threading.Thread(target=lambda: result.update(records=list(codrive.dump.read(fifo))))
    reader.start()
    with open(fifo, "w") as w:
        w.write("(1700000000.000000) can0 704#05\n")
    reader.join(timeout=10)
    assert not reader.is_alive()
    assert [r["id"] for r in result["records"]] == [0x704]


def test_a_missing_file_raises_os_error(tmp_path):
    with pytest.raises(FileNotFoundError):
        codrive.dump.read(tmp_path / "absent.log")


def test_a_large_trace_streams_and_an_abandoned_one_is_released(tmp_path):
    log = tmp_path / "big.log"
    with open(log, "w") as f:
        for i in range(50_000):
            f.write(f"({1700000000 + i / 1000:.6f}) can0 704#05\n")
    count = sum(1 for _ in codrive.dump.read(log))
    assert count == 50_000
    it = iter(codrive.dump.read(log))
    assert next(it)["service"] == "hb"
    del it  # the decoding thread ends without the rest being consumed
