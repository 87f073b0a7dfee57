"""The former place of :mod:`saggriac.runs.time_budget`, kept so that imports and pickles written against
it keep working: ``saggriac.time_budget`` is the same module object."""

import sys

from .runs import time_budget

sys.modules[__name__] = time_budget
