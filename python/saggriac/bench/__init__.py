"""The teacher bench: any teacher, built-in or a user's, on tasks of different character, placed
on a leaderboard among saggriac's own teachers (``saggriac bench``; docs/bench.md).

    from saggriac.bench import run_bench
    result = run_bench(["mypkg.teachers:MyTeacher"], out="bench-out", tier="quick")
    result.board        # the leaderboard: task, teacher, seeds, area, final, diff to random, rank

A task is a small class registered with one line (``register``); a teacher is a built-in one by
name (``saggriac.teachers.available()``) or a class by import path with saggriac's teacher
protocol. The parts: ``tasks`` (the task registry and the toy tasks), ``arm`` (the paper's
learner), ``rl`` (deep RL, the sb3 extra), ``oracle`` (goals uniform over what a body reaches), ``maze`` (PointMaze, Gymnasium-Robotics), ``minigrid`` (a deep-RL task list, the minigrid extra), ``value_loss`` (PLR told its value loss), ``teachers`` (building and guarding a teacher),
``expert`` (expert knowledge of a task at TeachMyAgent's levels, as each teacher's parameters),
``runner`` (one run, the pool, resuming), ``report`` (the leaderboard and figures), ``shipped`` (the built-in teachers' results
that ship with the package) and ``suite`` (``run_bench``).
"""

from . import arm, challenges, maze, minigrid, rl  # noqa: F401 (register the arm's tasks, the challenges, deep RL, PointMaze and MiniGrid)
from .runner import BenchError, Job, run_one
from .suite import BenchResult, run_bench
from .tasks import TASKS, TIERS, BenchTask, register
from .teachers import CALL_TIMEOUT, REFERENCE, TeacherError, TeacherSpec, parse_teacher

__all__ = ["run_bench", "BenchResult", "BenchError", "TeacherError", "TeacherSpec", "parse_teacher", "BenchTask", "register", "TASKS", "TIERS", "Job", "run_one", "REFERENCE", "CALL_TIMEOUT"]
