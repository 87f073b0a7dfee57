"""Fuzzing what surrounds a run: targets of every kind (free, nested, empty, a user's folder or
file, links, finished, damaged or foreign runs, read-only places, '.', '..', '', long and odd
names), every way of writing (CLI, API, resume, load, a study, two runs at once) and corrupted
files. Whatever happens: a result or a saggriac error (never a traceback), every file saggriac
did not write is byte-identical afterwards, a finished run is replaced only when asked, and no
temporary or lock file is left behind.

Examples: 40 in CI; ``SAGGRIAC_FUZZ_EXAMPLES=N`` raises it (benchmarks/fuzz_campaign.py).
"""

import contextlib
import io
import os
import shutil
import subprocess
import threading
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402

from tests import fuzzing  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import saggriac  # noqa: E402
from saggriac.cli import main  # noqa: E402
from saggriac.errors import SaggriacError  # noqa: E402
from saggriac.runs import storage  # noqa: E402
from saggriac.runs import checkpoint_dir  # noqa: E402

EXAMPLES = max(1, fuzzing.EXAMPLES * 2 // 3)
FUZZ = fuzzing.fuzz_settings(EXAMPLES)
COUNTS: dict[str, int] = {}
TINY = dict(n_steps=60, n_evals=1, n_test_goals=4, n_test_configs=4)
TINY_CLI = ["--steps", "60", "--set", "n_evals=1", "--set", "n_test_goals=4", "--set", "n_test_configs=4", "--no-progress"]
CAN_FREEZE = os.geteuid() == 0 and shutil.which("chattr") is not None

TARGETS = [
    "absent", "nested", "empty_dir", "user_dir", "user_file", "link_to_user_dir", "link_to_file", "under_a_file",
    "finished_run", "finished_run_plus_user_file", "damaged_run", "run_without_manifest", "study_folder",
    "dot", "dotdot", "empty_string", "long_name", "odd_name", "frozen_parent", "frozen_target_run",
]
ACTIONS = ["cli_run", "cli_run_overwrite", "api_run", "api_run_overwrite", "cli_resume", "load", "study", "two_runs"]
DAMAGE = ["delete", "truncate", "flip", "garbage_manifest", "table_is_a_dir"]


@pytest.fixture(scope="module")
def template(tmp_path_factory):
    """One finished tiny run, copied wherever a scenario needs a saggriac run."""
    out = tmp_path_factory.mktemp("template") / "run"
    saggriac.run(saggriac.Config.from_preset("exp1", **TINY), 0, out_dir=out)
    return out


def _freeze(path, on):
    subprocess.run(["chattr", "+i" if on else "-i", str(path)], check=True, capture_output=True)


def _damage(run, how, rng):
    table = run / rng.choice(["metrics.parquet", "goals.parquet", "attempts.parquet", "regions.parquet"])
    if how == "delete":
        table.unlink()
    elif how == "truncate":
        data = table.read_bytes()
        table.write_bytes(data[: rng.randrange(len(data))])
    elif how == "flip":
        data = bytearray(table.read_bytes())
        data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        table.write_bytes(bytes(data))
    elif how == "garbage_manifest":
        (run / "run.json").write_bytes(b"\xff{not json")
    else:
        table.unlink()
        table.mkdir()


def _setup(ws, kind, damage, rng, template):
    """Make the scenario; return the target as the user would type it and what it stands for."""
    user = ws / "user"
    user.mkdir()
    (user / "thesis.tex").write_text("years of work")
    if kind == "absent":
        return str(ws / "r")
    if kind == "nested":
        return str(ws / "a" / "b" / "r")
    if kind == "empty_dir":
        (ws / "r").mkdir()
        return str(ws / "r")
    if kind == "user_dir":
        (ws / "r").mkdir()
        (ws / "r" / "notes.txt").write_text("mine")
        return str(ws / "r")
    if kind == "user_file":
        (ws / "r").write_text("mine")
        return str(ws / "r")
    if kind == "link_to_user_dir":
        (ws / "r").symlink_to(user, target_is_directory=True)
        return str(ws / "r")
    if kind == "link_to_file":
        (ws / "r").symlink_to(user / "thesis.tex")
        return str(ws / "r")
    if kind == "under_a_file":
        return str(user / "thesis.tex" / "r")
    if kind in ("finished_run", "finished_run_plus_user_file", "damaged_run", "run_without_manifest", "frozen_target_run"):
        shutil.copytree(template, ws / "r")
        if kind == "finished_run_plus_user_file":
            (ws / "r" / "analysis.ipynb").write_text("{}")
        elif kind == "damaged_run":
            _damage(ws / "r", damage, rng)
        elif kind == "run_without_manifest":
            (ws / "r" / "run.json").unlink()
        elif kind == "frozen_target_run":
            _freeze(ws / "r", True)
        return str(ws / "r")
    if kind == "study_folder":
        (ws / "r").mkdir()
        (ws / "r" / "study.json").write_text('{"format": 1}')
        return str(ws / "r")
    if kind == "dot":
        return "."
    if kind == "dotdot":
        return ".."
    if kind == "empty_string":
        return ""
    if kind == "long_name":
        return str(ws / ("x" * 300))
    if kind == "odd_name":
        return str(ws / "r é -- 'q' \"d\" ;$(x)")
    if kind == "frozen_parent":
        (ws / "locked").mkdir()
        _freeze(ws / "locked", True)
        return str(ws / "locked" / "r")
    raise AssertionError(kind)


def _snapshot(ws):
    """Every file and link under ws, with its content: what must survive."""
    snap = {}
    for p in sorted(ws.rglob("*")):
        if p.is_symlink():
            snap[str(p)] = ("link", os.readlink(p))
        elif p.is_file():
            snap[str(p)] = ("file", p.read_bytes())
        elif p.is_dir():
            snap[str(p)] = ("dir", None)
    return snap


def _cli(args):
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            rc = main(args)
        except SystemExit as e:  # argparse's own usage errors
            rc = e.code
    return rc, err.getvalue()


def _act(action, target, cwd):
    """Do it; return (succeeded, traceback text or None)."""
    cfg = saggriac.Config.from_preset("exp1", **TINY)
    try:
        if action in ("cli_run", "cli_run_overwrite"):
            rc, err = _cli(["run", *TINY_CLI, "--out", target, *(["--overwrite"] if action.endswith("overwrite") else [])])
            if rc not in (0, 2) or (rc == 2 and "saggriac: error:" not in err and "usage:" not in err):
                return False, f"exit {rc}: {err}"
            return rc == 0, None
        if action in ("api_run", "api_run_overwrite"):
            saggriac.run(cfg, 1, out_dir=target, overwrite=action.endswith("overwrite"))
        elif action == "cli_resume":
            rc, err = _cli(["run", "--resume", target, "--no-progress"])
            if rc not in (0, 2):
                return False, f"exit {rc}: {err}"
            return rc == 0, None
        elif action == "load":
            saggriac.RunResult.load(target)
        elif action == "study":
            study = saggriac.Study(base=cfg, conditions=("sagg_riac",), seeds=(0,))
            saggriac.run_study(study, target, n_workers=1, progress=False)
        elif action == "two_runs":
            errors, wins = [], []

            def one(seed):
                try:
                    saggriac.run(cfg.replace(n_steps=3000), seed, out_dir=target)
                    wins.append(seed)
                except SaggriacError:
                    pass
                except BaseException as e:  # noqa: BLE001 - the property is about these
                    errors.append(repr(e))

            threads = [threading.Thread(target=one, args=(s,)) for s in (1, 2)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            if errors:
                return False, errors[0]
            if len(wins) > 1:
                return False, "two runs on one target both succeeded"
            return bool(wins), None
        return True, None
    except SaggriacError:
        return False, None
    except Exception as e:  # noqa: BLE001
        return False, f"{type(e).__name__}: {e}"


@FUZZ
@given(st.sampled_from(TARGETS), st.sampled_from(ACTIONS), st.sampled_from(DAMAGE), st.randoms(use_true_random=False))
def test_nothing_is_lost_and_every_failure_is_a_saggriac_error(tmp_path_factory, template, kind, action, damage, rng):
    if kind.startswith("frozen") and not CAN_FREEZE:
        kind = "user_dir"  # read-only places need root's chattr here; the rest still runs
    ws = tmp_path_factory.mktemp("ws")
    cwd = ws / "cwd" / "inner"
    cwd.mkdir(parents=True)
    old_cwd = os.getcwd()
    os.chdir(cwd)
    frozen = [p for p in (ws / "locked", ws / "r") if kind.startswith("frozen")]
    try:
        target = _setup(ws, kind, damage, rng, template)
        before = _snapshot(ws)
        ok, trace = _act(action, target, cwd)
    finally:
        os.chdir(old_cwd)
        for p in frozen:
            if p.exists():
                _freeze(p, False)
    COUNTS[f"{kind}/{action}"] = COUNTS.get(f"{kind}/{action}", 0) + 1
    assert trace is None, f"{kind} / {action}: {trace}"
    after = _snapshot(ws)
    tpath = Path(target) if target not in ("", ".", "..") else None
    replaced = ok and action in ("cli_run_overwrite", "api_run_overwrite")
    for path, what in before.items():
        inside_target = tpath is not None and (path == str(tpath) or path.startswith(str(tpath) + os.sep))
        if inside_target and kind in ("finished_run", "damaged_run") and replaced:
            continue  # the one thing overwrite may replace: a saggriac run holding only its own files
        assert after.get(path) == what, f"{kind} / {action}: {path} changed or vanished"
    # A study folder keeps its own .lock (documented); nothing else temporary may stay.
    leftovers = [p for p in after if p.endswith(".tmp") or (p.endswith(".lock") and not (action == "study" and p.endswith(os.sep + ".lock"))) or ".tmp" + os.sep in p]
    assert not leftovers, f"{kind} / {action}: {leftovers}"
    if ok and action in ("cli_run", "cli_run_overwrite", "api_run", "api_run_overwrite", "two_runs"):
        assert storage.run_damage(tpath) is None
        assert not checkpoint_dir(tpath).exists()


def test_report_counts():
    if COUNTS:
        print(f"storage fuzz cases: {sum(COUNTS.values())} over {len(COUNTS)} target/action pairs")
