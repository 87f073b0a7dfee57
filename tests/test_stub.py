"""The checked-in type stub describes the compiled module."""

import ast
from pathlib import Path

import saggriac
from saggriac import _core


def _stub_names():
    stub = Path(saggriac.__file__).with_name("_core.pyi")
    tree = ast.parse(stub.read_text())
    top, methods = set(), set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            top.add(node.target.id)
        elif isinstance(node, ast.ClassDef):
            top.add(node.name)
            methods |= {f"{node.name}.{m.name}" for m in node.body if isinstance(m, ast.FunctionDef) and not m.name.startswith("__")}
    return top, methods


def test_stub_matches_module():
    top, methods = _stub_names()
    public = {n for n in dir(_core) if not n.startswith("_")} | {"__version__"}
    assert top == public
    actual = {f"{c}.{n}" for c in ("Learner", "AskTell") for n in dir(getattr(_core, c)) if not n.startswith("_")}
    assert methods == actual


def test_config_keys_match():
    cfg = saggriac.Config()
    assert set(cfg.core_dict()) == set(_core.CONFIG_KEYS)
