"""The former place of :mod:`saggriac.runs.storage`, kept so that imports and pickles written against
it keep working: ``saggriac.storage`` is the same module object."""

import sys

from .runs import storage

sys.modules[__name__] = storage
