"""The former place of :mod:`saggriac.runs.result`, kept so that imports and pickles written against
it keep working: ``saggriac.result`` is the same module object."""

import sys

from .runs import result

sys.modules[__name__] = result
