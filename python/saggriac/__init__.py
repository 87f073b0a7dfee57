"""saggriac: SAGG-RIAC intrinsically motivated goal exploration with a Rust core.

Quick start::

    import saggriac
    res = saggriac.run(saggriac.Config.from_preset("exp1"), seed=0)
    res.reach_error  # learning curve, numpy array

``import saggriac`` (and ``import saggriac.teachers``) loads numpy and the compiled core only;
runs, results and studies, which need pandas and pyarrow, load on first use of their names.
"""

import importlib.abc
import importlib.util
import sys
import warnings
from importlib import import_module
from typing import Any

from . import _core, bodies, testing  # noqa: F401 (saggriac.bodies and saggriac.testing without their own import)
from .config import PRESETS, Config
from .errors import ConformanceError, InputError, ParameterError, SaggriacError, StorageError, WorkerRefusalError
from .teachers.competence import competence
from . import teachers as _teachers
from .teachers import TaskListSelector, load_selector

# Every teacher's class (the core's registry) under its name here too.
globals().update({name: getattr(_teachers, name) for name in _teachers.TEACHERS})

__version__ = _core.__version__

# Names whose modules need pandas and pyarrow: imported when first asked for.
_LAZY = {
    "Learner": "runs.learner",
    "run": "runs.runner",
    "resume": "runs.runner",
    "RunResult": "runs.result",
    "Study": "study",
    "run_study": "study",
    "load_study": "study",
}


# Subpackages and modules ``saggriac.<name>`` gives without their own import.
_SUBMODULES = {"runs": "runs", "analysis": "analysis", "study": "study", "seeding": "seeding", "teachers": "teachers", "adapters": "adapters"}

# Former module paths (saggriac <= 0.5) and where each module is now: the one mapping kept for
# old imports, old pickles and old Gymnasium entry points. Importing a former path warns
# (DeprecationWarning) and gives the module itself. ``saggriac.competence`` is not here: that
# name is the function. They are removed in REMOVED_IN (CHANGELOG.md).
REMOVED_IN = "0.7.0"
MOVED = {
    "saggriac.bodies.pusher": "saggriac.config.presets",
    "saggriac.environments": "saggriac.bodies.environments",
    "saggriac.mujoco_arm": "saggriac.bodies.mujoco_arm",
    "saggriac.scale": "saggriac.bodies.scale",
    "saggriac.reachable": "saggriac.bodies.reachable",
    "saggriac.gym": "saggriac.adapters.gym",
    "saggriac.sb3": "saggriac.adapters.sb3",
    "saggriac.syllabus": "saggriac.adapters.syllabus",
    "saggriac.progress_niches": "saggriac.teachers.progress_niches",
    "saggriac.teacher_params": "saggriac.teachers.params",
    "saggriac.goal_selection": "saggriac.teachers",
    "saggriac.teachers.random_goals": "saggriac.teachers.random",
    "saggriac.learner": "saggriac.runs.learner",
    "saggriac.resources": "saggriac.runs.resources",
    "saggriac.result": "saggriac.runs.result",
    "saggriac.runner": "saggriac.runs.runner",
    "saggriac.storage": "saggriac.runs.storage",
    "saggriac.time_budget": "saggriac.runs.time_budget",
    "saggriac.plots": "saggriac.analysis.plots",
    "saggriac.splits": "saggriac.analysis.splits",
    "saggriac.statistics": "saggriac.analysis.statistics",
    "saggriac.reproduce": "saggriac.study.reproduce",
}


def _moved_to(name: str) -> str | None:
    """The path of the module a former path ``name`` (or a module inside it) names now."""
    for old, new in MOVED.items():
        if name == old or name.startswith(old + "."):
            return new + name[len(old) :]
    return None


class _FormerPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports of a former path give the module now at the new one, with a warning."""

    def find_spec(self, fullname: str, path: Any = None, target: Any = None) -> Any:
        new = _moved_to(fullname) if fullname.startswith("saggriac.") else None
        if new is None:
            return None
        try:
            found = importlib.util.find_spec(new)
        except ImportError:
            found = None
        # No module at the new path: not found here, so that the error names what was typed.
        return None if found is None else importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec: Any) -> Any:
        new = _moved_to(spec.name)
        warnings.warn(f"{spec.name} is now {new}: import it from there (the former path will be removed in {REMOVED_IN}).", DeprecationWarning, stacklevel=2)
        module = import_module(new)
        spec.loader_state = module.__spec__  # kept with this import, not on the shared finder
        return module

    def exec_module(self, module: Any) -> None:
        # The import system set the former path's spec on the module: give it its own back.
        module.__spec__ = module.__spec__.loader_state


if not any(isinstance(f, _FormerPaths) for f in sys.meta_path):
    # First, so that a module inside a former path (saggriac.gym.goals) is not found by the
    # path finder inside the moved package and loaded a second time under the former name.
    sys.meta_path.insert(0, _FormerPaths())


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
    elif name in _SUBMODULES:
        value = import_module(f".{_SUBMODULES[name]}", __name__)
    elif f"{__name__}.{name}" in MOVED:
        value = import_module(f"{__name__}.{name}")  # warns, as the import of a former path does
    else:
        raise AttributeError(f"module 'saggriac' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY) | set(_SUBMODULES))


__all__ = [
    "Config",
    "PRESETS",
    "Learner",
    "run",
    "resume",
    "RunResult",
    *_teachers.TEACHERS,
    "TaskListSelector",
    "load_selector",
    "Study",
    "run_study",
    "load_study",
    "SaggriacError",
    "ConformanceError",
    "WorkerRefusalError",
    "ParameterError",
    "InputError",
    "StorageError",
    "competence",
    "__version__",
]
