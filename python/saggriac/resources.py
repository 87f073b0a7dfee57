"""The former place of :mod:`saggriac.runs.resources`, kept so that imports and pickles written against
it keep working: ``saggriac.resources`` is the same module object."""

import sys

from .runs import resources

sys.modules[__name__] = resources
