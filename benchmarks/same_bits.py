"""Same bits: record, then check, that a change of the code leaves every result unchanged.

    python benchmarks/same_bits.py --record benchmarks/same_bits_reference.json
    python benchmarks/same_bits.py --check benchmarks/same_bits_reference.json [--only exp1]

Every case is a short run written to disk. For each one the script keeps the sha256 of each of the
four Parquet tables (metrics, goals, attempts, regions), a hash of their decoded contents, and
every number of run.json except wall times, timers, version and git commit. `--check` reruns
the cases, prints one line per case and exits non-zero on any difference. A refactoring that
moves code without touching the maths must pass it byte for byte.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import importlib.util
import json
import math
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

import saggriac
from saggriac import _core
from saggriac.config import CONDITIONS

TABLES = ("metrics", "goals", "attempts", "regions")
# Keys of run.json that measure the machine, not the run ("checksum" hashes run.json itself, wall
# times included); "tables" holds the sizes and SHA-256 of the four tables, which are compared
# through their own hashes below.
SKIP = ("wall_seconds", "git_commit", "version", "python", "tables", "checksum")
# Which exact neighbour index ran: an implementation choice (every index returns the same
# neighbours), so a reference recorded with the k-d tree still checks the block index.
SKIP_PATHS = ("config.knn_index",)
# What was added after the reference: checked to be new, not compared. The cases run with the
# forward-model test configurations the reference had ("uniform"); the least-norm IK ones
# (issue 14) change the prediction error by design.
# Configuration keys added since, with the value that means what the reference ran.
ADDED_VALUES = {"config.test_configs": "uniform", "config.timeout_in_exploration": False, "config.competence": "relative", "config.actuator_candidates": 0, "config.chain": None, "config.teacher": "own", "config.interest_divisor": "window", "config.exploration_trigger": "executed", "config.mode3": "lowest_competence", "config.mode3_sigma": (0.05).hex()}
ADDED_PREFIXES = ("test_set.", "time_budget.", "scale.", "steps.", "profile.trigger_")
LENGTHS = ("v", "eps_max", "eval_tolerance")
ADDED_COLUMNS = {"metrics": ("dx_error",)}

SMALL: dict[str, Any] = dict(n_test_goals=30, n_test_configs=30, n_evals=8)
# The behaviour the reference had, where later versions changed a default (older versions,
# recording a reference, lack the keys).
for _key, _value in (("test_configs", "uniform"), ("actuator_candidates", 0), ("babble_step", 0.01), ("competence", "relative"), ("interest_divisor", "window"), ("eps_max", 0.25)):
    if _key in {f.name for f in dataclasses.fields(saggriac.Config)}:
        SMALL[_key] = _value
STEPS = {"exp1": 15000, "exp2": 30000, "explauto": 10000, "arm3d": 12000}


def _example(name: str) -> Any:
    """A module of examples/, whose Python environment is one of the cases."""
    path = Path(__file__).resolve().parents[1] / "examples" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class NoisySensorArm(_example("python_environment").NoisySensorArm):
    """The example's environment, named here as the reference's run.json names it."""


class CycleGoals:
    """A user's goal selector: a seeded uniform draw that favours goals it failed at."""

    def __init__(self, low, high, seed: int) -> None:
        self.low, self.high = np.asarray(low, float), np.asarray(high, float)
        self.rng = np.random.default_rng(seed)
        self.failed: list[np.ndarray] = []

    def sample(self) -> np.ndarray:
        if self.failed and self.rng.random() < 0.3:
            return self.failed.pop()
        return self.rng.uniform(self.low, self.high)

    def update(self, goal, competence) -> None:
        if competence < -0.5:
            self.failed.append(np.array(goal, float))


def numbers(d: Any, path: str = "") -> dict[str, Any]:
    """Every number (and bool/str of the config) of run.json, flattened, machine times left out."""
    out: dict[str, Any] = {}
    if isinstance(d, dict):
        for k, v in d.items():
            if k in SKIP or k.startswith("time_") or (f"{path}.{k}" if path else k) in SKIP_PATHS:
                continue
            out.update(numbers(v, f"{path}.{k}" if path else k))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            out.update(numbers(v, f"{path}[{i}]"))
    elif isinstance(d, float):
        # Bits, not a decimal rounding (NaN and -0.0 included).
        out[path] = "nan" if math.isnan(d) else float.hex(d)
    else:
        out[path] = d
    return out


def table_hashes(run_dir: Path) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for t in TABLES:
        f = run_dir / f"{t}.parquet"
        table = pq.read_table(f)
        added = [c for c in ADDED_COLUMNS.get(t, ()) if c in table.column_names]
        if added:
            # The file holds columns the reference did not have: compare the others' contents.
            table = table.drop_columns(added)
        else:
            out[f"{t}.file"] = hashlib.sha256(f.read_bytes()).hexdigest()
        # Unsigned counters became int64 in saggriac 0.4 (they wrapped around on subtraction):
        # the values are compared as int64 either way.
        for i, field in enumerate(table.schema):
            if pa.types.is_unsigned_integer(field.type):
                table = table.set_column(i, field.name, table.column(i).cast(pa.int64()))
        # Column names, types and bytes; not the schema's metadata, which lists every column.
        h = hashlib.sha256(str(table.schema.remove_metadata()).encode())
        for name, col in zip(table.column_names, table.columns):
            h.update(name.encode())
            h.update(col.to_numpy(zero_copy_only=False).tobytes())
        out[f"{t}.content"] = h.hexdigest()
        out[f"{t}.rows"] = table.num_rows
    return out


def summary(run_dir: Path) -> dict[str, Any]:
    manifest = json.loads((run_dir / "run.json").read_text())
    flat = numbers(manifest)
    # Length parameters left unset follow the reach (from saggriac 0.4); run.json's "scale"
    # holds the values the run used, which are what the reference's config recorded.
    for k in LENGTHS:
        if flat.get(f"config.{k}", 0) is None:
            flat[f"config.{k}"] = flat[f"scale.{k}"]
    return {"tables": table_hashes(run_dir), "run.json": flat}


def plain(preset: str, seed: int = 0, **kw: Any) -> Callable[[Path], None]:
    def go(out: Path) -> None:
        cfg = saggriac.Config.from_preset(preset, **{"n_steps": STEPS[preset], **SMALL, **kw})
        saggriac.run(cfg, seed=seed, out_dir=out)

    return go


def with_parts(environment: bool, selector: bool, seed: int = 3, **kw: Any) -> Callable[[Path], None]:
    def go(out: Path) -> None:
        cfg = saggriac.Config.from_preset("exp1", **{"n_steps": 4000, **SMALL, **kw})
        extra: dict[str, Any] = {}
        if environment:
            extra["environment"] = NoisySensorArm(0.05)
        if selector:
            extra["goal_selector"] = CycleGoals(cfg.goal_low, cfg.goal_high, 11)
        saggriac.run(cfg, seed=seed, out_dir=out, **extra)

    return go


def checkpointed(preset: str, seed: int = 5, **kw: Any) -> Callable[[Path], None]:
    """run(checkpoint_every=...) to the end, which stops and checkpoints on the way."""

    def go(out: Path) -> None:
        cfg = saggriac.Config.from_preset(preset, **{"n_steps": STEPS[preset], **SMALL, "n_evals": 15, **kw})
        saggriac.run(cfg, seed=seed, out_dir=out, checkpoint_every=2000)

    return go


def resumed(preset: str, seed: int = 6, **kw: Any) -> Callable[[Path], None]:
    """A run interrupted after its checkpoint at step ~4000, then saggriac.resume."""

    def go(out: Path) -> None:
        cfg = saggriac.Config.from_preset(preset, **{"n_steps": STEPS[preset], **SMALL, "n_evals": 15, **kw})
        # One thread: it stops right after the evaluation at step 4000, as the reference did.
        learner = saggriac.Learner(cfg, seed=seed, threads=1)
        learner.run(until=4000)
        learner.save_checkpoint(out, checkpoint_every=1000)
        del learner
        saggriac.resume(out)

    return go


def cases() -> dict[str, Callable[[Path], None]]:
    c: dict[str, Callable[[Path], None]] = {}
    for preset in STEPS:
        for cond in CONDITIONS:
            c[f"{preset}/{cond}"] = plain(preset, condition=cond)
    c["exp1/sagg_riac/noise"] = plain("exp1", seed=1, motor_noise=0.01, sensor_noise=0.02)
    c["exp1/actuator_riac/noise"] = plain("exp1", seed=1, condition="actuator_riac", motor_noise=0.01, sensor_noise=0.02)
    c["explauto/sagg_riac/noise"] = plain("explauto", seed=1, motor_noise=0.01, sensor_noise=0.02)
    c["exp1/sagg_riac/body_change"] = plain("exp1", seed=2, body_change_step=7000, body_change_link=3, body_change_length=5.0)
    c["explauto/sagg_riac/body_change"] = plain("explauto", seed=2, body_change_step=5000, body_change_link=3, body_change_length=5.0)
    c["arm3d/sagg_riac/body_change"] = plain("arm3d", seed=2, body_change_step=6000, body_change_link=1, body_change_length=2.0)
    c["explauto/sagg_riac/refine"] = plain("explauto", seed=4, episodic_refine=True, condition="sagg_riac")
    c["exp1/sagg_riac/brute_force"] = plain("exp1", seed=4, knn_index="brute_force", warm_start_recent=0)
    c["exp1/sagg_riac/python_environment"] = with_parts(True, False)
    c["exp1/sagg_random/python_environment"] = with_parts(True, False, condition="sagg_random")
    c["exp1/sagg_riac/user_selector"] = with_parts(False, True)
    c["exp1/sagg_riac/python_environment+user_selector"] = with_parts(True, True)
    c["explauto/sagg_riac/user_selector"] = lambda out: saggriac.run(
        saggriac.Config.from_preset("explauto", n_steps=2000, **SMALL), seed=3, out_dir=out, goal_selector=CycleGoals((-50, -50), (50, 50), 12)
    )
    c["exp1/sagg_riac/checkpoint_every"] = checkpointed("exp1")
    c["exp1/actuator_riac/checkpoint_every"] = checkpointed("exp1", condition="actuator_riac")
    c["exp1/sagg_riac/resume"] = resumed("exp1")
    c["exp1/actuator_random/resume"] = resumed("exp1", condition="actuator_random")
    c["explauto/actuator_riac/resume"] = resumed("explauto", condition="actuator_riac", motor_noise=0.01)
    c["arm3d/sagg_riac/resume"] = resumed("arm3d", body_change_step=3000, body_change_link=2, body_change_length=4.0)
    return c


def run_cases(only: str | None) -> dict[str, Any]:
    out: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, go in cases().items():
            if only and only not in name:
                continue
            t0 = time.perf_counter()
            d = Path(tmp) / name.replace("/", "_").replace("+", "_")
            go(d)
            out[name] = summary(d)
            print(f"  ran {name:50s} {time.perf_counter() - t0:6.1f} s", file=sys.stderr, flush=True)
    return out


def diff(ref: dict[str, Any], got: dict[str, Any]) -> list[str]:
    bad = []
    for part in ("tables", "run.json"):
        a, b = ref[part], got[part]
        for k in sorted(set(a) | set(b)):
            if k in SKIP_PATHS or (k not in a and k.startswith(ADDED_PREFIXES)):
                continue
            if k not in a and k in ADDED_VALUES:
                if b.get(k) != ADDED_VALUES[k]:
                    bad.append(f"{part}:{k}: new key with {b.get(k)!r}, not the reference's behaviour {ADDED_VALUES[k]!r}")
                continue
            if part == "tables" and k.endswith(".file") and k not in b:
                continue  # a table with added columns: its content hash decides
            if a.get(k) != b.get(k):
                bad.append(f"{part}:{k}: {a.get(k)!r} -> {b.get(k)!r}")
    return bad


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--record", metavar="FILE")
    g.add_argument("--check", metavar="FILE")
    p.add_argument("--only", default=None, help="run only the cases whose name contains this")
    p.add_argument("--contents-only", action="store_true", help="compare the tables' decoded contents, not their files (for a change of how the files are written)")
    a = p.parse_args()
    if a.record:
        res = run_cases(a.only)
        meta = {"version": saggriac.__version__, "git_commit": _core.GIT_COMMIT}
        Path(a.record).write_text(json.dumps({"recorded_with": meta, "cases": res}, indent=1, sort_keys=True) + "\n")
        print(f"recorded {len(res)} cases to {a.record} ({meta['git_commit'][:12]})")
        return 0
    ref = json.loads(Path(a.check).read_text())
    got = run_cases(a.only)
    n_bad = 0
    print(f"{'case':52s} {'tables':>7s} {'run.json':>9s}  result")
    for name, r in got.items():
        if name not in ref["cases"]:
            print(f"{name:52s} {'-':>7s} {'-':>9s}  NOT IN REFERENCE")
            n_bad += 1
            continue
        bad = diff(ref["cases"][name], r)
        if a.contents_only:
            bad = [line for line in bad if not line.startswith("tables:") or ".file:" not in line]
        print(f"{name:52s} {sum(k.endswith('.rows') for k in r['tables']):>7d} {len(r['run.json']):>9d}  {'same' if not bad else 'DIFFERENT'}")
        for line in bad[:8]:
            print(f"    {line}")
        n_bad += bool(bad)
    missing = [n for n in ref["cases"] if n not in got and not (a.only and a.only not in n)]
    for n in missing:
        print(f"{n:52s} missing from this run")
    n_bad += len(missing)
    print(f"{len(got) - n_bad} of {len(got) + len(missing)} cases the same bits as {ref['recorded_with']['git_commit'][:12]}")
    return 1 if n_bad else 0


if __name__ == "__main__":
    sys.exit(main())
