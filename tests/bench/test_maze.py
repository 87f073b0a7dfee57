"""The PointMaze bench tasks (saggriac.bench.maze) against the real Gymnasium-Robotics PointMaze:
the teacher's goal is the one rewarded and flagged, PointMaze's ignoring of options['goal'] is
refused, goals deep in walls are out of reach while every test goal is reached by a policy that
knows the maze, and a run through the bench gives the curve and measures it says. Skipped without
Gymnasium-Robotics or SB3, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it)."""

import os
from collections import deque

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("gymnasium_robotics", reason='Gymnasium-Robotics is not installed (pip install ".[test]")')
    pytest.importorskip("stable_baselines3", reason='the SB3 extra is not installed (pip install "saggriac[sb3]")')

from saggriac.bench import TASKS, maze  # noqa: E402
from saggriac.bench.rl import train_learner  # noqa: E402
from saggriac.errors import ConformanceError  # noqa: E402

MAPS = {"rl-pointmaze-umaze": "umaze", "rl-pointmaze-medium": "medium"}
#: A free point in the start's own corridor (a straight push reaches it), and the centre of a
#: wall cell inside the goal box, for each map.
NEAR = {"umaze": (0.9, 1.0), "medium": (-1.5, 2.5)}
WALL = {"umaze": (-0.5, 0.0), "medium": (0.5, 2.5)}


def push(obs, target, gain=10.0, damping=1.0):
    """A force towards ``target`` that brakes with the speed."""
    p, v = obs["observation"][:2], obs["observation"][2:4]
    return np.clip(gain * (np.asarray(target) - p) - damping * v, -1.0, 1.0)


class KnowsTheMaze:
    """A policy that knows the map: towards the next cell of the shortest way to the goal's cell,
    then to the goal. Its ``predict`` takes a batch, as SB3's does."""

    def __init__(self, name):
        self.geometry = maze.Maze(name)
        self.wall = np.array([[c == 1 for c in row] for row in self.geometry.map])

    def cell(self, p):
        h, w = self.wall.shape
        return int(np.floor(h / 2 - p[1])), int(np.floor(p[0] + w / 2))

    def next_cell(self, here, there):
        came = {there: None}
        todo = deque([there])
        while todo:
            c = todo.popleft()
            if c == here:
                return came[c]
            for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                n = (c[0] + di, c[1] + dj)
                if not self.wall[n] and n not in came:
                    came[n] = c
                    todo.append(n)
        raise AssertionError(f"no way from {here} to {there}")

    def predict(self, obs, deterministic=True):
        actions = []
        for o, g in zip(obs["observation"], obs["desired_goal"]):
            here, there = self.cell(o[:2]), self.cell(g)
            target = g if here == there else self.geometry.centres(np.array([self.next_cell(here, there)]))[0]
            actions.append(push({"observation": o}, target))
        return np.array(actions), None


def cells_of(geometry, points):
    """The (row, column) cells of ``points`` on the map."""
    h, w = len(geometry.map), len(geometry.map[0])
    return {(int(np.floor(h / 2 - p[1])), int(np.floor(p[0] + w / 2))) for p in points}


class Still:
    def predict(self, obs, deterministic=True):
        return np.zeros((len(obs["observation"]), 2)), None


@pytest.mark.parametrize("name", MAPS.values())
def test_reward_success_and_distance_follow_the_teachers_goal(name):
    env = maze.make_env(name)
    goal = np.array(NEAR[name])
    env.get_wrapper_attr("set_next_goal")(goal)
    obs, info = env.reset(seed=3)
    own = env.unwrapped.goal.copy()
    assert np.linalg.norm(own - goal) > 1.0  # the environment's own goal is elsewhere
    np.testing.assert_array_equal(obs["desired_goal"], goal)
    reached = False
    for _ in range(maze.EPISODE_STEPS[name]):
        obs, reward, terminated, truncated, info = env.step(push(obs, goal))
        d = float(np.linalg.norm(obs["achieved_goal"] - goal))
        np.testing.assert_array_equal(obs["desired_goal"], goal)
        assert reward == pytest.approx(np.exp(-d)) and reward != pytest.approx(np.exp(-np.linalg.norm(obs["achieved_goal"] - own)))
        assert info["is_success"] == info["success"] == (d <= maze.SUCCESS) and info["distance"] == pytest.approx(d)
        assert info["success_env_goal"] == (np.linalg.norm(obs["achieved_goal"] - own) <= maze.SUCCESS)
        assert not terminated
        reached |= info["is_success"]
    assert reached and truncated  # reached the teacher's goal; the episode runs to its limit


@pytest.mark.parametrize("name", MAPS.values())
def test_pointmaze_ignores_options_goal_and_training_refuses_it(name):
    env = maze.make_env(name, goal_via="options")
    env.get_wrapper_attr("set_next_goal")(np.array(NEAR[name]))
    obs, _ = env.reset(seed=0)
    assert np.linalg.norm(obs["desired_goal"] - NEAR[name]) > 0.5
    asked = []

    class Fixed:
        low, high = maze.Maze(name).low, maze.Maze(name).high

        def sample(self):
            asked.append(NEAR[name])
            return np.array(NEAR[name])

        def update(self, goal, competence):
            raise AssertionError("told a competence for a goal never pursued")

    with pytest.raises(ConformanceError, match="does not take goals that way"):
        train_learner(lambda: maze.make_env(name, goal_via="options"), lambda info: 0.0, Fixed(), 0, 4 * maze.EPISODE_STEPS[name] + 40, 10**9, lambda *a: None)
    assert asked


@pytest.mark.parametrize("name", MAPS.values())
def test_wall_goals_are_out_of_reach_and_the_ball_stays_out_of_walls(name):
    geometry = maze.Maze(name)
    wall = np.array(WALL[name])
    assert np.all((geometry.low <= wall) & (wall <= geometry.high)) and not geometry.reachable(wall)[0]
    # A goal this deep in a wall is further than the success distance from anywhere the ball can
    # be (0.6: half a cell and the ball's radius), on a dense sample of the reachable set.
    points = np.random.default_rng(1).uniform(geometry.low, geometry.high, size=(400_000, 2))
    points = points[geometry.reachable(points)]
    assert np.linalg.norm(points - wall, axis=1).min() == pytest.approx(0.6, abs=0.01)
    env = maze.make_env(name)
    rng = np.random.default_rng(0)
    positions = []
    for episode in range(3):
        env.get_wrapper_attr("set_next_goal")(wall)
        obs, _ = env.reset(seed=episode)
        for _ in range(maze.EPISODE_STEPS[name]):
            action = push(obs, wall) if episode < 2 else rng.uniform(-1, 1, 2)
            obs, _, _, _, info = env.step(action)
            positions.append(obs["achieved_goal"].copy())
            assert not info["is_success"]
    # The ball pressed into a wall stays out of it: MuJoCo's soft contact lets it sink about 0.02
    # (measured: its centre came within 0.079 of the U-maze's wall), far less than the margin of
    # 0.15 by which a goal this deep stays out of reach.
    assert geometry.wall_distance(np.array(positions)).min() >= maze.BALL - 0.03


@pytest.mark.parametrize("name", MAPS.values())
def test_test_goals_are_reachable_spread_and_reached_by_a_policy_that_knows_the_maze(name):
    geometry = maze.Maze(name)
    goals = maze.test_goals(geometry)
    assert goals.shape == (maze.N_TEST, 2) and np.all(geometry.reachable(goals))
    assert np.all((geometry.low <= goals) & (goals <= geometry.high))
    # Spread over the free cells: most of the maze's free cells hold a test goal.
    assert len(cells_of(geometry, goals)) >= 0.6 * len(geometry.free_cells)
    np.testing.assert_array_equal(goals, maze.test_goals(geometry))  # one set for every run
    success, distance = maze.evaluate(KnowsTheMaze(name), name, goals)
    assert success.all() and distance.max() <= maze.SUCCESS
    # Standing still reaches exactly the goals within the success distance of the episode's start.
    success, _ = maze.evaluate(Still(), name, goals)
    env = maze.make_env(name)
    starts = []
    for k in range(len(goals)):
        env.get_wrapper_attr("set_next_goal")(goals[k])
        starts.append(env.reset(seed=maze.TEST_SEED + k)[0]["achieved_goal"])
    expected = np.linalg.norm(np.array(starts) - goals, axis=1) <= maze.SUCCESS
    np.testing.assert_array_equal(success, expected)
    assert success.mean() < 0.1


@pytest.mark.parametrize("task", MAPS)
def test_the_oracle_asks_reachable_goals_over_the_whole_maze_from_its_seed(task):
    a, b = TASKS[task](106), TASKS[task](107)
    goals = np.array([a.oracle() for _ in range(500)])
    assert np.all(a.geometry.reachable(goals)) and np.all((a.low <= goals) & (goals <= a.high))
    assert len(cells_of(a.geometry, goals)) == len(a.geometry.free_cells)
    again = TASKS[task](106)
    np.testing.assert_array_equal(goals[:5], [again.oracle() for _ in range(5)])
    assert not np.allclose(goals[:5], [b.oracle() for _ in range(5)])


@pytest.mark.parametrize("task", MAPS)
def test_competence_and_expert_knowledge(task):
    t = TASKS[task](0)
    assert t.competence({"distance": 0.0}) == 1.0 and t.competence({"distance": t.scale}) == 0.0 and t.competence({"distance": 2 * t.scale}) == 0.0
    assert t.competence({"distance": t.scale / 4}) == pytest.approx(0.75)
    k = t.expert_knowledge()
    assert np.all(k.easy.low <= t.geometry.start) and np.all(t.geometry.start <= k.easy.high)
    corners = np.array([k.easy.low, k.easy.high, [k.easy.low[0], k.easy.high[1]], [k.easy.high[0], k.easy.low[1]]])
    assert np.all(t.geometry.wall_distance(corners) >= maze.BALL - 1e-9)  # the easy box is all free
    np.testing.assert_array_equal(k.target.low, t.low)


def test_a_short_run_gives_the_curve_the_teacher_and_the_measures_it_says(monkeypatch):
    """Through play, as the bench runs it: a teacher asking one wall goal and the oracle, on
    the same seed (5 test goals to keep it short)."""
    monkeypatch.setattr(maze, "N_TEST", 5)
    name = "rl-pointmaze-umaze"
    budget = 1_200  # 300 steps per environment: the teacher's goals run from step 150
    rows = {}
    for who in ("wall", "oracle"):
        task = TASKS[name](7)
        asked, told = [], []

        def ask():
            goal = np.array(WALL["umaze"]) if who == "wall" else task.oracle()
            asked.append(goal)
            return goal

        curve = task.play(ask, lambda goal, c: told.append((np.asarray(goal), c)), budget)
        assert [t for t, _ in curve] == list(range(120, budget + 1, 120)) and all(0.0 <= s <= 1.0 for _, s in curve)
        # Every environment ended its first teacher's episode: 4 told, each a goal asked.
        assert len(told) == 4 and all(any(np.array_equal(g, a) for a in asked) for g, _ in told)
        assert all(0.0 <= c < 1.0 for _, c in told)
        own = task.own_measures()
        assert len(own) == len(curve) and own[-1]["goals_asked"] == len(asked)
        assert [m["goals_asked"] for m in own] == sorted(m["goals_asked"] for m in own)
        rows[who] = own[-1]
    assert rows["wall"]["goals_reachable"] == rows["wall"]["reachable_share"] == 0.0
    assert rows["oracle"]["goals_reachable"] == rows["oracle"]["reachable_share"] == 1.0


def test_the_evidence_runner_runs_the_task_and_its_oracle(monkeypatch):
    """benchmarks/evidence.py's run of the task (the bench's guarded teachers, the oracle through
    GuardedOracle): the oracle's goals are the task's oracle() of the same seed, and the row
    carries the task's own measures."""
    from saggriac.bench.teachers import GuardedOracle
    from tests import benchmark_scripts

    name = "rl-pointmaze-umaze"
    guard = GuardedOracle(TASKS[name](7), TASKS[name].child_seeds(7)[0])
    task = TASKS[name](7)
    np.testing.assert_array_equal([guard.ask() for _ in range(20)], [task.oracle() for _ in range(20)])
    monkeypatch.setattr(maze, "N_TEST", 5)
    evidence = benchmark_scripts.load("evidence")
    curves, row = evidence.one_run((name, "oracle", 7, 1_200, 10, 30.0, "test", ()))
    assert len(curves) == 10 and row["budget"] == 1_200 and row["final"] == curves[-1]["score"]
    assert row["final_reachable_share"] == 1.0 and row["final_goals_asked"] == 12 and row["final_distance"] == curves[-1]["distance"]


def test_the_tasks_are_listed_by_the_bench():
    from saggriac.bench.command import listing

    text = listing()
    assert all(name in text for name in MAPS)
    assert all(TASKS[n].budgets["quick"] is None and TASKS[n].budgets["standard"] for n in MAPS)


def test_the_pilots_rules_on_its_committed_rows_give_what_the_protocol_holds():
    """docs/evidence/pointmaze.md's pilot numbers recompute from the committed rows: the rules
    give the map, budget and report seeds protocol.json holds (a changed row or rule breaks it)."""
    import json

    from tests import benchmark_scripts

    pilot = benchmark_scripts.load("pointmaze_pilot")
    protocol = json.loads(pilot.PROTOCOL.read_text())
    text = pilot.rules(pilot.OUT, protocol)
    choice = json.loads(text.strip().splitlines()[-1])
    task = protocol["tasks"][0]
    assert protocol["tasks"] == [choice["task"]] and protocol["budget"] == {task: choice["budget"]}
    first = choice["first_seed"]
    assert protocol["pilot_fixed"]["seeds"] == choice["seeds"] == protocol["amended"]["was"]
    # The amendment (before any report run): every seed the compute allows at B, the table's "seeds that fit".
    assert protocol["report"] == {task: f"{first}-{first + protocol['amended']['report_seeds'] - 1}"}
    assert f"| {choice['budget']:,} | 0.036 | 0.077 | 0.92 | {choice['seeds']} | {protocol['amended']['report_seeds']} | 4.31 |" in text
    assert TASKS[task].budgets["full"] == choice["budget"]
