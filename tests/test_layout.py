"""The shape of the Python package, checked (the Rust crates have tests/layout.rs): no import
circle among saggriac's modules, and no module over 500 lines."""

import ast
from pathlib import Path

import saggriac

PACKAGE = Path(saggriac.__file__).parent
MAX_LINES = 500


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
    assert "saggriac.config" in graph["saggriac.runner"] and "saggriac.teachers" in graph["saggriac.syllabus"]


def test_no_module_over_500_lines():
    long = {str(f.relative_to(PACKAGE)): n for f in _modules().values() if (n := len(f.read_text().splitlines())) > MAX_LINES}
    assert not long, f"over {MAX_LINES} lines: {long}"
