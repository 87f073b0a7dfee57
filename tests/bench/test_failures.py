"""A teacher that raises, hangs past the bound, or asks goals outside the space gets an error that
names the teacher, the task and the seed; every other run is kept and on the leaderboard."""

import pytest

from saggriac.bench import BenchError, run_bench
from saggriac.errors import ParameterError

from .teachers_module import write


@pytest.fixture
def module(tmp_path):
    (tmp_path / "user").mkdir()
    return write(tmp_path / "user")


def _bench(module, tmp_path, bad, **kw):
    with pytest.raises(BenchError) as info:
        run_bench([f"{module}:Uniform", f"{module}:{bad}"], out=tmp_path / "out", tasks=["2d", "niches-0"], seeds=2, progress=False, expert=False, **kw)
    err = info.value
    board = err.result.board
    # The good teacher's runs are all there, the bad one's are not.
    assert set(board[board.teacher == f"{module}:Uniform"].task) == {"2d", "niches-0"}
    assert f"{module}:{bad}" not in set(board.teacher)
    assert len(err.failures) == 4 and (tmp_path / "out" / "errors.csv").is_file()
    return str(err)


def test_a_raising_teacher_is_named_with_task_and_seed_in_worker_processes(module, tmp_path):
    msg = _bench(module, tmp_path, "Raises", workers=2)
    assert f"teacher {module}:Raises on task '2d', seed 0 raised ValueError: my teacher broke (when it was told a competence (update); call 100)" in msg
    assert "task 'niches-0', seed 1" in msg and "4 of 8 bench runs failed" in msg


def test_a_goal_outside_the_box_is_refused(module, tmp_path):
    msg = _bench(module, tmp_path, "OutOfBox", workers=1)
    assert f"teacher {module}:OutOfBox on task 'niches-0', seed 1 asked the goal array([2., 2.]) (call 7), which is outside the space: the goals are 2 floats in the box low=[0.0, 0.0], high=[1.0, 1.0]" in msg


def test_a_teacher_that_hangs_is_stopped_at_the_bound(module, tmp_path):
    msg = _bench(module, tmp_path, "Hangs", workers=1, timeout=0.3)
    assert f"teacher {module}:Hangs on task '2d', seed 0 took more than 0.3 s in one call (it was asked a goal (sample); call 4)" in msg


def test_a_task_index_that_does_not_exist_is_refused(module, tmp_path):
    with pytest.raises(BenchError, match=r"on task '2d-cells', seed 0 asked the goal 100 \(call 5\), which is not a task index: the goals are ints in \[0, 100\)"):
        run_bench([f"{module}:FirstTask"], out=tmp_path / "out", tasks=["2d-cells"], seeds=1, workers=1, progress=False)


@pytest.mark.parametrize(("kw", "words"), [
    (dict(teachers=["no_such_teacher"]), "The '--teacher' parameter of saggriac bench must be a built-in teacher's name"),
    (dict(teachers=["os.path:nothing"]), "os.path has no class 'nothing'"),
    (dict(tier="huge"), "The 'tier' parameter of run_bench must be one of quick, standard, full. Got 'huge' instead."),
    (dict(seeds=0), "The 'seeds' parameter of run_bench must be an int >= 1. Got 0 instead."),
    (dict(tasks=["3d"]), "The 'tasks' parameter of run_bench must name tasks of the bench"),
    (dict(timeout=-1), "The 'timeout' parameter of run_bench must be seconds in (0, 1e6). Got -1 instead."),
])
def test_bad_arguments_are_named(tmp_path, kw, words):
    with pytest.raises(ParameterError) as info:
        run_bench(out=tmp_path / "out", progress=False, **kw)
    assert words in str(info.value)


class Says:
    """A teacher that takes any box (an infinite one too) and asks the goals it is handed, in turn."""

    def __init__(self, low, high, seed=0):
        self.goals = iter(())

    def sample(self):
        return next(self.goals)

    def update(self, goal, competence):
        pass


@pytest.mark.parametrize("infinite", [False, True])
def test_nan_and_infinite_goals_are_refused_in_finite_and_infinite_boxes(infinite):
    """The guard's one-pass check: NaN fails every comparison; an infinity is outside a finite box,
    and still refused when the task's box is itself infinite."""
    import numpy as np

    from saggriac.bench import TASKS, parse_teacher
    from saggriac.bench.teachers import Guarded, TeacherError

    task = TASKS["2d"](0)
    if infinite:
        task.low, task.high = np.array([-np.inf, 0.0]), np.array([np.inf, 1.0])
    g = Guarded(parse_teacher(f"{__name__}:Says"), task, 0, 30.0)
    bad = [[np.nan, 0.5], [0.5, np.nan], [np.inf, 0.5], [-np.inf, 0.5], [0.5, 0.5, 0.5], [0.5]]
    g.teacher.goals = iter([[0.25, 0.75]] + bad)
    assert g.ask().tolist() == [0.25, 0.75]
    for goal in bad:
        with pytest.raises(TeacherError, match=r"which is outside the space"):
            g.ask()
