"""Goal GAN against its paper's claims (Florensa et al., ICML 2018) on the U-maze of
benchmarks/goal_gan_claims.py (issue 46, item 6): the share of asked goals of intermediate
difficulty rises above uniform goals', and coverage grows, faster than with uniform goals.

The oracle (goals drawn among those of intermediate difficulty) meets both claims on the same
task, so the task can tell a teacher that does from one that does not; uniform goals meet
neither. Seeds 0-3, 3,000 goals each: benchmarks/goal_gan_claims.py prints the longer run."""

from __future__ import annotations


import numpy as np
import pytest

from tests import benchmark_scripts

SEEDS, GOALS, WINDOWS = range(4), 3000, 2


@pytest.fixture(scope="module")
def claims():
    return benchmark_scripts.load("goal_gan_claims")


@pytest.fixture(scope="module")
def runs(claims):
    """Per teacher, means over the seeds: the share of goals of intermediate difficulty in the
    first and the second half, and the coverage at the start and at the end."""
    out = {}
    for name in claims.TEACHERS:
        rs = [claims.run(name, GOALS, s, WINDOWS) for s in SEEDS]
        out[name] = {"goid_first": np.mean([r["goid"][0] for r in rs]), "goid": np.mean([r["goid"][-1] for r in rs]), "start": np.mean([r["coverage"][0] for r in rs]), "end": np.mean([r["coverage"][-1] for r in rs])}
    return out


def test_the_maze_is_a_u_around_its_wall(claims):
    free, dist = claims.maze()
    # The wall's cells are not free and have no distance; the far arm is reached around the wall.
    assert not free[0, claims.N // 2] and np.isinf(dist[0, claims.N // 2])
    start, far = claims._cell(np.array(claims.START)), claims._cell(np.array([-0.8, 0.7]))
    straight = np.hypot(*(np.subtract(far, start) * 2.0 / claims.N))
    assert dist[far] > 2.5 * straight  # around the wall, not through it
    assert np.isfinite(dist[free]).all()


def test_the_learner_learns_only_at_its_frontier(claims):
    learner = claims.MazeLearner(0)
    reach = learner.reach
    for g in ([0.9, 0.9], [-0.8, -0.7]):  # never reached, always reached: nothing learnt
        for _ in range(50):
            learner.attempt(np.array(g))
    assert learner.reach == reach
    p = learner.p_cells()
    edge = np.argwhere((p > 0.2) & (p < 0.8))[0]
    goal = -1.0 + (edge + 0.5) * 2.0 / claims.N
    for _ in range(200):
        learner.attempt(goal)
    assert learner.reach > reach


def test_the_oracle_meets_both_claims_and_uniform_goals_neither(runs):
    """The check has teeth: what the claims ask is reachable on this task, and not by chance."""
    oracle, uniform = runs["oracle"], runs["uniform"]
    # The oracle masters the whole maze in about 2,000 goals (no goal is left of intermediate
    # difficulty after that): its first half is all such goals.
    assert oracle["goid_first"] > 0.9 and oracle["goid_first"] > 10 * uniform["goid_first"]
    assert oracle["end"] > 0.99 and oracle["end"] > 5 * uniform["end"] and uniform["end"] > uniform["start"]
    assert uniform["goid"] < 0.05 and uniform["goid_first"] < 0.05


def test_goal_gans_coverage_grows_faster_than_with_uniform_goals(runs):
    """Holds on the mean of the seeds (0.137 against 0.111 from 0.054), with a wide spread: one
    seed of four never leaves the start (0.055)."""
    gan, uniform = runs["goal_gan"], runs["uniform"]
    assert gan["end"] > gan["start"] + 0.05 and gan["end"] > uniform["end"], runs


def test_goal_gan_first_asks_more_goals_of_intermediate_difficulty_than_uniform_goals(runs):
    assert runs["goal_gan"]["goid_first"] > 1.5 * runs["uniform"]["goid_first"], runs


# Today's Goal GAN finds the frontier in its first goals (0.068 against uniform's 0.036 in the
# first half), then its generator leaves it and its share falls below uniform goals' (0.020
# against 0.035 in the second half). A batch of update_size labelled goals that holds no goal of
# intermediate difficulty trains nothing (goal_gan.rs, as TeachMyAgent's), so a generator whose
# goals all fail stays where it is. docs/teachers.md's Goal GAN section gives the numbers.
# strict: the day it passes, the mark goes.
@pytest.mark.xfail(strict=True, reason="Goal GAN's generator leaves the maze's frontier and a batch without a good goal trains nothing (docs/teachers.md, Goal GAN)")
def test_goal_gan_keeps_asking_more_goals_of_intermediate_difficulty_than_uniform_goals(runs):
    assert runs["goal_gan"]["goid"] > runs["uniform"]["goid"], runs
