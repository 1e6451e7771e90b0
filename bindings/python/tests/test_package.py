"""The installed package: its stubs, marker and docstrings."""

import ast
import inspect
from pathlib import Path

import micromap_index as mmi


def test_stubs_and_marker_are_installed():
    here = Path(mmi.__file__).parent
    assert (here / "py.typed").exists()
    stub = ast.parse((here / "__init__.pyi").read_text())
    names = set()
    for node in ast.walk(stub):
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        elif isinstance(node, ast.alias):
            names.add(node.asname or node.name)
    assert set(mmi.__all__) <= names, set(mmi.__all__) - names
    native = ast.parse((here / "_native.pyi").read_text())
    native_names = {n.name for n in ast.walk(native) if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    assert {n for n in dir(mmi._native) if not n.startswith("_")} <= native_names


def test_every_public_name_is_documented():
    for name in mmi.__all__:
        value = getattr(mmi, name)
        if callable(value):
            assert (value.__doc__ or "").strip(), name
    for method in ("encode", "from_bytes", "to_bytes", "lookup", "state_at", "decode"):
        assert getattr(mmi.Tree, method).__doc__.strip(), method
    assert mmi.__version__ == "0.1.0"


def test_stub_signatures_match_the_functions():
    here = Path(mmi.__file__).parent
    stub = ast.parse((here / "__init__.pyi").read_text())
    checked = set()
    for node in stub.body:
        if isinstance(node, ast.FunctionDef):
            a = node.args
            stubbed = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
            assert stubbed == list(inspect.signature(getattr(mmi, node.name)).parameters), node.name
            checked.add(node.name)
    assert {"bake", "bake_gltf", "verify"} <= checked
