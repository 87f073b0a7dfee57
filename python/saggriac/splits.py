"""The former place of :mod:`saggriac.analysis.splits`, kept so that imports and pickles written against
it keep working: ``saggriac.splits`` is the same module object."""

import sys

from .analysis import splits

sys.modules[__name__] = splits
