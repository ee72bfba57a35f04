# SPDX-License-Identifier: Apache-2.0
"""docs/python.md is code: every python block that needs no vcan runs here (host), from the
repository root; the set-up command runs against the build tree under test."""
import os
import subprocess

import pytest

import codrive
from docs_blocks import blocks, python_blocks


@pytest.mark.parametrize("line,code", python_blocks(vcan=False),
                         ids=lambda v: f"line{v}" if isinstance(v, int) else "")
def test_python_block_runs(root, monkeypatch, line, code):
    if "codrive.sim.ethercat" in code and os.environ.get("CODRIVE_SKIP_ETHERCAT") == "1":
        pytest.skip("CODRIVE_SKIP_ETHERCAT=1 (the block needs root and veth)")
    monkeypatch.chdir(root)
    exec(compile(code, f"docs/python.md:{line}", "exec"), {"__name__": "__docs__"})


def test_the_page_has_blocks_for_host_and_vcan():
    assert len(python_blocks(vcan=False)) >= 5
    assert len(python_blocks(vcan=True)) >= 1


def test_the_set_up_command_prints_the_version(root):
    pkg_dir = os.path.dirname(os.path.dirname(codrive.__file__))
    (line, code), = [(n, c) for n, c in blocks("sh") if "import codrive" in c]
    command = code.replace("build-release/python", pkg_dir)
    out = subprocess.run(["bash", "-euo", "pipefail", "-c", command], cwd=root, check=True,
                         capture_output=True, text=True, env={"PATH": os.environ["PATH"]}).stdout
    assert out.strip() == codrive.__version__, f"docs/python.md:{line}"
