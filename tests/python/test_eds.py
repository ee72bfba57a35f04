# SPDX-License-Identifier: Apache-2.0
"""codrive.eds on the repository's EDS/DCF test files and a real-world file (host)."""
import pytest

import codrive


def test_objects_by_index_and_name(root):
    eds = codrive.eds.load(str(root / "tests/data/eds/full.eds"))
    identity = eds[0x1018]
    assert identity.name == "Identity object"
    assert identity.code == "RECORD"
    assert eds["identity OBJECT"].index == 0x1018  # names match case-insensitively
    vendor = eds[0x1018, 1]
    assert (vendor.name, vendor.type, vendor.access) == ("Vendor-ID", "UNSIGNED32", "ro")
    assert vendor.value == eds.device_info["vendor_number"] == 171
    assert identity["Product code"].value == eds.device_info["product_number"]
    assert [s.subindex for s in identity.subs] == [0, 1, 2, 3, 4]
    assert len(eds) == len(list(eds)) == 15
    assert 0x1018 in eds and 0x9999 not in eds and "Identity object" in eds
    assert not eds.findings and not eds.has_errors


def test_missing_objects_raise_key_error_naming_file_and_object(root):
    eds = codrive.eds.load(str(root / "tests/data/eds/full.eds"))
    with pytest.raises(KeyError, match="no object 0x9999"):
        eds[0x9999]
    with pytest.raises(KeyError, match="0x1018 has no sub-index 9"):
        eds[0x1018, 9]


def test_lint_findings_are_objects_with_line_and_severity(root):
    path = str(root / "tests/data/eds/sloppy.eds")
    eds = codrive.eds.load(path)
    assert eds.findings, "sloppy.eds has findings"
    first = eds.findings[0]
    assert first.file == path and first.line > 0
    assert first.severity in ("info", "warning", "error")
    assert str(first) == f"{path}:{first.line}: {first.severity}: {first.message}"


def test_an_error_in_a_file_is_a_finding_and_the_rest_loads(root):
    eds = codrive.eds.load(str(root / "tests/data/eds/malformed/bad_datatype.eds"))
    assert eds.has_errors
    errors = [f for f in eds.findings if f.severity == "error"]
    assert any("DataType 0x0020" in f.message for f in errors)


def test_an_unreadable_file_raises_os_error(tmp_path):
    with pytest.raises(FileNotFoundError):
        codrive.eds.load(str(tmp_path / "absent.eds"))


def test_a_dcf_evaluates_nodeid_expressions(root):
    eds = codrive.eds.load(str(root / "tests/data/eds/device.dcf"))
    assert eds.node_id == 5  # [DeviceComissioning] NodeID=0x05
    tpdo1 = eds[0x1800, 1]
    assert tpdo1.default_text == "$NODEID+0x180"
    assert tpdo1.default == 0x185
    assert tpdo1.value == 0x80000185  # ParameterValue=$NODEID+0x80000180
    again = codrive.eds.load(str(root / "tests/data/eds/device.dcf"), node_id=9)
    assert again.node_id == 9 and again[0x1800, 1].default == 0x189


def test_a_real_world_file_loads_without_errors(root):
    path = root / "tests/data/eds/real/canopennode-ds301-profile.eds"
    eds = codrive.eds.load(str(path))
    assert not eds.has_errors, [str(f) for f in eds.findings]
    assert eds[0x1000].subs[0].type == "UNSIGNED32"
