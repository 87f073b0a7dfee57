"""The shape of the Python package, checked (the Rust crates have tests/layout.rs): its parts as
subpackages under a small top level, no import circle among saggriac's modules, no module over
500 lines, no private name taken from another module, and the former module paths kept by one
mapping that warns (nothing in the package imports through them)."""

import ast
import re
import subprocess
import sys
from pathlib import Path

import saggriac

PACKAGE = Path(saggriac.__file__).parent
MAX_LINES = 500
#: The package's top level: its parts as subpackages, and the few modules every part uses.
TOP_LEVEL = {
    "adapters", "analysis", "bench", "bodies", "runs", "study", "teachers",  # the parts
    "cli", "config", "errors", "files", "seeding", "testing", "values", "_core",
}
MAX_TOP_LEVEL = 15


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
    assert "saggriac.config" in graph["saggriac.runs.runner"] and "saggriac.teachers" in graph["saggriac.adapters.syllabus"]


def test_no_module_over_500_lines():
    long = {str(f.relative_to(PACKAGE)): n for f in _modules().values() if (n := len(f.read_text().splitlines())) > MAX_LINES}
    assert not long, f"over {MAX_LINES} lines: {long}"


def test_the_top_level_shows_the_parts():
    """At most 15 modules besides __init__ (issue 34; the bench, issue 47, is the 15th): the parts are subpackages."""
    found = {p.name.split(".")[0] if p.is_file() else p.name for p in PACKAGE.iterdir() if (p.suffix in (".py", ".so") or (p / "__init__.py").exists()) and p.name != "__init__.py"}
    assert found == TOP_LEVEL and len(found) <= MAX_TOP_LEVEL


def _import_targets(name: str, modules: dict[str, Path]) -> set[str]:
    """Every absolute module path ``name`` imports from, as written (not resolved to a file)."""
    base = name.split(".") if _is_package(name, modules) else name.split(".")[:-1]
    out = set()
    for node in ast.walk(ast.parse(modules[name].read_text())):
        if isinstance(node, ast.ImportFrom):
            root = base[: len(base) - (node.level - 1)] if node.level else []
            target = ".".join(root + ([node.module] if node.module else []))
            out |= {target} | {f"{target}.{a.name}" for a in node.names}
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
    return out


def test_every_former_path_warns_and_gives_the_module_now_there():
    """saggriac <= 0.5's module paths: one mapping (saggriac.MOVED), no module files left."""
    modules = _modules()
    assert not set(saggriac.MOVED) & set(modules), "a former path is a module again: remove it or its MOVED entry"
    code = """
import importlib, warnings, saggriac
for old, new in saggriac.MOVED.items():
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        got = importlib.import_module(old)
    assert got is importlib.import_module(new), old
    assert got.__spec__.name == new, (old, got.__spec__.name)
    assert [x.category for x in w] == [DeprecationWarning] and new in str(w[0].message), (old, [str(x.message) for x in w])
print(len(saggriac.MOVED))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert int(out.stdout) == len(saggriac.MOVED) >= 20


def test_nothing_in_the_package_imports_through_a_former_path():
    modules = _modules()
    former = tuple(saggriac.MOVED)
    users = {m: sorted(t for t in _import_targets(m, modules) if t in former or t.startswith(tuple(f"{f}." for f in former))) for m in modules}
    assert not {m: a for m, a in users.items() if a}, "import the new path instead"
    # The check sees imports (a test that cannot fail is a defect).
    assert "saggriac.teachers.competence" in _import_targets("saggriac.adapters.syllabus", modules)


def test_no_module_takes_another_ones_private_names():
    """Subpackages and modules talk through public names (issue 34): nothing imports a name
    that starts with an underscore from another saggriac module (``_core`` is the compiled
    core's module name)."""
    found = []
    for name, f in _modules().items():
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("saggriac")):
                found += [f"{name}: {a.name}" for a in node.names if a.name.startswith("_") and a.name != "_core"]
    assert found == []


#: Modules that drive other modules' objects (a learner, a study, the command line): they use
#: those objects' public faces only.
DRIVERS = ["saggriac.runs.runner", "saggriac.study", "saggriac.study.backends", "saggriac.study.folder", "saggriac.study.reproduce", "saggriac.study.spec", "saggriac.cli"]


def test_drivers_name_no_private_attribute_of_another_module():
    """The runner, the studies and the CLI reach no ``obj._name`` of what they drive (issue 45):
    the runner once used five private members of Learner seven times. The standard library's
    documented ``os._exit`` and ``sys._getframe`` are not another saggriac module's."""
    modules = _modules()
    found = []
    for name in DRIVERS:
        for node in ast.walk(ast.parse(modules[name].read_text())):
            if isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__"):
                if not (isinstance(node.value, ast.Name) and node.value.id in ("os", "sys", "_core")):
                    found.append(f"{name}:{node.lineno}: {ast.unparse(node)}")
    assert found == []


def test_the_docs_index_lists_every_page():
    docs = Path(__file__).resolve().parent.parent / "docs"
    index = (docs / "README.md").read_text()
    pages = sorted(p.name for p in docs.glob("*.md") if p.name != "README.md")
    assert [p for p in pages if f"]({p})" not in index] == []


def test_nothing_cites_a_spec_the_repository_does_not_hold():
    """The project's reading of the paper is in its own docs; a citation of a SPEC.md that is not
    in the repository sends a reader nowhere (issue 34, item 5)."""
    root = Path(__file__).resolve().parent.parent
    files = [*(root / "python").rglob("*.py"), *(root / "crates").rglob("*.rs"), *(root / "docs").glob("*.md"), *(root / "tests").rglob("*.py"), root / "README.md"]
    found = [str(f.relative_to(root)) for f in files if f.name != "test_layout.py" and re.search(r"\bSPEC\b", f.read_text(errors="replace"))]
    assert files and found == []


def test_the_files_of_a_teacher_are_those_docs_architecture_lists():
    """docs/architecture.md lists the files a teacher is (with the name foo): every registered
    teacher has each of them, and its line in the registry."""
    import re

    from saggriac.teachers import available

    root = Path(__file__).resolve().parents[1]
    text = (root / "docs" / "architecture.md").read_text()
    listed = text.split("<!-- teacher-files -->")[1].split("<!-- /teacher-files -->")[0]
    paths = re.findall(r"^- `([^`]+)`", listed, flags=re.MULTILINE)
    assert len(paths) == 4, paths
    registry = (root / "crates/saggriac-core/src/config/teachers/mod.rs").read_text().split("macro_rules! registry")[1].split("pub(crate) use registry")[0]
    for kind in available():
        for path in paths:
            assert (root / path.replace("foo", kind)).is_file(), (kind, path)
        assert re.search(rf"^\s+{kind}: \w+\(\w+Config\),$", registry, flags=re.MULTILINE), kind
