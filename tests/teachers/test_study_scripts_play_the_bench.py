"""The toy and niche study scripts (benchmarks/toy_tasks.py, teacher_niches.py) play the bench's
tasks through the bench's own loop (BenchTask.play) and watch where the goals land: a run must be
the one a plain loop over the same task and teacher gives, with the seeds of the committed runs."""

from __future__ import annotations

import numpy as np
import pytest

from tests import benchmark_scripts


@pytest.fixture(scope="module")
def toy():
    return benchmark_scripts.load("toy_tasks")


@pytest.fixture(scope="module")
def niches():
    return benchmark_scripts.load("teacher_niches")


def plain_toy_run(toy, name, space, seed, every):
    # The loop the script had before it called the bench: ask, note the place, attempt, tell.
    make, cells = toy.TEACHERS[name]
    env = toy.HypercubeUnlock(**toy.SPACES[space])
    teacher = make(env, seed)
    placed, scores = dict.fromkeys(toy.PLACES, 0), []
    for t in range(1, toy.BUDGET[space] + 1):
        if cells:
            c = teacher.sample_task()
            placed[env.where(c)] += 1
            teacher.update(c, env.attempt_cell(c))
        else:
            g = teacher.sample()
            placed[env.where(env.cell(g))] += 1
            teacher.update(g, env.attempt(g))
        if t % every == 0:
            scores.append(env.score())
    return placed, scores


@pytest.mark.parametrize("name", ["sagg_riac", "plr", "alp_gmm"])
def test_a_toy_run_is_the_plain_loops_run(toy, monkeypatch, name):
    monkeypatch.setitem(toy.BUDGET, "2d-reach", 1_200)
    run, curve, modes = toy.one_run((name, "2d-reach", 4, 200))
    placed, scores = plain_toy_run(toy, name, "2d-reach", 4, 200)
    assert [c["score"] for c in curve] == scores and [c["goals"] for c in curve] == list(range(200, 1_201, 200))
    assert {p: run[p] * 1_200 for p in toy.PLACES} == pytest.approx(placed, abs=1e-9)
    assert run["final"] == scores[-1] and run["auc"] == pytest.approx(np.mean(scores), abs=0)


def test_a_toy_every_that_does_not_divide_the_budget_is_refused(toy):
    with pytest.raises(ValueError, match="--every must divide the budget of every space; got 300 for 2d"):
        toy.one_run(("random", "2d", 0, 300))


@pytest.mark.parametrize("name", ["random", "discrete_lp", "riac"])
def test_a_niche_run_is_the_plain_loops_run(niches, name):
    run, curve = niches.one_run((name, 4, 3, 1_000, 250))
    env_seq, teacher_seq = np.random.SeedSequence(3).spawn(2)
    env = niches.ProgressNiches(int(env_seq.generate_state(1, np.uint64)[0] >> 1), distractors=4)
    teacher = niches.make_teacher(name, env, int(teacher_seq.generate_state(1, np.uint64)[0]))
    kinds, counts, points = [env.kind(c) for c in range(env.n_cells)], {}, []
    for t in range(1, 1_001):
        if name in niches.TASK_LISTS:
            cell = teacher.sample_task()
            teacher.update(cell, env.attempt(env.centre(cell)))
        else:
            g = teacher.sample()
            cell = env.cell(g)
            teacher.update(g, env.attempt(g))
        counts[kinds[cell]] = counts.get(kinds[cell], 0) + 1
        if t % 250 == 0:
            points.append((t, env.mastery(), env.unlocked))
    assert [(c["update"], c["mastery"], c["unlocked"]) for c in curve] == points
    assert run["final"] == points[-1][1] and run["unlocked"] == points[-1][2]
    assert (run["share_noisy"], run["share_impossible"]) == (counts.get("noisy", 0) / 1_000, counts.get("impossible", 0) / 1_000)


def test_a_niche_every_that_does_not_divide_the_updates_is_refused(niches):
    with pytest.raises(ValueError, match="--every must divide --updates; got 300 and 1000"):
        niches.one_run(("random", 0, 0, 1_000, 300))
