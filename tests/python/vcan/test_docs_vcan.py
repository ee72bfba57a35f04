# SPDX-License-Identifier: Apache-2.0
"""docs/python.md is code: the python blocks that use vcan0 run here, in the vcan guest."""
import pytest

from docs_blocks import python_blocks


@pytest.mark.parametrize("line,code", python_blocks(vcan=True),
                         ids=lambda v: f"line{v}" if isinstance(v, int) else "")
def test_python_block_runs_on_vcan(root, build_dir, monkeypatch, line, code):
    monkeypatch.chdir(root)
    monkeypatch.setenv("CODRIVE_SIM", str(build_dir / "tools/codrive-sim"))
    exec(compile(code, f"docs/python.md:{line}", "exec"), {"__name__": "__docs__"})
