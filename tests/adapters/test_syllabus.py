"""The Syllabus extra: saggriac teachers as Syllabus curricula, over Syllabus's own task spaces.

Skipped when Syllabus is not installed, unless SAGGRIAC_REQUIRE_EXTRAS=1 (CI sets it): then a
missing extra fails."""

import os
import pickle
import time

import numpy as np
import pytest

if os.environ.get("SAGGRIAC_REQUIRE_EXTRAS") != "1":
    pytest.importorskip("syllabus", reason='the Syllabus extra is not installed (pip install "saggriac[syllabus]")')

import gymnasium
from syllabus.core import GymnasiumSyncWrapper, TaskEnv, make_multiprocessing_curriculum
from syllabus.task_space import BoxTaskSpace, DiscreteTaskSpace, MultiDiscreteTaskSpace, TupleTaskSpace

import saggriac as sg
from saggriac.errors import ConformanceError, ParameterError
from saggriac.adapters.syllabus import SelectorCurriculum

LOW, HIGH = [0.0, -2.0, 0.5], [1.0, 2.0, 0.75]


def box_space():
    return BoxTaskSpace(gymnasium.spaces.Box(np.array(LOW, np.float32), np.array(HIGH, np.float32), dtype=np.float32))


def progress_of(task):
    """A made-up task completion: high near one corner, in [0, 1]."""
    t = np.asarray(task, dtype=np.float64)
    return float(np.exp(-np.sum(((t - np.array(LOW)) / (np.array(HIGH) - np.array(LOW))) ** 2)))


QUICK = {
    "riac": {"max_region_size": 30},
    "alp_gmm": {"fit_rate": 40, "bootstrap": 40},
    "covar_gmm": {"fit_rate": 40, "bootstrap": 40},
    "adr": {"buffer_size": 3, "t_low": 0.2, "t_high": 0.4},
    "spdl": {"update_every": 20, "warmup": 20},
    "goal_gan": {"update_size": 10, "gan_iterations": 10, "hidden": 8},
}
# Every registered teacher of a box (the registry's), quick where it has slow parameters.
BOX_TEACHERS = {kind: (lambda s, cls=cls: cls(LOW, HIGH, seed=s, **QUICK.get(cls._kind, {}))) for kind, cls in sg.teachers.available().items() if "box" in cls.spaces}


@pytest.mark.parametrize("name", list(BOX_TEACHERS))
def test_box_curriculum_asks_the_teachers_tasks_and_tells_it_each_episode(name):
    space = box_space()
    cur = SelectorCurriculum(space, BOX_TEACHERS[name](5))
    bare = BOX_TEACHERS[name](5)
    for i in range(150):
        (task,) = cur.sample(k=1)
        assert space.contains(task) and task.dtype == np.float32
        g = bare.sample().astype(np.float32)
        np.testing.assert_array_equal(task, g)
        p = progress_of(task)
        cur.update_on_episode(episode_return=-3.0, length=10, task=task, progress=p)
        bare.update(g.astype(np.float64), p)
    assert cur.told == 150
    h = cur.selector.history()
    np.testing.assert_array_equal(h["told_goal"], bare.history()["told_goal"])
    np.testing.assert_array_equal(h["told_competence"], bare.history()["told_competence"])
    # Batches of tasks, all inside the space.
    tasks = cur.sample(k=64)
    assert len(tasks) == 64 and all(space.contains(t) for t in tasks)


def test_pickled_curriculum_continues_with_the_same_tasks():
    cur = SelectorCurriculum(box_space(), sg.AlpGmmSelector(LOW, HIGH, seed=2, fit_rate=30, bootstrap=30))
    for _ in range(100):
        (t,) = cur.sample()
        cur.update_on_episode(0.0, 5, t, progress_of(t))
    copy = pickle.loads(pickle.dumps(cur))
    for _ in range(100):
        (a,), (b,) = cur.sample(), copy.sample()
        np.testing.assert_array_equal(a, b)
        cur.update_on_episode(0.0, 5, a, progress_of(a))
        copy.update_on_episode(0.0, 5, b, progress_of(b))
    assert copy.told == cur.told == 200


def test_competence_is_progress_return_or_a_function():
    space = box_space()
    for competence, expected in [("progress", 0.25), ("return", -7.5), (lambda ret, length, task, p: ret / length, -0.75)]:
        cur = SelectorCurriculum(space, sg.SaggRiacSelector(LOW, HIGH, seed=0), competence=competence)
        (t,) = cur.sample()
        cur.update_on_episode(episode_return=-7.5, length=10, task=t, progress=0.25)
        assert cur.selector.history()["told_competence"].tolist() == [expected]


def test_discrete_curriculum_draws_task_indices_by_learning_progress():
    space = DiscreteTaskSpace(6)
    cur = SelectorCurriculum(space, sg.DiscreteLpSelector(6, seed=1))
    counts = np.zeros(6, dtype=int)
    success = np.zeros(6)
    for _ in range(3000):
        (task,) = cur.sample()
        assert isinstance(task, int) and space.contains(task)
        counts[task] += 1
        # Task 4 is being learnt; the others stay where they are.
        if task == 4:
            success[4] = min(1.0, success[4] + 0.002)
        cur.update_on_episode(0.0, 1, task, success[task])
    assert cur.told == 3000
    assert counts[4] == counts.max() and counts[4] > 2 * np.delete(counts, 4).max()


def test_plr_over_a_discrete_task_space_asks_the_teachers_levels():
    """PLR as a Syllabus curriculum: the same levels as the bare teacher told the same
    competences, every level drawn before replays start to dominate."""
    space = DiscreteTaskSpace(6)
    cur = SelectorCurriculum(space, sg.PlrSelector(6, seed=3))
    bare = sg.PlrSelector(6, seed=3)
    for i in range(300):
        (task,) = cur.sample()
        assert isinstance(task, int) and space.contains(task)
        assert task == bare.sample_task()
        p = 0.1 * task + 0.01 * (i % 7)
        cur.update_on_episode(0.0, 1, task, p)
        bare.update(task, p)
    assert sorted(set(cur.selector.history()["asked_goal"][:, 0].astype(int))) == list(range(6))
    np.testing.assert_array_equal(cur.selector.history()["told_competence"], bare.history()["told_competence"])
    with pytest.raises(ConformanceError, match="PlrSelector chooses among a task list"):
        SelectorCurriculum(box_space(), sg.PlrSelector(4))


def check_the_map(space, flat):
    """Every index of the flat list is a task of the space: its encoding decodes to the space's
    task at that place (C order), and encoding the task gives back the index."""
    assert len(flat) == space.num_tasks
    for i in range(len(flat)):
        enc = flat.encoding(i)
        assert flat.task(i) == space.decode(enc) == space.tasks[i]
        assert flat.index(enc) == i and flat.index(space.encode(space.tasks[i])) == i


@pytest.mark.parametrize("flatten", [False, True])
def test_a_multidiscrete_task_space_is_one_list_with_a_map_back(flatten):
    space = MultiDiscreteTaskSpace(gymnasium.spaces.MultiDiscrete([3, 4]), flatten=flatten)
    cur = SelectorCurriculum(space, sg.PlrSelector(12, seed=2))
    check_the_map(space, cur.flat_tasks)
    bare = sg.PlrSelector(12, seed=2)
    for _ in range(200):
        (enc,) = cur.sample()
        i = bare.sample_task()
        assert enc == cur.flat_tasks.encoding(i) and isinstance(enc, int if flatten else tuple)
        a, b = space.decode(enc)
        assert (a, b) == divmod(i, 4)
        cur.update_on_episode(0.0, 1, enc, (a + b) / 5)
        bare.update(i, (a + b) / 5)
    np.testing.assert_array_equal(cur.selector.history()["told_goal"], bare.history()["told_goal"])
    np.testing.assert_array_equal(cur.selector.history()["asked_goal"], bare.history()["asked_goal"])


@pytest.mark.parametrize("flatten", [False, True])
def test_a_tuple_task_space_of_discrete_parts_is_one_list_with_a_map_back(flatten):
    space = TupleTaskSpace((DiscreteTaskSpace(2, ["easy", "hard"]), MultiDiscreteTaskSpace([2, 3]), DiscreteTaskSpace(3)), flatten=flatten)
    cur = SelectorCurriculum(space, sg.DiscreteLpSelector(36, seed=1))
    check_the_map(space, cur.flat_tasks)
    assert cur.flat_tasks.task(35) == ("hard", (1, 2), 2) and cur.flat_tasks.task(7) == ("easy", (0, 2), 1)  # 7 = 0 * 18 + 2 * 3 + 1
    for _ in range(50):
        (enc,) = cur.sample()
        cur.update_on_episode(0.0, 1, enc, 0.5)
    told = cur.selector.history()["told_goal"][:, 0].astype(int)
    np.testing.assert_array_equal(told, cur.selector.history()["asked_goal"][:, 0])


def test_gymnasium_spaces_are_taken_as_syllabus_task_spaces():
    from gymnasium.spaces import Box, Dict, Discrete, MultiDiscrete, Tuple

    cur = SelectorCurriculum(MultiDiscrete([2, 3]), sg.PlrSelector(6, seed=0))
    assert isinstance(cur.task_space, MultiDiscreteTaskSpace) and cur.task_space.gym_space.contains(np.array(cur.sample()[0]))
    cur = SelectorCurriculum(Tuple((Discrete(2), MultiDiscrete([3, 2]))), sg.TsclSelector(12, seed=0))
    assert isinstance(cur.task_space, TupleTaskSpace) and cur.flat_tasks.task(11) == (1, (2, 1))
    check_the_map(cur.task_space, cur.flat_tasks)
    assert isinstance(SelectorCurriculum(Discrete(4), sg.DiscreteLpSelector(4)).task_space, DiscreteTaskSpace)
    box = SelectorCurriculum(Box(np.array(LOW, np.float32), np.array(HIGH, np.float32)), sg.RandomSelector(LOW, HIGH))
    assert isinstance(box.task_space, BoxTaskSpace) and box.flat_tasks is None
    with pytest.raises(ConformanceError, match="no task space for a gymnasium Dict"):
        SelectorCurriculum(Dict({"a": Discrete(2), "b": Discrete(3)}), sg.PlrSelector(6))
    with pytest.raises(ConformanceError, match="part 1 is a BoxTaskSpace"):
        SelectorCurriculum(Tuple((Discrete(2), Box(0, 1, (1,)))), sg.PlrSelector(2))
    with pytest.raises(ParameterError, match="count its values from 0") as e:
        SelectorCurriculum(Discrete(3, start=1), sg.PlrSelector(3))
    assert e.value.param == "task_space"
    with pytest.raises(ParameterError, match="6 tasks \\(2 x 3\\)"):
        SelectorCurriculum(Tuple((Discrete(2), Discrete(3))), sg.PlrSelector(5))
    with pytest.raises(ConformanceError, match="DiscreteLpSelector, saggriac.PlrSelector"):
        SelectorCurriculum(MultiDiscrete([2, 3]), sg.RandomSelector([0], [5]))
    # A task that is no encoding of the space is refused, and nothing is told.
    cur = SelectorCurriculum(MultiDiscrete([2, 3]), sg.PlrSelector(6, seed=0))
    for bad in [(2, 0), (0, 3), (1,), 4, (0.5, 1), "a"]:
        with pytest.raises(sg.InputError, match="not an encoding of a task of MultiDiscreteTaskSpace \\[2, 3\\]"):
            cur.update_on_episode(0.0, 1, bad, 0.5)
    assert cur.told == 0 and len(cur.selector.history()["told_goal"]) == 0


def test_bad_pairings_and_parameters_are_refused_with_the_rule():
    space = box_space()
    with pytest.raises(ParameterError, match="bounds"):
        SelectorCurriculum(space, sg.SaggRiacSelector([0, 0, 0], [1, 1, 1]))
    with pytest.raises(ParameterError, match="3-D"):
        SelectorCurriculum(space, sg.SaggRiacSelector([0, 0], [1, 1]))
    with pytest.raises(ConformanceError, match="DiscreteTaskSpace"):
        SelectorCurriculum(space, sg.DiscreteLpSelector(4))
    with pytest.raises(ConformanceError, match="DiscreteLpSelector"):
        SelectorCurriculum(DiscreteTaskSpace(4), sg.RandomSelector([0], [3]))
    with pytest.raises(ParameterError, match="4 tasks"):
        SelectorCurriculum(DiscreteTaskSpace(4), sg.DiscreteLpSelector(5))
    with pytest.raises(ParameterError, match="6 tasks \\(2 x 3\\); it has 5"):
        SelectorCurriculum(MultiDiscreteTaskSpace([2, 3]), sg.DiscreteLpSelector(5))
    with pytest.raises(ParameterError, match="random_start_tasks"):
        SelectorCurriculum(space, sg.SaggRiacSelector(LOW, HIGH), random_start_tasks=10)
    with pytest.raises(ParameterError, match="'competence'"):
        SelectorCurriculum(space, sg.SaggRiacSelector(LOW, HIGH), competence="reward")
    cur = SelectorCurriculum(space, sg.SaggRiacSelector(LOW, HIGH))
    with pytest.raises(ParameterError, match="'k'"):
        cur.sample(k=0)
    # A task outside the box is refused by the teacher, which then holds nothing of it.
    with pytest.raises(sg.InputError):
        cur.update_on_episode(0.0, 1, np.array([5.0, 0.0, 0.6], np.float32), 1.0)
    assert cur.told == 0 and len(cur.selector.history()["told_goal"]) == 0


def test_log_metrics_reports_the_episodes_told():
    cur = SelectorCurriculum(box_space(), sg.SaggRiacSelector(LOW, HIGH, seed=0))
    for _ in range(70):
        (t,) = cur.sample()
        cur.update_on_episode(0.0, 1, t, progress_of(t))

    class Writer:
        def __init__(self):
            self.scalars = {}

        def add_scalar(self, name, value, step):
            self.scalars[name] = (value, step)

    w = Writer()
    logs = cur.log_metrics(w, None, step=9)
    assert ("curriculum/told", 70) in logs
    assert w.scalars["curriculum/told"] == (70, 9)
    assert w.scalars["curriculum/regions"][0] == cur.selector.n_regions >= 2


class Still(gymnasium.Env):
    observation_space = gymnasium.spaces.Box(-np.inf, np.inf, (3,), np.float64)
    action_space = gymnasium.spaces.Box(-1.0, 1.0, (3,), np.float32)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.steps = 0
        return np.zeros(3), {}


class PointEnv(TaskEnv, Still):
    """A Syllabus task environment (its TaskEnv over a plain Env): the task is a target point
    each episode reports progress on."""

    def __init__(self):
        super().__init__()
        self.received = []

    def change_task(self, new_task):
        self.received.append(np.asarray(new_task).copy())

    def observation(self, observation):
        return observation

    def step(self, action):
        self.steps += 1
        done = self.steps == 4
        info = {"task_completion": progress_of(self.task)}
        return np.zeros(3), -1.0, False, done, info


def through_sync_wrapper(space, selector, inner, episodes, steps):
    """Syllabus's own plumbing: ``selector`` behind a curriculum in Syllabus's update thread,
    ``inner`` behind its sync wrapper, ``episodes`` episodes of ``steps`` random actions; the
    curriculum once it was told every episode (or after 30 s)."""
    cur = make_multiprocessing_curriculum(SelectorCurriculum(space, selector))
    try:
        env = GymnasiumSyncWrapper(inner, space, cur.components, buffer_size=1)
        for _ in range(episodes):
            env.reset()
            for _ in range(steps):
                env.step(env.action_space.sample())
        deadline = time.time() + 30
        while cur.curriculum.told < episodes and time.time() < deadline:
            time.sleep(0.01)
    finally:
        cur.stop()
    return cur.curriculum


@pytest.mark.parametrize("make", [lambda: sg.SaggRiacSelector(LOW, HIGH, seed=4), lambda: sg.AdrSelector(LOW, HIGH, seed=4, buffer_size=2, boundary_prob=1.0, t_low=0.1, t_high=0.2)], ids=["sagg_riac", "adr"])
def test_through_syllabus_sync_wrappers(make):
    """Syllabus's own plumbing: the curriculum behind its update thread, the environment behind
    its sync wrapper; the teacher is told every finished episode of the tasks it chose."""
    inner = PointEnv()
    curriculum = through_sync_wrapper(box_space(), make(), inner, 60, 4)
    teacher = curriculum.selector
    h = teacher.history()
    assert curriculum.told == 60
    received = np.array(inner.received, dtype=np.float64)
    assert len(received) == 60
    np.testing.assert_array_equal(h["told_goal"], received)
    np.testing.assert_array_equal(h["asked_goal"][:60].astype(np.float32), received.astype(np.float32))
    np.testing.assert_allclose(h["told_competence"], [progress_of(t) for t in received])
    if isinstance(teacher, sg.AdrSelector):
        # Every goal was a boundary sample told a progress >= 0.2 somewhere: the ranges grew.
        lo, hi = teacher.bounds
        assert np.all(hi - lo > 0), (lo, hi)


class LevelEnv(TaskEnv, Still):
    """A Syllabus task environment over a list of levels: progress grows with the level index."""

    def __init__(self):
        super().__init__()
        self.received = []

    def change_task(self, new_task):
        self.received.append(int(new_task))

    def observation(self, observation):
        return observation

    def step(self, action):
        self.steps += 1
        return np.zeros(3), -1.0, False, self.steps == 4, {"task_completion": self.task / 10}


def test_plr_through_syllabus_sync_wrappers():
    inner = LevelEnv()
    curriculum = through_sync_wrapper(DiscreteTaskSpace(8), sg.PlrSelector(8, seed=1), inner, 40, 4)
    h = curriculum.selector.history()
    assert curriculum.told == 40
    np.testing.assert_array_equal(h["told_goal"][:, 0], inner.received)
    np.testing.assert_array_equal(h["asked_goal"][:40, 0], inner.received)
    np.testing.assert_allclose(h["told_competence"], np.array(inner.received) / 10)


class PairEnv(TaskEnv, Still):
    """A Syllabus task environment over a MultiDiscrete task space: a task is a pair (a, b)."""

    def __init__(self):
        super().__init__()
        self.task_space = MultiDiscreteTaskSpace([3, 4])
        self.received = []

    def change_task(self, new_task):
        self.received.append(tuple(int(x) for x in new_task))

    def observation(self, observation):
        return observation

    def step(self, action):
        self.steps += 1
        a, b = self.task
        return np.zeros(3), -1.0, False, self.steps == 3, {"task_completion": (a + b) / 5}


def test_plr_over_a_multidiscrete_space_through_syllabus_sync_wrappers():
    """The environments decode what the curriculum hands out and report tasks in Syllabus's
    encoding; the teacher is asked and told indices of the flat list."""
    inner = PairEnv()
    curriculum = through_sync_wrapper(inner.task_space, sg.PlrSelector(12, seed=4), inner, 30, 3)
    h = curriculum.selector.history()
    assert curriculum.told == 30 and all(isinstance(t, tuple) for t in inner.received)
    indices = [a * 4 + b for a, b in inner.received]
    np.testing.assert_array_equal(h["told_goal"][:, 0], indices)
    np.testing.assert_array_equal(h["asked_goal"][:30, 0], indices)
    np.testing.assert_allclose(h["told_competence"], [(a + b) / 5 for a, b in inner.received])


def test_saggriacs_goal_environments_as_syllabus_task_environments():
    """GoalTaskWrapper, shipped: a saggriac goal environment behind Syllabus's sync wrapper, its
    goals chosen by a SAGG-RIAC curriculum in Syllabus's update thread."""
    import saggriac.adapters.gym  # noqa: F401 (registers the environments)
    from saggriac.adapters.syllabus import GoalTaskWrapper

    env = GoalTaskWrapper(gymnasium.make("saggriac/PlanarArmExp1-v0", max_episode_steps=5))
    space = env.task_space
    teacher = sg.SaggRiacSelector(space.gym_space.low, space.gym_space.high, seed=2)
    cur = make_multiprocessing_curriculum(SelectorCurriculum(space, teacher))
    try:
        synced = GymnasiumSyncWrapper(env, space, cur.components, buffer_size=1)
        pursued = []
        for _ in range(20):
            obs, info = synced.reset()
            pursued.append(np.asarray(obs["desired_goal"]).copy())
            assert info["task_completion"] == 0.0
            done = False
            while not done:
                obs, _, term, trunc, info = synced.step(synced.action_space.sample())
                assert 0.0 <= info["task_completion"] <= 1.0
                done = term or trunc
        deadline = time.time() + 30
        while cur.curriculum.told < 19 and time.time() < deadline:
            time.sleep(0.01)
    finally:
        cur.stop()
    h = cur.curriculum.selector.history()
    # Every told goal is one an episode pursued: the curriculum's goals reached the environment.
    told = h["told_goal"]
    assert len(told) >= 19
    assert all(any(np.allclose(g, p) for p in pursued) for g in told)


def test_goal_task_wrapper_refuses_tasks_outside_the_goal_box():
    import saggriac.adapters.gym  # noqa: F401
    from saggriac.errors import InputError
    from saggriac.adapters.syllabus import GoalTaskWrapper

    env = GoalTaskWrapper(gymnasium.make("saggriac/PlanarArmExp1-v0"))
    with pytest.raises(InputError, match="goal box"):
        env.reset(new_task=[500.0, 0.0])
    obs, info = env.reset(new_task=[20.0, 10.0], seed=3)
    assert obs["desired_goal"].tolist() == [20.0, 10.0] and info["task"].tolist() == [20.0, 10.0]
    with pytest.raises(ConformanceError):
        GoalTaskWrapper(gymnasium.make("CartPole-v1"))
