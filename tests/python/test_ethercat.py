# SPDX-License-Identifier: Apache-2.0
"""codrive from Python on an EtherCAT segment (host, root: a veth pair with codrive-ecat-sim in
its own network namespace): boot a bus file, enable the FIO's axis, follow a CSP ramp queued
from Python, shut down safely; a simulator that is not there is named in the error.
CODRIVE_SKIP_ETHERCAT=1 skips them (counted as skipped, as the C++ EtherCAT suite does)."""
import os

import pytest

import codrive

pytestmark = pytest.mark.skipif(os.environ.get("CODRIVE_SKIP_ETHERCAT") == "1",
                                reason="CODRIVE_SKIP_ETHERCAT=1")


@pytest.fixture
def ecat_sim(build_dir):
    return str(build_dir / "tools" / "codrive-ecat-sim")


def test_boot_enable_and_follow_a_csp_ramp_over_ethercat(root, ecat_sim):
    with codrive.sim.veth() as link, \
            codrive.sim.ethercat(link.slave, ["fio"], netns=link.netns, executable=ecat_sim):
        c = codrive.Controller.from_file(str(root / "tests/data/bus/ecat-fio.yml"))
        c.start()
        assert [(a["node"], a["axis"]) for a in c.axes] == [(0, 1)]
        axis = c.axis(0, 1)  # slave position 0, axis 1 (bus 0: no CAN bus in the file)
        axis.enable()
        status = axis.status
        assert status["state"] == "OPERATION ENABLED"
        assert status["statusword"] & 0x6F == 0x27  # CiA 402 Table 30
        assert status["error_code"] is None
        start = status["position"]
        assert start is not None  # 6064h arrives in the LRW frame
        for step in range(1, 51):
            axis.set_target_position(start + step * 200)
            c.run_for(0.02)
        c.run_for(0.2)
        assert abs(axis.status["position"] - (start + 50 * 200)) < 500
        stats = c.stats()
        assert stats["cycles"] > 400  # 2 ms cycle for about 1.2 s
        c.shutdown()
        assert axis.status["state"] != "OPERATION ENABLED"
        assert not c.running


def test_a_segment_without_slaves_fails_start_with_a_sentence(root):
    with codrive.sim.veth():  # nobody answers on the other end
        c = codrive.Controller.from_file(str(root / "tests/data/bus/ecat-fio.yml"))
        with pytest.raises(codrive.Error, match="ecpy0") as raised:
            c.start()
        assert raised.value.reason == "segment_failed"


def test_a_simulator_that_cannot_start_is_named(tmp_path):
    with pytest.raises(codrive.Error, match="codrive-ecat-sim on nosuchif0 did not get ready"):
        codrive.sim.ethercat("nosuchif0", ["fio"], timeout=5.0).start()
