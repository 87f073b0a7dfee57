"""The former place of :mod:`saggriac.runs.runner`, kept so that imports and pickles written against
it keep working: ``saggriac.runner`` is the same module object."""

import sys

from .runs import runner

sys.modules[__name__] = runner
