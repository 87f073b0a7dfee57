"""The array view is MiniGrid's observation to the element: compared with MiniGrid's own
``gen_obs`` at every step of random walks, on every grade of rl-minigrid and on MiniGrid levels
it must either compute or hand back to MiniGrid (doors and keys, moving obstacles, lava, other
view sizes, walls seen through)."""

from __future__ import annotations

import os

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("minigrid")

from minigrid.core.world_object import Lava, Wall  # noqa: E402
from minigrid.envs import CrossingEnv, DoorKeyEnv, DynamicObstaclesEnv, EmptyEnv, FourRoomsEnv  # noqa: E402
from minigrid.minigrid_env import MiniGridEnv  # noqa: E402

from saggriac.bench.minigrid import GRADES, _grade_env  # noqa: E402
from saggriac.bench.minigrid_view import ArrayView  # noqa: E402


def walk(env, seed: int, steps: int) -> tuple[int, int]:
    """Random actions (all seven) from resets of several layouts; every observation, from the
    reset's and the step's, equals MiniGrid's. (fast, fallen back) observations counted."""
    if not isinstance(env.gen_obs, ArrayView):
        env.gen_obs = ArrayView(env)
    view = env.gen_obs
    rng = np.random.default_rng(seed)
    counts = [0, 0]

    def same(obs):
        own = MiniGridEnv.gen_obs(env)
        assert np.array_equal(obs["image"], own["image"]) and obs["image"].dtype == own["image"].dtype
        assert (obs["direction"], obs["mission"]) == (own["direction"], own["mission"])
        fast = view.usable and view.static and env.carrying is None
        counts[0 if fast else 1] += 1

    obs, _ = env.reset(seed=int(rng.integers(1 << 30)))
    same(obs)
    for _ in range(steps):
        obs, _, term, trunc, _ = env.step(int(rng.integers(env.action_space.n)))
        same(obs)
        if term or trunc:
            obs, _ = env.reset(seed=int(rng.integers(1 << 30)))
            same(obs)
    return tuple(counts)


@pytest.mark.parametrize("grade", range(len(GRADES)))
def test_every_grade_is_observed_as_minigrid_observes_it(grade):
    fast, slow = walk(_grade_env(grade), grade, 1500)
    # The task's levels never fall back: the speed is there.
    assert slow == 0 and fast > 1500
    assert isinstance(_grade_env(grade).gen_obs, ArrayView)


def test_other_static_levels_lava_four_rooms_small_views_and_walls_seen_through():
    see_through = EmptyEnv(size=8, agent_view_size=5)
    assert see_through.see_through_walls
    for env in (CrossingEnv(size=9, num_crossings=2, obstacle_type=Lava), FourRoomsEnv(), see_through, CrossingEnv(size=11, num_crossings=3, obstacle_type=Wall, agent_view_size=5)):
        fast, slow = walk(env, 7, 1000)
        assert slow == 0 and fast > 1000


def test_levels_it_cannot_compute_are_left_to_minigrid():
    # A door and a key: the agent may pick the key up and open the door, so the view falls back.
    fast, slow = walk(DoorKeyEnv(size=6), 3, 2000)
    assert fast == 0 and slow > 2000
    # Obstacles that move: an environment with a step of its own.
    assert walk(DynamicObstaclesEnv(size=6, n_obstacles=2), 4, 500)[0] == 0
