"""The former place of :mod:`saggriac.analysis.plots`, kept so that imports and pickles written against
it keep working: ``saggriac.plots`` is the same module object."""

import sys

from .analysis import plots

sys.modules[__name__] = plots
