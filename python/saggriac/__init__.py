"""saggriac: SAGG-RIAC intrinsically motivated goal exploration with a Rust core.

Quick start::

    import saggriac
    res = saggriac.run(saggriac.Config.from_preset("exp1"), seed=0)
    res.reach_error  # learning curve, numpy array

``import saggriac`` (and ``import saggriac.teachers``) loads numpy and the compiled core only;
runs, results and studies, which need pandas and pyarrow, load on first use of their names.
"""

from importlib import import_module
from typing import Any

from . import _core, environments, testing  # noqa: F401 (saggriac.environments and saggriac.testing without their own import)
from .competence import competence
from .config import PRESETS, Config
from .errors import ConformanceError, InputError, ParameterError, SaggriacError, StorageError
from .teachers import AdrSelector, AlpGmmSelector, CovarGmmSelector, DiscreteLpSelector, GoalGanSelector, PlrSelector, RandomSelector, RiacSelector, SaggRiacSelector, SpdlSelector, TaskListSelector, load_selector

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


# Modules that ``import saggriac`` used to load with everything (so ``saggriac.runner`` worked
# without its own import), by the path they now have: loaded when first asked for.
_SUBMODULES = {
    "goal_selection": "teachers",
    "learner": "runs.learner",
    "reachable": "reachable",
    "resources": "runs.resources",
    "result": "runs.result",
    "runner": "runs.runner",
    "seeding": "seeding",
    "storage": "runs.storage",
    "study": "study",
    "time_budget": "runs.time_budget",
    "runs": "runs",
    "analysis": "analysis",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
    elif name in _SUBMODULES:
        value = import_module(f".{_SUBMODULES[name]}", __name__)
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
    "SaggRiacSelector",
    "RandomSelector",
    "RiacSelector",
    "DiscreteLpSelector",
    "AlpGmmSelector",
    "CovarGmmSelector",
    "AdrSelector",
    "PlrSelector",
    "TaskListSelector",
    "SpdlSelector",
    "GoalGanSelector",
    "load_selector",
    "Study",
    "run_study",
    "load_study",
    "SaggriacError",
    "ConformanceError",
    "ParameterError",
    "InputError",
    "StorageError",
    "competence",
    "__version__",
]
