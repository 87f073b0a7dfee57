"""The former name of :mod:`saggriac.teachers`, kept so that code and pickles written against it
keep working: it is the same module object."""

import sys

from . import teachers

sys.modules[__name__] = teachers
