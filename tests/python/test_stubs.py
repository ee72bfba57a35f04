# SPDX-License-Identifier: Apache-2.0
"""The type stubs (_native.pyi) name what the extension really has, so completion never
offers a method that does not exist (host)."""
import ast
import pathlib

import codrive
from codrive import _native

STUB = pathlib.Path(_native.__file__).with_name("_native.pyi")
# Stub classes standing for objects reached through a submodule.
REAL = {"_VirtualDrive": _native.sim.VirtualDrive, "_SimModule": _native.sim,
        "_Finding": _native.eds.Finding, "_SubObject": _native.eds.SubObject,
        "_Object": _native.eds.Object, "_Eds": _native.eds.Eds, "_EdsModule": _native.eds,
        "_TraceStream": _native.dump.TraceStream, "_DumpModule": _native.dump}


def stub_classes():
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    members.add(item.target.id)
                elif isinstance(item, ast.Assign):
                    members.update(t.id for t in item.targets if isinstance(t, ast.Name))
            yield node.name, members


def test_the_stub_file_is_installed_with_the_package():
    assert STUB.is_file()
    assert STUB.with_name("py.typed").is_file()


def test_every_stubbed_member_exists():
    missing = []
    for name, members in stub_classes():
        real = REAL.get(name, getattr(_native, name, None))
        assert real is not None, f"stub class {name} has no counterpart"
        for m in members - {"__init__"}:
            if not hasattr(real, m):
                # Exception attributes are set per instance when raised.
                if isinstance(real, type) and issubclass(real, codrive.Error):
                    continue
                missing.append(f"{name}.{m}")
    assert not missing


def test_every_public_class_and_method_is_stubbed():
    stubbed = dict(stub_classes())
    for cls in (codrive.Bus, codrive.VirtualNetwork, codrive.SdoClient, codrive.Nmt,
                codrive.Controller, codrive.Axis):
        public = {m for m in vars(cls) if not m.startswith("__")}
        assert public <= stubbed[cls.__name__], (cls.__name__, public - stubbed[cls.__name__])


def test_every_public_call_has_a_docstring():
    for obj in (codrive.Bus, codrive.VirtualNetwork, codrive.SdoClient.read,
                codrive.SdoClient.write, codrive.Nmt.wait_for_state, codrive.sim.VirtualDrive,
                codrive.sim.can, codrive.eds.load, codrive.dump.read, codrive.SdoAbortError):
        assert obj.__doc__ and len(obj.__doc__) > 20, obj
