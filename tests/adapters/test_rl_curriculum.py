"""The RL curriculum study's command (docs/rl_curriculum.md) on a tiny budget: the sparse reward,
teachers given by name with the oracle, the per-run tables, resuming without rerunning, a clash
of budgets refused, and --analyse recomputing the tables from curves.csv alone. Skipped without
the SB3 extra, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tests import benchmark_scripts

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "rl_curriculum.py"
ENV = {**os.environ, "TQDM_DISABLE": "1"}


def bench():
    return benchmark_scripts.load("rl_curriculum")


def run(*args, timeout=600):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True, timeout=timeout, env=ENV)


def test_a_tiny_sparse_study_runs_resumes_and_reanalyses(tmp_path):
    out = tmp_path / "rl"
    # PPO collects 4 x 2048 steps per rollout, so a budget of 8192 is one rollout.
    args = ["--out", out, "--reward", "sparse", "--seeds", "7,8", "--steps", 8192, "--every", 4096, "--teachers", "random", "oracle"]
    done = run(*args)
    assert done.returncode == 0, done.stderr[-3000:]
    runs = pd.read_csv(out / "runs.csv")
    assert {"teacher", "seed", "reward", "final_success", "final_distance", "auc"} <= set(runs.columns)
    assert sorted(zip(runs["teacher"], runs["seed"])) == [("oracle", 7), ("oracle", 8), ("random", 7), ("random", 8)]
    assert (runs["reward"] == "sparse").all() and runs["final_success"].between(0, 1).all() and (runs["final_distance"] > 0).all()
    curves = pd.read_csv(out / "curves.csv")
    assert sorted(curves["step"].unique()) == [0, 4096, 8192]
    # The oracle asks only for goals in reach; random for goals anywhere in the box (a fifth in reach).
    assert (runs.loc[runs["teacher"] == "oracle", "final_reachable_share"] == 1.0).all()
    assert (runs.loc[runs["teacher"] == "random", "final_reachable_share"] < 0.5).all()
    text = (out / "results.md").read_text()
    assert "Interim" in text and "oracle" in text and (out / "rl_curriculum.png").stat().st_size > 10_000

    # Resuming skips what is done: nothing is run again, nothing changes.
    before = (out / "curves.csv").read_bytes()
    again = run(*args)
    assert again.returncode == 0 and "0 runs to do, 4 already" in again.stderr
    assert (out / "curves.csv").read_bytes() == before

    # Another budget in the same folder would mix incomparable runs: refused, nothing written.
    clash = run(*[x if x != 8192 else 16384 for x in args])
    assert clash.returncode != 0 and "budget" in clash.stderr and (out / "curves.csv").read_bytes() == before

    # --analyse recomputes the tables from curves.csv alone.
    (out / "runs.csv").unlink()
    (out / "results.md").unlink()
    redo = run("--out", out, "--analyse")
    assert redo.returncode == 0, redo.stderr[-3000:]
    pd.testing.assert_frame_equal(pd.read_csv(out / "runs.csv"), runs)
    assert (out / "results.md").read_text() == text


def test_a_resumed_study_writes_what_a_straight_one_does_with_the_commit_as_text(tmp_path, monkeypatch):
    """A commit hash such as 540e725 reads as a number (inf) unless read as text; a resume
    rewrites the earlier rows, so it must read them back as they were written. The runs are
    replaced by made-up curves (the bookkeeping is under test, not PPO)."""
    b = bench()

    def made_up(job):
        reward, name, seed, steps, every, threshold, code = job
        rng = np.random.default_rng([seed, len(name)])
        return [dict(reward=reward, teacher=name, seed=seed, budget=steps, threshold=threshold, step=step, success=rng.uniform(), distance=rng.uniform(0.1, 1), episodes=step // 10, reachable_share=rng.uniform(), seconds=rng.uniform(), cpu_seconds=rng.uniform(), commit=code) for step in range(0, steps + 1, every)]

    monkeypatch.setattr(b, "one_run", made_up)
    monkeypatch.setattr(b, "commit", lambda: "540e725")
    monkeypatch.setenv("TQDM_DISABLE", "1")
    study = ["--reward", "sparse", "--steps", "8192", "--every", "4096", "--teachers", "random", "oracle"]
    b.main(["--out", str(tmp_path / "straight"), *study, "--seeds", "7,8"])
    b.main(["--out", str(tmp_path / "resumed"), *study, "--seeds", "7"])
    b.main(["--out", str(tmp_path / "resumed"), *study, "--seeds", "7,8"])
    for name in ("curves.csv", "runs.csv", "comparisons.csv", "results.md"):
        assert (tmp_path / "resumed" / name).read_bytes() == (tmp_path / "straight" / name).read_bytes(), name
    for name in ("curves.csv", "runs.csv"):
        assert set(b.read_table(tmp_path / "resumed" / name)["commit"]) == {"540e725"}
        assert set(pd.read_csv(tmp_path / "resumed" / name, dtype=str)["commit"]) == {"540e725"}


def test_teachers_are_found_by_name_and_bad_names_refused(tmp_path):
    names = bench().teacher_names()
    assert {"random", "oracle", "sagg_riac", "riac", "alp_gmm", "covar_gmm"} <= set(names) and "discrete_lp" not in names
    bad = run("--out", tmp_path, "--teachers", "random", "nosuch")
    assert bad.returncode != 0 and "nosuch" in bad.stderr and "sagg_riac" in bad.stderr
    bad = run("--out", tmp_path, "--reward", "shaped")
    assert bad.returncode != 0 and "shaped" in bad.stderr


def test_the_oracle_draws_uniformly_from_the_reachable_set():
    b = bench()
    teacher = b.make_teacher("oracle", 3)
    goals = np.array([teacher.sample() for _ in range(4000)])
    radius = np.linalg.norm(goals, axis=1)
    assert radius.max() <= 1.0  # the arm's reach
    # Uniform in the disc: the share within radius r is r^2.
    assert abs(np.mean(radius <= 0.5) - 0.25) < 0.03
    # Every point of the disc is reachable by the arm itself (3 equal links, joints of +-pi).
    from saggriac.bodies.environments import PlanarArm

    arm = PlanarArm(n_joints=3, arm_length=1.0, joint_limit=np.pi)
    tips = np.array([arm.forward(t) for t in np.random.default_rng(0).uniform(-np.pi, np.pi, (4000, 3))])
    assert np.linalg.norm(tips, axis=1).max() <= 1.0 + 1e-9 and np.mean(np.linalg.norm(tips, axis=1) < 0.2) > 0.01
    again = b.make_teacher("oracle", 3)
    assert np.array_equal(goals[:5], [again.sample() for _ in range(5)])


def test_the_sparse_reward_reaches_the_student():
    b = bench()
    env = b.make_env("sparse", 0.2)
    env.reset(options={"goal": np.array([1.8, 1.8])})
    rewards = {env.step(env.action_space.sample())[1] for _ in range(10)}
    assert rewards == {-1.0}
    dense = b.make_env("dense", 0.2)
    dense.reset(options={"goal": np.array([1.8, 1.8])})
    assert dense.step(dense.action_space.sample())[1] < -1.0


def test_the_committed_tables_and_the_pages_tables_recompute_from_curves(tmp_path):
    """docs/figures/rl_curriculum holds the study's curves; --analyse on them alone gives the
    committed runs.csv and comparisons.csv, and every table row under the page's results."""
    root = Path(__file__).resolve().parents[2]
    figures = root / "docs" / "figures" / "rl_curriculum"
    (tmp_path / "curves.csv").write_bytes((figures / "curves.csv").read_bytes())
    text = bench().analyse(tmp_path)
    for name in ("runs.csv", "comparisons.csv"):
        pd.testing.assert_frame_equal(pd.read_csv(tmp_path / name), pd.read_csv(figures / name), rtol=1e-9, obj=name)
    page = (root / "docs" / "rl_curriculum.md").read_text()
    results = page[page.index("## Results of the second study") : page.index("### Diagnostics")]
    rows = [line for line in results.splitlines() if line.startswith("| ")]
    assert len(rows) >= 20
    missing = [row for row in rows if row not in text]
    assert not missing, f"rows of the page that --analyse does not give: {missing[:3]}"
    # The guide's deep-RL table quotes the primary gains and CIs: each as --analyse gives it.
    guide = (root / "docs" / "choosing_a_teacher.md").read_text()
    table = "\n".join(line for line in guide[guide.index("## Deep RL") :].splitlines() if line.startswith("| "))  # the PPO table (the SAC study's gains are prose)
    quoted = re.findall(r"([+-]\d\.\d{3}) (\[[+-]\d\.\d{3}, [+-]\d\.\d{3}\])", table)
    assert len(quoted) == 16
    absent = [q for q in quoted if f"| {q[0]} | {q[1]} |" not in text]
    assert not absent, f"gains in docs/choosing_a_teacher.md that --analyse does not give: {absent}"


def test_a_study_of_its_own_registers_its_seeds_and_teachers_in_protocol_json(tmp_path):
    """A replication's report runs are data (protocol.json): --analyse counts them and marks the
    numbers interim until they are all done."""
    import json

    root = Path(__file__).resolve().parents[2]
    curves = pd.read_csv(root / "docs" / "figures" / "rl_curriculum" / "curves.csv", dtype={"commit": str})
    mine = curves[(curves.reward == "dense") & curves.seed.isin([500, 501]) & curves.teacher.isin(["random", "spdl", "alp_gmm"])]
    mine.to_csv(tmp_path / "curves.csv", index=False)
    for seeds, interim in (("500-501", False), ("500-502", True)):
        (tmp_path / "protocol.json").write_text(json.dumps({"report": {"dense": {"seeds": seeds, "teachers": ["random", "spdl", "alp_gmm"]}}}))
        text = bench().analyse(tmp_path)
        want = 3 * (len(range(int(seeds[:3]), int(seeds[-3:]) + 1)))
        assert f"- dense: 6 of the protocol's {want} runs done (random, spdl, alp_gmm x seeds {seeds}" in text
        assert ("**Interim" in text) == interim


def test_a_protocol_with_free_joints_runs_them_and_counts_goal_blind_policies(tmp_path):
    """The free-joint check's protocol changes the arm (task.joints = "free"): its runs record
    the spread of the final tips, --analyse counts the goal-blind policies instead of the fold,
    and a protocol naming any other task option is refused."""
    import json

    out = tmp_path / "free"
    out.mkdir()
    (out / "protocol.json").write_text(json.dumps({"task": {"joints": "free"}, "report": {"sparse": {"seeds": "9", "teachers": ["random"]}}}))
    done = run("--out", out, "--reward", "sparse", "--steps", 8192, "--every", 4096, "--teachers", "random")
    assert done.returncode == 0, done.stderr[-3000:]
    curves = pd.read_csv(out / "curves.csv")
    assert (curves["joints"] == "free").all() and (curves["tip_spread"] >= 0).all()
    runs = pd.read_csv(out / "runs.csv")
    assert runs["final_tip_spread"].iloc[0] == curves["tip_spread"].iloc[-1]
    blind = int(runs["final_tip_spread"].iloc[0] < 1e-6)
    assert f"(goal-blind; free joints cannot fold): random {blind}/1." in (out / "results.md").read_text()
    (out / "protocol.json").write_text(json.dumps({"task": {"joints": "free", "links": 4}, "report": {"sparse": {"seeds": "9", "teachers": ["random"]}}}))
    bad = run("--out", out, "--reward", "sparse", "--steps", 8192, "--every", 4096, "--teachers", "random")
    assert bad.returncode != 0 and "the task options ['links'] are unknown" in bad.stderr


def test_the_free_joint_section_recomputes_from_its_committed_curves(tmp_path):
    """docs/rl_curriculum.md's free-joint results: each teacher's gain, CI and Holm p as --analyse
    gives them from free_joints/curves.csv, the limited arm's beside them as the second study's
    tables give them, and the nearly goal-blind counts from the recomputed runs table."""
    root = Path(__file__).resolve().parents[2]
    figures = root / "docs" / "figures" / "rl_curriculum"
    for name in ("curves.csv", "protocol.json"):
        (tmp_path / name).write_bytes((figures / "free_joints" / name).read_bytes())
    text = bench().analyse(tmp_path)
    assert text == (figures / "free_joints" / "results.md").read_text()
    limited = (figures / "results.md").read_text()
    page = (root / "docs" / "rl_curriculum.md").read_text()
    section = page[page.index("**Results: every verdict survives**") : page.index("## The first study")]
    rows = re.findall(r"^\| ([A-Za-z -]+) \| ([+-]\d\.\d{3}) (\[[+-]\d\.\d{3}, [+-]\d\.\d{3}\]) \| ([\d.e-]+) \| ([a-z ]+) \| ([+-]\d\.\d{3}) (\[[+-]\d\.\d{3}, [+-]\d\.\d{3}\]), ([a-z ]+) \| (yes|no) \|$", section, re.M)
    assert len(rows) == 8
    for name, gain, ci, p_holm, verdict, l_gain, l_ci, l_verdict, survives in rows:
        name = name.replace("Goal GAN", "GoalGAN")
        assert re.search(rf"\| final_distance \| {name} \| random \| {re.escape(gain)} \| {re.escape(ci)} \| [^|]+ \| [^|]+ \| {re.escape(p_holm)} \| [^|]+ \| {verdict} \|", text), name
        assert re.search(rf"\| final_distance \| {name} \| random \| {re.escape(l_gain)} \| {re.escape(l_ci)} \| .* \| {l_verdict} \|", limited), name
        assert (survives == "yes") == (verdict == l_verdict)
    runs = pd.read_csv(tmp_path / "runs.csv")
    blind = runs.assign(b=runs.final_tip_spread < 0.2).groupby("teacher").b.sum()
    names = {"random": "random", "oracle": "oracle", "SAGG-RIAC": "sagg_riac", "RIAC": "riac", "ALP-GMM": "alp_gmm", "Covar-GMM": "covar_gmm", "ADR": "adr", "SPDL": "spdl", "Goal GAN": "goal_gan"}
    table = re.findall(r"^\| ([A-Za-z -]+) \| (\d+)/12 \| (\d+)/12 \|$", section, re.M)
    assert {names[k]: int(v) for k, v, _ in table} == blind.to_dict()
    sparse = limited[limited.index("## sparse reward") :]
    folded = sparse[sparse.index("folds the arm onto its joint limits") :].splitlines()[0]
    for k, _, f in table:
        assert f"{k.replace('Goal GAN', 'GoalGAN')} {f}/12" in folded, k
    spread = runs.final_tip_spread
    assert not ((spread > 0.16) & (spread < 0.24)).any()  # the gap the page names
