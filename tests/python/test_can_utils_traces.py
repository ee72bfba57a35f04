# SPDX-License-Identifier: Apache-2.0
"""codrive.dump.read against can-utils' converter log2asc (Debian's can-utils): a candump log of
random frames and log2asc's Vector ASC file of it must read as the same frames, so codrive-dump's
ASC reader agrees with an ASC writer it shares no code with."""
import random
import shutil
import subprocess

import pytest

import codrive

FD_LENGTHS = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64]


def random_candump_log(seed, count):
    """candump -l lines: classic, 29-bit, remote with a DLC, CAN FD with and without BRS."""
    rnd = random.Random(seed)
    t = 1_700_000_000.0
    lines = []
    for _ in range(count):
        t += rnd.choice([0.000123, 0.001, 0.0105, 0.25])
        ext = rnd.random() < 0.3
        ident = f"{rnd.randrange(1 << 29):08X}" if ext else f"{rnd.randrange(1 << 11):03X}"
        kind = rnd.random()
        if kind < 0.2:
            data = bytes(rnd.randrange(256) for _ in range(rnd.choice(FD_LENGTHS)))
            lines.append(f"({t:.6f}) can0 {ident}##{rnd.choice([0, 1])}{data.hex().upper()}")
        elif kind < 0.27:
            dlc = rnd.randrange(9)
            lines.append(f"({t:.6f}) can0 {ident}#R{dlc if dlc else ''}")
        else:
            data = bytes(rnd.randrange(256) for _ in range(rnd.randrange(9)))
            lines.append(f"({t:.6f}) can0 {ident}#{data.hex().upper()}")
    return "\n".join(lines) + "\n"


def frames(path):
    return [(r["id"], r["ext"], r["rtr"], r["fd"], r["len"], r["data"], r["ts"])
            for r in codrive.dump.read(path) if "id" in r]


@pytest.mark.parametrize("seed", [1, 2])
def test_log2asc_output_reads_as_the_candump_log(tmp_path, seed):
    log2asc = shutil.which("log2asc")
    assert log2asc, "log2asc (can-utils, .ci/install-deps.sh) is not installed"
    log = tmp_path / "trace.log"
    log.write_text(random_candump_log(seed, 3000))
    asc = tmp_path / "trace.asc"
    subprocess.run([log2asc, "-I", str(log), "-O", str(asc), "can0"], check=True)
    want, got = frames(log), frames(asc)
    assert len(want) == 3000 and len(got) == 3000
    for i, (w, g) in enumerate(zip(want, got)):
        assert w[:6] == g[:6], f"frame {i}"
        # log2asc writes times from the first frame and the first frame's date.
        assert abs((g[6] - got[0][6]) - (w[6] - want[0][6])) < 2e-6, f"frame {i}"
