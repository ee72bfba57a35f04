# SPDX-License-Identifier: Apache-2.0
"""pytest set-up: import codrive from a build tree (CODRIVE_PYTHON_DIR, default
build-ubsan/python) unless CODRIVE_PYTHON_DIR=installed asks for the installed package."""
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
_where = os.environ.get("CODRIVE_PYTHON_DIR", str(ROOT / "build-ubsan" / "python"))
if _where != "installed":
    sys.path.insert(0, _where)
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))  # docs_blocks for vcan/

import pytest  # noqa: E402

# vcan/ needs SocketCAN: it runs where vcan-scripts/run-in-vcan.sh provides it (CODRIVE_VCAN set).
collect_ignore = [] if os.environ.get("CODRIVE_VCAN") else ["vcan"]


@pytest.fixture
def root():
    """The repository root (test data lives under tests/data)."""
    return ROOT


@pytest.fixture
def build_dir():
    """The build tree whose tools the tests run (CODRIVE_BUILD_DIR, default build-ubsan)."""
    return pathlib.Path(os.environ.get("CODRIVE_BUILD_DIR", str(ROOT / "build-ubsan")))


@pytest.fixture(scope="module")
def build_dir_module():
    """build_dir for module-scoped fixtures."""
    return pathlib.Path(os.environ.get("CODRIVE_BUILD_DIR", str(ROOT / "build-ubsan")))
