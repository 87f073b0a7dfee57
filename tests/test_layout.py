"""The shape of the Python package, checked (the Rust crates have tests/layout.rs): no import
circle among saggriac's modules, no module over 500 lines, and the modules left at a former
path only point to the new one (nothing in the package imports through them)."""

import ast
import importlib
from pathlib import Path

import saggriac

PACKAGE = Path(saggriac.__file__).parent
MAX_LINES = 500
#: Former module paths, kept as aliases of the module that moved (issue 26).
ALIASES = {
    "saggriac.goal_selection": "saggriac.teachers",
    "saggriac.learner": "saggriac.runs.learner",
    "saggriac.plots": "saggriac.analysis.plots",
    "saggriac.reproduce": "saggriac.study.reproduce",
    "saggriac.resources": "saggriac.runs.resources",
    "saggriac.result": "saggriac.runs.result",
    "saggriac.runner": "saggriac.runs.runner",
    "saggriac.splits": "saggriac.analysis.splits",
    "saggriac.statistics": "saggriac.analysis.statistics",
    "saggriac.storage": "saggriac.runs.storage",
    "saggriac.time_budget": "saggriac.runs.time_budget",
}
MAX_ALIAS_LINES = 10


def _modules() -> dict[str, Path]:
    out = {}
    for f in PACKAGE.rglob("*.py"):
        parts = list(f.relative_to(PACKAGE).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(["saggriac", *parts])] = f
    return out


def _is_package(name: str, modules: dict[str, Path]) -> bool:
    return modules[name].name == "__init__.py"


def _imports(name: str, modules: dict[str, Path]) -> set[str]:
    """The saggriac modules ``name`` imports at run time (imports under ``if TYPE_CHECKING`` are
    annotations only and left out; imports inside functions count)."""
    tree = ast.parse(modules[name].read_text())
    base = name.split(".") if _is_package(name, modules) else name.split(".")[:-1]
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip.update(id(n) for b in node.body for n in ast.walk(b))
    found = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.ImportFrom):
            if node.level:
                root = base[: len(base) - (node.level - 1)]
                target = ".".join(root + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            candidates = [target] + [f"{target}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            candidates = [a.name for a in node.names]
        else:
            continue
        for c in candidates:
            # The longest module prefix: `from .files import x` is saggriac.files.
            while c and c not in modules:
                c = c.rpartition(".")[0]
            if c and c != name and c.startswith("saggriac"):
                found.add(c)
    return found


def test_no_import_circle_in_the_package():
    modules = _modules()
    graph = {m: _imports(m, modules) for m in modules}
    # A package's __init__ may gather its own submodules, and saggriac/__init__ the whole
    # package; the edges from a parent package to its children are not circles of design.
    for m, deps in graph.items():
        graph[m] = {d for d in deps if not d.startswith(m + ".") and not (m == "saggriac")}
    state: dict[str, int] = {}

    def visit(m: str, stack: list[str]) -> None:
        if state.get(m) == 2:
            return
        if state.get(m) == 1:
            raise AssertionError("import circle: " + " -> ".join(stack[stack.index(m):] + [m]))
        state[m] = 1
        for d in sorted(graph[m]):
            visit(d, stack + [m])
        state[m] = 2

    for m in sorted(graph):
        visit(m, [])
    # The check sees the imports (a test that cannot fail is a defect).
    assert "saggriac.config" in graph["saggriac.runs.runner"] and "saggriac.teachers" in graph["saggriac.syllabus"]


def test_no_module_over_500_lines():
    long = {str(f.relative_to(PACKAGE)): n for f in _modules().values() if (n := len(f.read_text().splitlines())) > MAX_LINES}
    assert not long, f"over {MAX_LINES} lines: {long}"


def _points_elsewhere(tree: ast.Module) -> bool:
    """The module replaces itself in sys.modules (``sys.modules[__name__] = ...``)."""
    return any(isinstance(n, ast.Assign) and any(isinstance(t, ast.Subscript) and ast.unparse(t) == "sys.modules[__name__]" for t in n.targets) for n in ast.walk(tree))


def test_modules_at_former_paths_only_point_to_the_new_ones():
    modules = _modules()
    found = {m for m, f in modules.items() if _points_elsewhere(ast.parse(f.read_text()))}
    assert found == set(ALIASES), "an alias module was added or removed without updating ALIASES"
    for old, new in ALIASES.items():
        text = modules[old].read_text()
        assert len(text.splitlines()) <= MAX_ALIAS_LINES, f"{old} does more than point to {new}"
        body = [n for n in ast.parse(text).body if not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))]
        # import sys; from <package> import <module>; sys.modules[__name__] = <module>
        assert len(body) == 3 and isinstance(body[0], ast.Import) and isinstance(body[1], ast.ImportFrom) and _points_elsewhere(ast.Module(body=[body[2]], type_ignores=[])), f"{old} does more than point to {new}"
        assert _imports(old, modules) - {new.rpartition(".")[0]} == {new}, f"{old} must import {new} and nothing else of saggriac"
        assert importlib.import_module(old) is importlib.import_module(new)


def test_nothing_in_the_package_imports_through_a_former_path():
    modules = _modules()
    users = {m: sorted(_imports(m, modules) & set(ALIASES)) for m in modules if m not in ALIASES}
    assert not {m: a for m, a in users.items() if a}, "import the new path instead"


def test_the_docs_index_lists_every_page():
    docs = Path(__file__).resolve().parent.parent / "docs"
    index = (docs / "README.md").read_text()
    pages = sorted(p.name for p in docs.glob("*.md") if p.name != "README.md")
    assert [p for p in pages if f"]({p})" not in index] == []
