"""The hypercube-unlocking benchmark's task (benchmarks/toy_tasks.py), including the space where
most of the box is impossible: what the docs say about it must hold."""

from __future__ import annotations


import numpy as np
import pytest

from tests import benchmark_scripts



@pytest.fixture(scope="module")
def toy():
    return benchmark_scripts.load("toy_tasks")


def _master_everything_possible(env) -> None:
    # Sweeping every cell `need` times, as often as there are cells, unlocks along every path.
    for _ in range(env.bins * env.relevant):
        for c in range(env.n_cells):
            for _ in range(env.need):
                env.attempt_cell(c)


def test_the_reach_space_leaves_21_cells_of_100_and_the_rest_always_give_0(toy):
    env = toy.HypercubeUnlock(**toy.SPACES["2d-reach"])
    assert env.n_cells == 100 and int(env.possible.sum()) == 21
    _master_everything_possible(env)
    assert env.score() == 1.0
    impossible = np.flatnonzero(~env.possible)
    assert all(env.attempt_cell(int(c)) == 0.0 for c in impossible)
    assert all(env.where(int(c)) == "impossible" for c in impossible)
    assert not env.unlocked[impossible].any() and (env.practice[impossible] == 0).all()
    # The cell (5, 0) can be mastered, (6, 0) and (3, 3) cannot.
    assert env.possible[env.cell(np.array([0.55, 0.05]))]
    assert not env.possible[env.cell(np.array([0.65, 0.05]))]
    assert not env.possible[env.cell(np.array([0.35, 0.35]))]


def test_the_other_spaces_have_no_impossible_cell(toy):
    for space in ("2d", "5d", "2d+3"):
        env = toy.HypercubeUnlock(**toy.SPACES[space])
        assert env.possible.all()
    env = toy.HypercubeUnlock(**toy.SPACES["2d"])
    assert env.score() == 0.0 and env.where(0) == "frontier" and env.where(1) == "locked"
    _master_everything_possible(env)
    assert env.score() == 1.0 and env.where(99) == "mastered"


@pytest.mark.parametrize("name", ["random", "plr"])
def test_a_run_says_where_its_goals_went(toy, monkeypatch, name):
    monkeypatch.setitem(toy.BUDGET, "2d-reach", 400)
    run, curve, modes = toy.one_run((name, "2d-reach", 0, 100))
    assert sum(run[p] for p in toy.PLACES) == pytest.approx(1.0)
    assert [c["goals"] for c in curve] == [100, 200, 300, 400]
    # Every goal is counted once, under the mode that asked for it.
    assert sum(m["goals"] for m in modes) == 400
    assert sum(m[p] for m in modes for p in toy.PLACES) == 400
    if name == "random":
        # Uniform goals: about 79 % of them fall where nothing can ever be learnt.
        assert 0.65 < run["impossible"] < 0.92
