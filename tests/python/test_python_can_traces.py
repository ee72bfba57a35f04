# SPDX-License-Identifier: Apache-2.0
"""codrive.dump.read against an independent writer: python-can (Debian's python3-can) writes
traces of random frames in every format it and codrive-dump share, and every frame must come back
with its identifier, flags, data and time. python-can's readers and writers are a separate
implementation of these formats, so a misreading on either side shows here."""
import gzip
import random

import can  # python3-can: a test dependency (.ci/install-deps.sh), never skipped
import pytest

import codrive

FD_LENGTHS = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64]
START = 1_700_000_000.0


def random_frames(seed, count, fd, remote):
    """Classic, 29-bit, remote (DLC 0..8) and CAN FD (0..64 bytes, BRS or not) frames, seeded."""
    rnd = random.Random(seed)
    t = START
    frames = []
    for _ in range(count):
        t += rnd.choice([0.000123, 0.001, 0.0105, 0.25])
        ext = rnd.random() < 0.3
        ident = rnd.randrange(1 << 29) if ext else rnd.randrange(1 << 11)
        kind = rnd.random()
        common = dict(timestamp=t, arbitration_id=ident, is_extended_id=ext, channel=0)
        if fd and kind < 0.25:
            data = bytes(rnd.randrange(256) for _ in range(rnd.choice(FD_LENGTHS)))
            frames.append(can.Message(is_fd=True, bitrate_switch=rnd.random() < 0.5, data=data,
                                      **common))
        elif remote and kind < 0.32:
            frames.append(can.Message(is_remote_frame=True, dlc=rnd.randrange(9), **common))
        else:
            data = bytes(rnd.randrange(256) for _ in range(rnd.randrange(9)))
            frames.append(can.Message(data=data, **common))
    return frames


# (suffix, writer, CAN FD written, remote frames written, remote DLC written). python-can's
# TRCWriter leaves remote frames out; its candump-log writer writes them as "#R" without the DLC
# that candump puts after the R.
FORMATS = [
    ("blf", can.BLFWriter, True, True, True),
    ("asc", can.ASCWriter, True, True, True),
    ("trc", can.TRCWriter, False, False, True),
    ("log", can.CanutilsLogWriter, True, True, False),
    ("csv", can.CSVWriter, False, True, True),
]


def frames_read(path):
    return [r for r in codrive.dump.read(path) if "id" in r]  # notes have no frame


def assert_same(written, read, remote_dlc):
    assert len(read) == len(written)
    for i, (m, r) in enumerate(zip(written, read)):
        where = f"frame {i}: {m}"
        assert (r["id"], r["ext"], r["rtr"], r["fd"]) == (
            m.arbitration_id, m.is_extended_id, m.is_remote_frame, m.is_fd), where
        if m.is_remote_frame:
            assert r["len"] == (m.dlc if remote_dlc else 0), where
        else:
            assert bytes.fromhex(r["data"]) == bytes(m.data), where
        # Times from the first frame: ASC files carry the writer's wall clock as their start,
        # and python-can 4.1's TRCWriter a wrong $STARTTIME.
        assert abs((r["ts"] - read[0]["ts"]) - (m.timestamp - written[0].timestamp)) < 2e-6, where


@pytest.mark.parametrize("suffix,writer,fd,remote,remote_dlc", FORMATS,
                         ids=[f[0] for f in FORMATS])
def test_frames_python_can_writes_read_back(tmp_path, suffix, writer, fd, remote, remote_dlc):
    written = random_frames(seed=len(suffix) * 7 + ord(suffix[0]), count=3000, fd=fd,
                            remote=remote)
    path = tmp_path / f"trace.{suffix}"
    with writer(str(path)) as w:
        for m in written:
            w.on_message_received(m)
    assert_same(written, frames_read(path), remote_dlc)
    # The same file gzip-compressed reads the same.
    packed = tmp_path / f"trace.{suffix}.gz"
    packed.write_bytes(gzip.compress(path.read_bytes()))
    assert_same(written, frames_read(packed), remote_dlc)
