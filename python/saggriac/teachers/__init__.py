"""Teachers (goal selectors) on their own, ask/tell style: SAGG-RIAC and the field's other
learning-progress teachers as curricula for any learner. ``saggriac.teachers`` is the same
module under its former name.

    teacher = SaggRiacSelector(low=[0, 0], high=[1, 1], seed=0)
    for _ in range(1000):
        goal = teacher.sample()
        competence = my_learner.try_goal(goal)   # a float (|c| <= 1e100), higher is better (paper: <= 0)
        teacher.update(goal, competence)

The region tree, the interest (competence progress) and the three goal modes are the Rust core's,
the same code the run loop uses.
"""

from importlib import import_module

from .. import _core
from .ask_tell import MAGIC, MODES, AskTellSelector, GoalSelectorProtocol, available, classes, load_selector
from .task_list import TaskListSelector

# The core's registry names every teacher; each has its class in the module of its name here
# (teachers/<name>.py), imported now so that available() and the names below know it.
for _kind in _core.teacher_defaults():
    import_module(f".{_kind}", __name__)
TEACHERS = tuple(c.__name__ for c in available().values())
globals().update({c.__name__: c for c in available().values()})

__all__ = [*TEACHERS, "TaskListSelector", "AskTellSelector", "GoalSelectorProtocol", "load_selector", "available", "classes", "MAGIC", "MODES"]
