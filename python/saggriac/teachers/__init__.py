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

from .adr import AdrSelector
from .alp_gmm import AlpGmmSelector
from .ask_tell import MAGIC, MODES, AskTellSelector, GoalSelectorProtocol, available, classes, load_selector
from .covar_gmm import CovarGmmSelector
from .discrete_lp import DiscreteLpSelector
from .goal_gan import GoalGanSelector
from .plr import PlrSelector
from .random_goals import RandomSelector
from .riac import RiacSelector
from .sagg_riac import SaggRiacSelector
from .spdl import SpdlSelector
from .task_list import TaskListSelector

__all__ = [
    "SaggRiacSelector", "RandomSelector", "RiacSelector", "AlpGmmSelector", "CovarGmmSelector", "AdrSelector", "SpdlSelector", "GoalGanSelector",
    "TaskListSelector", "DiscreteLpSelector", "PlrSelector",
    "AskTellSelector", "GoalSelectorProtocol", "load_selector", "available", "classes", "MAGIC", "MODES",
]
