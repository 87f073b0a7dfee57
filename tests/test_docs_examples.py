"""Every ```python block of README.md and docs/*.md runs, as a reader would run it: as a script of
its own, in a fresh process, in a working folder of pytest's.

Marks, an HTML comment on the line before a block's fence:

* ``<!-- continues -->``: the block goes on from the one before it (same script);
* ``<!-- slow -->``: the script is run under the ``slow`` marker;
* ``<!-- not-run: reason -->``: a fragment that cannot run alone (counted, and listed below).

The scripts of one page share its working folder and run in the page's order, so that a block
may read what an earlier one wrote (docs/studies.md loads the study it ran). A script that fails
for want of an optional extra (ImportError of one of EXTRAS) is skipped, unless
SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it): then it fails.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

#: The modules of saggriac's optional extras (and what they bring) a block may need.
EXTRAS = ("stable_baselines3", "torch", "syllabus", "gymnasium_robotics", "gymnasium", "mujoco", "dask", "distributed", "dask_jobqueue")

#: How many fragments each page has: adding one means saying here too that it cannot run.
NOT_RUN = {"README.md": 1, "docs/studies.md": 3, "docs/teachers.md": 1}

_FENCE = re.compile(r"^([ \t]*)```python[ \t]*\n(.*?)^\1```[ \t]*$", re.M | re.S)
_MARK = re.compile(r"<!--\s*(continues|slow|not-run:\s*(?P<why>.*?))\s*-->\s*$")


@dataclass
class Script:
    page: str
    lines: list[int]  # the first line of each block's code
    code: str
    slow: bool = False
    not_run: str | None = None
    order: int = 0
    blocks: list[str] = field(default_factory=list)

    @property
    def name(self) -> str:
        return f"{self.page}:{'+'.join(map(str, self.lines))}"


def _scripts(page: Path) -> list[Script]:
    text = page.read_text(encoding="utf-8")
    rel = page.relative_to(ROOT).as_posix()
    out: list[Script] = []
    for m in _FENCE.finditer(text):
        line = text.count("\n", 0, m.start()) + 2
        before = text[: m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        mark = _MARK.search(before)
        code = textwrap.dedent(m.group(2))
        kind = mark.group(1).split(":")[0] if mark else None
        if kind == "continues":
            assert out, f"{rel}:{line}: <!-- continues --> on the page's first block"
            prev = out[-1]
            prev.lines.append(line)
            prev.code += "\n" + code
            continue
        out.append(Script(rel, [line], code, slow=kind == "slow", not_run=mark.group("why") if kind == "not-run" else None, order=len(out)))
    return out


SCRIPTS = [s for page in PAGES for s in _scripts(page)]
_FOLDERS: dict[str, Path] = {}
_OUTCOME: dict[str, str] = {}  # script name -> "ok" or why it did not run


def _missing_extra(stderr: str) -> str | None:
    m = re.search(r"ModuleNotFoundError: No module named '([\w.]+)'", stderr)
    return m.group(1) if m and m.group(1).split(".")[0] in EXTRAS else None


def _run(script: Script, folder: Path) -> str:
    env = dict(os.environ)
    # One thread for torch's kernels: on a shared machine its default oversubscribes the cores
    # (20 times slower here).
    env.setdefault("OMP_NUM_THREADS", "1")
    path = folder / f"_block_{script.order}.py"
    path.write_text(script.code, encoding="utf-8")
    proc = subprocess.run([sys.executable, path.name], cwd=folder, env=env, capture_output=True, text=True, timeout=900)
    if proc.returncode == 0:
        return "ok"
    extra = _missing_extra(proc.stderr)
    if extra is not None and os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
        return f"skip: needs the optional module {extra}, not installed"
    tail = "\n".join(proc.stderr.strip().splitlines()[-25:])
    return f"fail: {script.name} exited with {proc.returncode}:\n{tail}"


def _outcome(script: Script, tmp_path_factory) -> str:
    if script.name not in _OUTCOME:
        folder = _FOLDERS.setdefault(script.page, tmp_path_factory.mktemp(re.sub(r"\W", "_", script.page)))
        for earlier in SCRIPTS:
            if earlier.page == script.page and earlier.order < script.order and earlier.not_run is None and earlier.name not in _OUTCOME:
                _OUTCOME[earlier.name] = _run(earlier, folder)  # a block may read what an earlier one wrote
        _OUTCOME[script.name] = _run(script, folder)
    return _OUTCOME[script.name]


@pytest.mark.parametrize("script", [pytest.param(s, id=s.name, marks=[pytest.mark.slow] if s.slow else []) for s in SCRIPTS if s.not_run is None])
def test_the_docs_code_runs(script, tmp_path_factory):
    outcome = _outcome(script, tmp_path_factory)
    if outcome.startswith("skip: "):
        pytest.skip(outcome[6:])
    assert outcome == "ok", outcome


def test_the_fragments_are_marked_and_few():
    fragments = {(s.page, s.lines[0]): s.not_run for s in SCRIPTS if s.not_run is not None}
    print(f"{len(fragments)} of {len(SCRIPTS)} scripts of the docs are fragments, not run:", *(f"{p}:{n}: {why}" for (p, n), why in sorted(fragments.items())), sep="\n  ")
    assert all(fragments.values()), "a <!-- not-run: reason --> gives its reason"
    per_page = {page: sum(p == page for p, _ in fragments) for page, _ in fragments}
    assert per_page == NOT_RUN


def test_every_python_fence_is_found():
    # A fence the pattern misses would go untested without a word.
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        assert len(re.findall(r"^[ \t]*```python[ \t]*$", text, re.M)) == len(_FENCE.findall(text)), page
