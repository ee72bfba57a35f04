# SPDX-License-Identifier: Apache-2.0
"""codrive.Controller from Python over vcan: boot a bus file against codrive-sim, enable both
AKD2G axes, move one in CSP with set-points queued from Python, home the other, PP and PV moves,
safe shutdown (guest)."""
import pytest

import codrive


def test_boot_enable_and_move_two_akd2g_axes_in_csp(root, build_dir):
    with codrive.sim.can("vcan0", {1: "akd2g"}, executable=str(build_dir / "tools/codrive-sim")):
        c = codrive.Controller.from_file(str(root / "tests/data/bus/akd2g-csp.yml"))
        c.start()
        assert [a["axis"] for a in c.axes] == [1, 2]
        assert c.boot_reports and "node 1" in c.boot_reports[0]
        first, second = c.axis(1, 1), c.axis(1, 2)
        first.enable()
        second.enable()
        assert first.status["state"] == second.status["state"]
        assert first.status["statusword"] & 0x6F == 0x27  # OPERATION ENABLED (CiA 402 Table 30)
        start = first.status["position"]
        assert start is not None  # 6064h comes cyclically (TPDO)
        for step in range(1, 51):  # a ramp queued from Python, sent by the C++ cycle
            first.set_target_position(start + step * 200)
            c.run_for(0.02)
        c.run_for(0.2)
        assert abs(first.status["position"] - (start + 50 * 200)) < 500
        stats = c.stats()
        assert stats["cycles"] > 50 and stats["tpdos_received"] > 0
        with pytest.raises(KeyError):
            c.axis(1, 3)
        second.set_mode(6)  # homing, then back to CSP (as examples/demo.cpp does)
        second.home(35, offset=-5000)  # method 35: the current position is home (CiA 402)
        assert abs(second.status["position"] - (-5000)) < 100
        second.set_mode(8)
        c.shutdown()
        assert first.status["state"] != "OPERATION ENABLED"
        assert not c.running


def test_a_broken_bus_file_raises_with_its_findings(tmp_path):
    bad = tmp_path / "bus.yml"
    bad.write_text("bus:\n  interface: vcan0\nnodes:\n  - id: 300\n")
    with pytest.raises(codrive.Error, match="bus.yml") as raised:
        codrive.Controller.from_file(str(bad))
    assert raised.value.reason == "bus_file_invalid"


def test_profile_position_and_velocity_from_python(root, build_dir, tmp_path):
    bus_file = tmp_path / "pp-pv.yml"
    bus_file.write_text("bus:\n  interface: vcan0\n  sync_period_us: 4000\n"
                        "nodes:\n  - id: 1\n    profile: akd2g\n    heartbeat_ms: 100\n"
                        "    axes:\n      - {axis: 1, mode: pp}\n      - {axis: 2, mode: pv}\n")
    with codrive.sim.can("vcan0", {1: "akd2g"}, executable=str(build_dir / "tools/codrive-sim")):
        c = codrive.Controller.from_file(str(bus_file))
        c.start()
        pp, pv = c.axis(1, 1), c.axis(1, 2)
        pp.enable()
        pv.enable()
        start = pp.status["position"]
        pp.move_to(start + 4000, velocity=100000, timeout=5.0)
        assert abs(pp.status["position"] - (start + 4000)) < 100
        pv.run_velocity(20000, timeout=5.0)
        assert pv.status["statusword"] & 0x0400  # target reached (bit 10)
        with pytest.raises(codrive.DriveError, match="axis"):
            pv.move_to(1000, timeout=0.5)  # PV axis: a profile position move is refused
        c.shutdown()


def test_the_last_emergency_and_its_text_are_in_the_axis_status(build_dir, tmp_path):
    bus_file = tmp_path / "ds-bvs.yml"
    bus_file.write_text("bus:\n  interface: vcan0\n  sync_period_us: 4000\n"
                        "nodes:\n  - id: 2\n    profile: ds-bvs\n    heartbeat_ms: 100\n"
                        "    axes:\n      - {axis: 1, mode: csp}\n")
    with codrive.sim.can("vcan0", {2: "ds-bvs"},
                         executable=str(build_dir / "tools/codrive-sim")) as sim:
        c = codrive.Controller.from_file(str(bus_file))
        c.start()
        axis = c.axis(2)
        axis.enable()
        assert axis.status["error_code"] is None and axis.status["error_text"] is None
        sim.inject_fault(2, "overcurrent")
        c.run_for(0.3)
        status = axis.status
        assert status["state"] == "FAULT"
        # DS-BVS manual §6.2.79: 2310h "Over current" (the EMCY's error code, the drive's text).
        assert status["error_code"] == 0x2310
        assert status["error_text"] == "Over current"
        assert "Over current" in status["diagnosis"]
        c.shutdown()
