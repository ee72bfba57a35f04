# SPDX-License-Identifier: Apache-2.0
"""SDO and NMT from Python on the in-process VirtualNetwork with simulated drives (host)."""
import threading

import pytest

import codrive


@pytest.fixture
def net():
    return codrive.VirtualNetwork()


@pytest.fixture
def bvs(net):
    return codrive.sim.VirtualDrive(net, 4, "ds-bvs")


def test_version_is_the_projects():
    major, minor, patch = codrive.__version__.split(".")
    assert int(major) >= 0 and int(minor) >= 0 and int(patch) >= 0


def test_typed_reads_return_python_values(net, bvs):
    sdo = net.sdo(4)
    assert sdo.read(0x1000, 0, "u32") == 0x00020192  # CiA 402 device, DS-BVS manual 1000h
    assert sdo.read(0x1008, 0, "str") == "DS-BVS"
    assert isinstance(sdo.read(0x1018, 1, "bytes"), bytes)
    assert len(sdo.read(0x1018, 1, "bytes")) == 4


def test_writes_are_read_back_in_every_integer_type(net, bvs):
    sdo = net.sdo(4)
    sdo.write(0x6060, 0, 1, "i8")  # profile position
    assert sdo.read(0x6060, 0, "i8") == 1
    sdo.write(0x6060, 0, 8, "i8")
    assert sdo.read(0x6060, 0, "i8") == 8
    sdo.write(0x6081, 0, 123456, "u32")
    assert sdo.read(0x6081, 0, "u32") == 123456


def test_a_missing_object_raises_sdo_abort_error_with_code_and_sentence(net, bvs):
    with pytest.raises(codrive.SdoAbortError) as info:
        net.sdo(4).read(0x1234, 0, "u32")
    e = info.value
    assert e.code == 0x06020000
    assert (e.node, e.index, e.subindex) == (4, 0x1234, 0)
    assert e.origin == "server"
    assert str(e) == ("node 4: SDO upload 0x1234:00 aborted by server: 0x06020000 object does "
                      "not exist in the object dictionary")
    assert isinstance(e, codrive.SdoError) and isinstance(e, codrive.Error)


def test_a_mode_the_drive_lacks_is_refused_with_the_abort_code(net, bvs):
    with pytest.raises(codrive.SdoAbortError) as info:
        net.sdo(4).write(0x6060, 0, 77, "i8")
    assert info.value.code == 0x06090030  # value range of parameter exceeded
    assert info.value.direction == "download"


def test_a_wrong_size_is_an_sdo_error_not_garbage(net, bvs):
    with pytest.raises(codrive.SdoError) as info:
        net.sdo(4).read(0x1000, 0, "u16")
    assert not isinstance(info.value, codrive.SdoTimeoutError)
    assert "0x1000:00" in str(info.value)


def test_a_silent_node_times_out_after_the_per_call_timeout(net, bvs):
    t0 = net.time
    with pytest.raises(codrive.SdoTimeoutError) as info:
        net.sdo(9).read(0x1000, 0, "u32", timeout=0.25)
    assert info.value.timeout == pytest.approx(0.25)
    assert "timed out after 250 ms" in str(info.value)
    assert net.time - t0 == pytest.approx(0.25, abs=0.01)  # simulated seconds


def test_values_that_do_not_fit_are_refused_before_sending(net, bvs):
    with pytest.raises(ValueError, match="70000 does not fit u16"):
        net.sdo(4).write(0x6040, 0, 70000, "u16")
    with pytest.raises(ValueError, match="does not fit u8"):
        net.sdo(4).write(0x6040, 0, -1, "u8")
    with pytest.raises(TypeError, match="give the type"):
        net.sdo(4).write(0x6040, 0, 5)
    with pytest.raises(ValueError, match="unknown SDO type"):
        net.sdo(4).read(0x1000, 0, "u24")
    with pytest.raises(ValueError, match="not 1..127"):
        net.sdo(0)


def test_segmented_and_block_transfers_with_progress(net, bvs):
    sdo = net.sdo(4)
    name = sdo.read(0x1008, 0, "str", mode="segmented")
    seen = []
    assert sdo.read(0x1008, 0, "str", mode="block", progress=lambda d, t: seen.append((d, t))) == name
    assert seen and seen[-1][0] == len(name)


def test_an_exception_in_a_progress_callback_reaches_the_caller(net, bvs):
    def boom(done, total):
        raise KeyError("from progress")

    with pytest.raises(KeyError, match="from progress"):
        net.sdo(4).read(0x1008, 0, "str", mode="block", progress=boom)
    assert net.sdo(4).read(0x1000, 0, "u32") == 0x00020192  # the bus still works


def test_nmt_commands_change_the_simulated_nodes_state(net, bvs):
    assert net.nmt.state(4) == "boot-up"
    net.nmt.start(4)
    assert bvs.nmt_state == "operational"
    net.nmt.stop(4)
    assert bvs.nmt_state == "stopped"
    net.nmt.pre_operational(4)
    assert bvs.nmt_state == "pre-operational"
    boots = net.nmt.boot_ups(4)
    net.nmt.reset(4)
    assert net.nmt.wait_for_state(4, "boot-up", timeout=2.0)
    assert net.nmt.boot_ups(4) == boots + 1
    net.nmt.reset_communication(0)  # all nodes
    assert net.nmt.wait_for_state(4, "boot-up", timeout=2.0)
    with pytest.raises(ValueError):
        net.nmt.start(128)


def test_the_gil_is_released_while_a_transfer_waits():
    # Two networks, two threads: both finish (a held GIL or a shared lock would serialise, not
    # deadlock, so this checks that waiting threads let Python run).
    results = []

    def worker(node):
        n = codrive.VirtualNetwork()
        drive = codrive.sim.VirtualDrive(n, node, "akd2g")  # noqa: F841 (kept on the bus)
        for _ in range(50):
            results.append(n.sdo(node).read(0x1000, 0, "u32"))

    threads = [threading.Thread(target=worker, args=(i,)) for i in (1, 2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)
    assert len(results) == 100


def test_bus_on_a_missing_interface_raises_bus_error():
    with pytest.raises(codrive.BusError, match="nosuchcan0"):
        codrive.Bus("nosuchcan0")


def test_scan_finds_the_simulated_nodes_with_identity_and_name():
    net = codrive.VirtualNetwork()
    drives = [codrive.sim.VirtualDrive(net, 3, "akd2g"), codrive.sim.VirtualDrive(net, 7, "ds-bvs")]
    rows = codrive.scan(net, 1, 10, timeout=0.1)
    assert [r["node"] for r in rows] == [3, 7]
    assert rows[0]["vendor_id"] == 0x6A  # Kollmorgen (AKD2G manual, 1018h:1)
    assert rows[1]["name"] == "DS-BVS"
    assert all(r["device_type"] == 0x00020192 for r in rows)
    assert len(drives) == 2
    with pytest.raises(ValueError):
        net.scan(0, 200)


def test_asyncio_reads_and_writes_keep_the_event_loop_running():
    import asyncio

    net = codrive.VirtualNetwork()
    drives = [codrive.sim.VirtualDrive(net, 1, "akd2g"), codrive.sim.VirtualDrive(net, 2, "ds-bvs")]

    async def main():
        ticks = 0

        async def ticker():
            nonlocal ticks
            while True:
                ticks += 1
                await asyncio.sleep(0)

        t = asyncio.create_task(ticker())
        await net.sdo(2).awrite(0x6060, 0, 1, "i8")
        names = await asyncio.gather(net.sdo(1).aread(0x1008, 0, "str"),
                                     net.sdo(2).aread(0x1008, 0, "str"),
                                     net.sdo(2).aread(0x6060, 0, "i8"))
        with pytest.raises(codrive.SdoAbortError):
            await net.sdo(1).aread(0x1234, 0, "u8")
        t.cancel()
        return names, ticks

    names, ticks = asyncio.run(main())
    assert names[1] == "DS-BVS" and names[2] == 1 and names[0]
    assert ticks > 0
    assert len(drives) == 2


def test_read_many_reads_several_nodes_in_one_call(net):
    drives = [codrive.sim.VirtualDrive(net, 3, "akd2g"), codrive.sim.VirtualDrive(net, 7, "ds-bvs")]
    values = net.read_many([(3, 0x1008, 0, "str"), (7, 0x1008, 0, "str"),
                            (3, 0x1000, 0, "u32"), (7, 0x1018, 1)])
    assert values[0].startswith("AKD2G") and values[1] == "DS-BVS"
    assert values[2] & 0xFFFF == 0x0192  # CiA 402 device type
    assert isinstance(values[3], bytes) and len(values[3]) == 4
    assert len(drives) == 2


def test_read_many_runs_the_nodes_side_by_side(net):
    # Two silent nodes with a 0.5 s timeout: side by side the call takes one timeout of
    # simulated time, not two (one after the other would take 1.0 s).
    start = net.time
    with pytest.raises(codrive.SdoTimeoutError, match="node 20"):
        net.read_many([(20, 0x1000, 0, "u32"), (21, 0x1000, 0, "u32")], timeout=0.5)
    assert 0.45 <= net.time - start < 0.75


def test_read_many_names_a_bad_request():
    net = codrive.VirtualNetwork()
    with pytest.raises(ValueError, match="request 0"):
        net.read_many([(1, 0x1000)])
    with pytest.raises(ValueError, match="node id 200"):
        net.read_many([(200, 0x1000, 0)])
