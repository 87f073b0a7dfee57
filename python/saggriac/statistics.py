"""The former place of :mod:`saggriac.analysis.statistics`, kept so that imports and pickles written against
it keep working: ``saggriac.statistics`` is the same module object."""

import sys

from .analysis import statistics

sys.modules[__name__] = statistics
