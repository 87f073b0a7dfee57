"""The former place of :mod:`saggriac.runs.learner`, kept so that imports and pickles written against
it keep working: ``saggriac.learner`` is the same module object."""

import sys

from .runs import learner

sys.modules[__name__] = learner
