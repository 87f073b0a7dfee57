"""The evidence runner (benchmarks/evidence.py) on a tiny protocol over cheap bench tasks (progress
niches, a box and a task list): it runs the protocol's seeds, resumes a killed study with the same
rows, refuses a protocol it cannot run, and its analysis agrees with a hand computation."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from tests import benchmark_scripts

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "evidence.py"
ENV = {**os.environ, "TQDM_DISABLE": "1"}
#: Columns that are the same whenever a run is made again (not its times or commit).
SAME = ["task", "learner", "teacher", "seed", "budget", "final", "area"]


def protocol(**change):
    p = {
        "study": "tiny",
        "question": "Does RIAC beat random on the niches?",
        "registered": {"date": "2026-12-07", "commit": "test"},
        "tasks": ["niches-0", "niches-cells"],
        "teachers": ["random", "oracle", "riac"],
        "budget": {"niches-0": 400, "niches-cells": 300},
        "scorings": 4,
        "pilot": {"seeds": "100-101", "teachers": ["random"]},
        "report": {"niches-0": "900-903", "niches-cells": "910-912"},
        "rule": {"primary": "final", "alpha": 0.05, "correction": "holm", "meaningful": {"d_z": 0.75}, "baseline": "random"},
    }
    p.update(change)
    return p


def write(root, p):
    (root / p["study"]).mkdir(parents=True, exist_ok=True)
    (root / p["study"] / "protocol.json").write_text(json.dumps(p))
    return root / p["study"]


def run(root, *args):
    return subprocess.run([sys.executable, str(SCRIPT), "--study", "tiny", "--root", str(root), *args], capture_output=True, text=True, timeout=600, env=ENV)


def test_a_tiny_study_runs_its_seeds_resumes_after_a_kill_and_reanalyses(tmp_path, monkeypatch):
    out = write(tmp_path, protocol())
    done = run(tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    runs = pd.read_csv(out / "runs.csv")
    # niches-0 is a box: three teachers on seeds 900-903; niches-cells a task list, which RIAC
    # (a box teacher) does not take: random and the oracle on 910-912.
    assert sorted(zip(runs["task"], runs["teacher"], runs["seed"])) == sorted([("niches-0", t, s) for s in range(900, 904) for t in ("random", "oracle", "riac")] + [("niches-cells", t, s) for s in range(910, 913) for t in ("random", "oracle")])
    assert set(runs["budget"]) == {400, 300} and runs["final"].between(0, 1).all() and (runs["cpu_seconds"] > 0).all()
    # Each row names the CPU's kind it was made on (deep-RL runs agree to the bit only on one kind).
    from saggriac.runs.resources import cpu_kind

    assert set(runs["machine"]) == {cpu_kind()}
    curves = pd.read_csv(out / "curves.csv")
    assert sorted(curves.loc[curves["task"] == "niches-0", "step"].unique()) == [100, 200, 300, 400]
    # The runner's row is the bench's own run of the same seed and budget (the same task class,
    # guarded teacher and seed derivation).
    from saggriac.bench import TASKS, TeacherSpec, run_one
    from saggriac.bench.runner import Job

    monkeypatch.setattr(TASKS["niches-0"], "budgets", dict(TASKS["niches-0"].budgets, standard=400))
    monkeypatch.setattr(TASKS["niches-0"], "points", 4)
    bench = run_one(Job("niches-0", "standard", TeacherSpec("riac"), 902))["row"]
    mine = runs[(runs["task"] == "niches-0") & (runs["teacher"] == "riac") & (runs["seed"] == 902)].iloc[0]
    assert (mine["final"], mine["area"]) == (bench["final"], bench["area"])
    # The oracle opens the chain of niches faster than random on every seed.
    w = runs[runs["task"] == "niches-0"].pivot(index="seed", columns="teacher", values="final")
    assert (w["oracle"] > w["random"]).all()
    text = (out / "results.md").read_text()
    assert "12 of the protocol's 12 runs done" in text and "Interim" not in text and (out / "evidence.png").stat().st_size > 5_000

    # Killed after writing a run's curves but not its row, and after two earlier runs: the rerun
    # makes exactly those three runs again and ends with the same rows.
    full_runs, full_curves = runs, curves
    cut = runs.iloc[:-2]
    cut.to_csv(out / "runs.csv", index=False)
    again = run(tmp_path)
    assert again.returncode == 0 and "2 runs to do, 16 already" in again.stderr
    after = pd.read_csv(out / "runs.csv")
    key = ["task", "teacher", "seed"]
    pd.testing.assert_frame_equal(after[SAME].sort_values(key).reset_index(drop=True), full_runs[SAME].sort_values(key).reset_index(drop=True))
    cols = ["task", "teacher", "seed", "step", "score"]
    pd.testing.assert_frame_equal(pd.read_csv(out / "curves.csv")[cols].sort_values(cols).reset_index(drop=True), full_curves[cols].sort_values(cols).reset_index(drop=True))
    nothing = run(tmp_path)
    assert nothing.returncode == 0 and "0 runs to do, 18 already" in nothing.stderr

    # --analyse recomputes the tables from runs.csv alone.
    table = pd.read_csv(out / "comparisons.csv")
    (out / "comparisons.csv").unlink()
    (out / "results.md").unlink()
    redo = run(tmp_path, "--analyse")
    assert redo.returncode == 0, redo.stderr[-3000:]
    pd.testing.assert_frame_equal(pd.read_csv(out / "comparisons.csv"), table)


def test_the_pilot_runs_its_own_seeds_in_its_own_folder(tmp_path):
    rules = {"budget": {"runs": 10, "cpu_seconds": 1e9, "step": 100, "min": 100, "max": 500}}
    out = write(tmp_path, protocol(budget={"niches-0": None, "niches-cells": None}, pilot={"seeds": "100-101", "teachers": ["random"], "budget": {"niches-0": 200, "niches-cells": 200}, "rules": rules}))
    refused = run(tmp_path)
    assert refused.returncode == 2 and "no budget for 'niches-0' yet (null): the pilot fixes it" in refused.stderr
    done = run(tmp_path, "--pilot")
    assert done.returncode == 0, done.stderr[-3000:]
    runs = pd.read_csv(out / "pilot" / "runs.csv")
    assert sorted(zip(runs["task"], runs["seed"])) == [("niches-0", 100), ("niches-0", 101), ("niches-cells", 100), ("niches-cells", 101)]
    assert set(runs["teacher"]) == {"random"} and not (out / "runs.csv").exists()
    text = (out / "pilot" / "results.md").read_text()
    assert "CPU s per 1,000 units" in text and "-> B = 500" in text  # all the compute in the world: the largest budget
    rules["budget"]["cpu_seconds"] = 0.0
    write(tmp_path, protocol(budget={"niches-0": None, "niches-cells": None}, pilot={"seeds": "100-101", "teachers": ["random"], "budget": {"niches-0": 200, "niches-cells": 200}, "rules": rules}))
    none = run(tmp_path, "--pilot", "--analyse")
    assert none.returncode == 0 and "-> B = 100" in none.stdout and "even 100 does not fit" in none.stdout


@pytest.mark.parametrize(
    "change, message",
    [
        ({"tasks": ["niches-0", "no-such-task"]}, "'tasks' of the protocol .* must be bench tasks"),
        ({"teachers": ["random", "not_a_teacher"]}, "'--teacher' parameter of saggriac bench must be a built-in teacher's name"),
        ({"budget": {"niches-0": 0, "niches-cells": 300}}, "budget of 'niches-0' .* must be an int > 0 .* Got 0"),
        ({"rule": {"primary": "final", "alpha": 0.05, "correction": "bonferroni", "meaningful": {"d_z": 0.75}, "baseline": "random"}}, "correction 'holm'"),
        ({"report": {"niches-0": "900-903"}}, "'report' of the protocol .* must have one entry per task"),
    ],
)
def test_a_protocol_it_cannot_run_is_refused_before_any_run(tmp_path, change, message):
    out = write(tmp_path, protocol(**change))
    r = run(tmp_path)
    assert r.returncode != 0 and not (out / "runs.csv").exists()
    import re

    assert re.search(message, r.stderr), r.stderr[-2000:]


def test_the_analysis_is_the_hand_computation_on_a_small_table(tmp_path):
    """Three teachers on four seeds of one task, made-up finals: each gain, t interval, p, Holm
    adjustment and verdict as computed by hand; an incomplete seed is left out of the pairing."""
    ev = benchmark_scripts.load("evidence")
    p = protocol(tasks=["niches-0"], budget={"niches-0": 400}, report={"niches-0": "900-904"}, earlier={"source": "a made-up study", "verdicts": {"niches-0": {"oracle": "helps", "riac": "hurts"}}})
    finals = {"random": [0.10, 0.20, 0.15, 0.30], "oracle": [0.50, 0.62, 0.55, 0.71], "riac": [0.12, 0.18, 0.20, 0.29]}
    rows = [dict(task="niches-0", learner="x", teacher=t, seed=900 + i, budget=400, final=v, area=v / 2, seconds=1.0, cpu_seconds=1.0, teacher_seconds=0.1, commit="abc") for t, vs in finals.items() for i, v in enumerate(vs)]
    rows.append(dict(rows[0], seed=904))  # random alone on seed 904: not a complete seed
    (tmp_path / "runs.csv").parent.mkdir(exist_ok=True)
    pd.DataFrame(rows).to_csv(tmp_path / "runs.csv", index=False)
    text = ev.analyse(p, tmp_path)
    table = pd.read_csv(tmp_path / "comparisons.csv")
    assert set(table["seeds"]) == {4} and "Interim" in text  # seeds 901-904 lack oracle and RIAC

    def hand(a, b):
        d = np.array(finals[a]) - np.array(finals[b])
        half = stats.t.ppf(0.975, 3) * d.std(ddof=1) / 2
        return d.mean(), d.mean() - half, d.mean() + half, stats.ttest_rel(finals[a], finals[b]).pvalue

    base = table[table["family"] == "against the baseline"].set_index("a")
    (go, lo_o, hi_o, po), (gr, lo_r, hi_r, pr) = hand("oracle", "random"), hand("riac", "random")
    assert base.loc["oracle", "gain"] == pytest.approx(go) and base.loc["oracle", "ci_low"] == pytest.approx(lo_o) and base.loc["oracle", "ci_high"] == pytest.approx(hi_o)
    assert base.loc["riac", "gain"] == pytest.approx(gr) and base.loc["riac", "ci_low"] == pytest.approx(lo_r) and base.loc["riac", "ci_high"] == pytest.approx(hi_r)
    # Holm over two: the smaller p times 2, the larger times 1 (but not below the first).
    small, large = sorted([po, pr])
    holm = {small: min(1.0, 2 * small), large: max(min(1.0, 2 * small), large)}
    assert base.loc["oracle", "p_holm"] == pytest.approx(holm[po]) and base.loc["riac", "p_holm"] == pytest.approx(holm[pr])
    assert base.loc["oracle", "verdict"] == ("helps" if holm[po] < 0.05 else "no difference shown")
    assert base.loc["riac", "verdict"] == "no difference shown"
    # Set against the earlier study's verdicts: RIAC's "hurts" does not hold.
    assert base.loc["riac", "earlier"] == "hurts" and base.loc["riac", "holds"] == "no"
    assert base.loc["oracle", "holds"] == ("yes" if base.loc["oracle", "verdict"] == "helps" else "no") and "Earlier verdicts: a made-up study." in text
    # The bootstrap interval holds the mean and lies within the differences' range.
    d = np.array(finals["oracle"]) - np.array(finals["random"])
    assert d.min() <= base.loc["oracle", "boot_low"] <= go <= base.loc["oracle", "boot_high"] <= d.max()
    vs = table[table["family"] == "against the oracle"]
    assert list(vs["a"]) == ["riac"] and vs["gain"].iloc[0] == pytest.approx(np.mean(np.array(finals["riac"]) - finals["oracle"]))


def test_a_complete_study_says_what_its_seeds_could_detect_at_the_spread_seen(tmp_path):
    """Once every run is in, the results give, per teacher against the baseline, the paired
    differences' SD, the smallest gain with 80 % power (Holm's first and last step) and the power
    for the registered meaningful gain: here checked against the noncentral t by hand."""
    ev = benchmark_scripts.load("evidence")
    rule = dict(protocol()["rule"], meaningful={"score": 0.2, "d_z": 0.75})
    p = protocol(tasks=["niches-0"], budget={"niches-0": 400}, report={"niches-0": "900-905"}, rule=rule)
    finals = {"random": [0.10, 0.20, 0.15, 0.30, 0.22, 0.18], "oracle": [0.50, 0.62, 0.55, 0.71, 0.40, 0.66], "riac": [0.12, 0.18, 0.20, 0.29, 0.25, 0.10]}
    rows = [dict(task="niches-0", learner="x", teacher=t, seed=900 + i, budget=400, final=v, area=v / 2, seconds=1.0, cpu_seconds=1.0, teacher_seconds=0.1, commit="abc") for t, vs in finals.items() for i, v in enumerate(vs)]
    pd.DataFrame(rows).to_csv(tmp_path / "runs.csv", index=False)
    text = ev.analyse(p, tmp_path)

    def power(n, d, alpha):
        crit = stats.t.ppf(1 - alpha / 2, n - 1)
        return stats.nct.sf(crit, n - 1, d * np.sqrt(n)) + stats.nct.cdf(-crit, n - 1, d * np.sqrt(n))

    need = [next(x for x in np.round(np.arange(0.05, 5, 0.01), 2) if power(6, x, a) >= 0.8) for a in (0.025, 0.05)]
    assert "Interim" not in text and f"What 6 seeds could detect at the spread seen (paired t-test, 80 % power: d_z {need[0]:.2f} at Holm's first step, alpha 0.05 / 2; {need[1]:.2f} at its last" in text
    for t in ("oracle", "riac"):
        sd = (np.array(finals[t]) - finals["random"]).std(ddof=1)
        row = f"| {t} | random | {sd:.3f} | {need[0] * sd:.3f} / {need[1] * sd:.3f} | {power(6, 0.2 / sd, 0.025):.2f} / {power(6, 0.2 / sd, 0.05):.2f} |"
        assert row in text, row
    # An interim analysis decides nothing, so it says nothing of what the study could detect.
    pd.DataFrame(rows[:-1]).to_csv(tmp_path / "runs.csv", index=False)
    assert "could detect" not in ev.analyse(p, tmp_path)


def test_the_sac_study_as_registered_plans_its_324_runs_dense_first_and_paired_by_seed():
    """docs/figures/evidence/sac/protocol.json reads, and its plan is the registration's: 9
    teachers on dense seeds 900-923 then sparse 950-961 at the pilot's budget, every teacher on a
    seed before the next seed (a partial study stays paired)."""
    ev = benchmark_scripts.load("evidence")
    p = ev.read_protocol(ev.ROOT / "sac" / "protocol.json")
    jobs = ev.plan(p, pilot=False)
    assert len(jobs) == 9 * (24 + 12) and {j[3] for j in jobs} == {20_000}
    assert [j[:3] for j in jobs[:10]] == [("rl-arm-sac-dense", t, 900) for t in p["teachers"]] + [("rl-arm-sac-dense", "random", 901)]
    assert {j[2] for j in jobs if j[0] == "rl-arm-sac-dense"} == set(range(900, 924)) and {j[2] for j in jobs if j[0] == "rl-arm-sac-sparse"} == set(range(950, 962))
    assert jobs.index(next(j for j in jobs if j[0] == "rl-arm-sac-sparse")) == 9 * 24
    from saggriac.bench import TASKS

    assert all(TASKS[t].budgets["full"] == p["budget"][t] for t in p["tasks"])  # the bench's full tier reruns it


def test_a_failing_teacher_is_recorded_and_the_study_goes_on(tmp_path):
    """A teacher that raises on one seed: its run goes to failures.csv with the reason, every other
    run is done, the results say so, and resuming tries that run again (and only it)."""
    (tmp_path / "flaky.py").write_text(
        "import numpy as np\n"
        "class Flaky:\n"
        "    def __init__(self, low, high, seed=0):\n"
        "        self.low, self.high, self.rng, self.n = np.asarray(low), np.asarray(high), np.random.default_rng(seed), 0\n"
        "        self.bad = seed % 2 == 0\n"
        "    def sample(self):\n"
        "        self.n += 1\n"
        "        if self.bad and self.n == 5:\n"
        "            raise RuntimeError('flaky on purpose')\n"
        "        return self.rng.uniform(self.low, self.high)\n"
        "    def update(self, goal, competence):\n"
        "        pass\n"
    )
    teacher = f"{tmp_path / 'flaky.py'}:Flaky"
    out = write(tmp_path, protocol(tasks=["niches-0"], budget={"niches-0": 200}, report={"niches-0": "900-905"}, teachers=["random", teacher]))
    done = run(tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    runs, failed = pd.read_csv(out / "runs.csv"), pd.read_csv(out / "failures.csv")
    assert len(failed) >= 1 and failed["error"].str.contains("flaky on purpose").all() and (failed["teacher"] == teacher).all()
    assert len(runs) + len(failed) == 12 and not set(zip(failed["teacher"], failed["seed"])) & set(zip(runs["teacher"], runs["seed"]))
    assert "Refused on the way" in (out / "results.md").read_text() and "Interim" in (out / "results.md").read_text()
    again = run(tmp_path)
    assert again.returncode == 0 and f"{len(failed)} runs to do, {len(runs)} already" in again.stderr


def test_a_task_of_the_studys_own_module_runs_on_two_workers(tmp_path):
    """A task registered by a module the protocol names (``modules``), not by saggriac.bench, runs
    in the workers' fresh processes too, and two workers give the rows one does."""
    (tmp_path / "mytasks.py").write_text(
        "from saggriac.bench.tasks import Niches, register\n"
        "@register\n"
        "class Mine(Niches):\n"
        "    name = 'my-niches'\n"
    )
    env = {**ENV, "PYTHONPATH": os.pathsep.join([str(tmp_path), ENV.get("PYTHONPATH", "")])}
    rows = {}
    for workers in (1, 2):
        root = tmp_path / f"w{workers}"
        out = write(root, protocol(tasks=["my-niches"], budget={"my-niches": 200}, report={"my-niches": "900-902"}, teachers=["random", "riac"], modules=["mytasks"]))
        r = subprocess.run([sys.executable, str(SCRIPT), "--study", "tiny", "--root", str(root), "--workers", str(workers)], capture_output=True, text=True, timeout=600, env=env)
        assert r.returncode == 0, r.stderr[-3000:]
        rows[workers] = pd.read_csv(out / "runs.csv")[SAME].sort_values(["teacher", "seed"]).reset_index(drop=True)
    assert len(rows[1]) == 6 and (rows[1]["task"] == "my-niches").all()
    pd.testing.assert_frame_equal(rows[1], rows[2])
