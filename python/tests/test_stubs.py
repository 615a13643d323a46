"""The type stubs (_core.pyi) name exactly what the compiled module has."""
from __future__ import annotations

import ast
import inspect
from pathlib import Path

import vlpground
from vlpground import _core

STUBS = Path(vlpground.__file__).with_name("_core.pyi")


def _stub_tree():
    tree = ast.parse(STUBS.read_text())
    classes, functions = {}, set()
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign):
                    members.add(item.target.id)
            bases = [b.id for b in node.bases if isinstance(b, ast.Name)]
            classes[node.name] = (members, bases)
        elif isinstance(node, ast.FunctionDef):
            functions.add(node.name)
    return classes, functions


def _public(names):
    return {n for n in names if not n.startswith("__")}


def test_stubs_match_the_module():
    classes, functions = _stub_tree()
    runtime_classes = {n for n, v in vars(_core).items() if inspect.isclass(v)}
    runtime_functions = {n for n, v in vars(_core).items() if callable(v) and not inspect.isclass(v)}
    assert set(c for c in classes if not c.startswith("_")) == runtime_classes
    assert functions == runtime_functions
    for name in runtime_classes:
        members, bases = classes[name]
        for base in bases:
            members |= classes.get(base, (set(), []))[0]
        runtime = _public(n for n in dir(getattr(_core, name)) if not n.startswith("_pybind11"))
        assert _public(members) == runtime, name


def test_package_ships_the_typing_marker():
    assert Path(vlpground.__file__).with_name("py.typed").exists()
