"""The former place of :mod:`saggriac.study.reproduce`, kept so that imports and pickles written against
it keep working: ``saggriac.reproduce`` is the same module object."""

import sys

from .study import reproduce

sys.modules[__name__] = reproduce
