"""saggriac: SAGG-RIAC intrinsically motivated goal exploration with a Rust core.

Quick start::

    import saggriac
    res = saggriac.run(saggriac.Config.from_preset("exp1"), seed=0)
    res.reach_error  # learning curve, numpy array
"""

from . import _core, environments, testing
from .competence import competence
from .config import PRESETS, Config
from .goal_selection import AlpGmmSelector, CovarGmmSelector, DiscreteLpSelector, RandomSelector, RiacSelector, SaggRiacSelector, load_selector
from .errors import ConformanceError, InputError, ParameterError, SaggriacError, StorageError
from .result import RunResult
from .runner import resume, run
from .study import Study, load_study, run_study

__version__ = _core.__version__

__all__ = ["Config", "PRESETS", "run", "resume", "RunResult", "SaggRiacSelector", "RandomSelector", "RiacSelector", "DiscreteLpSelector", "AlpGmmSelector", "CovarGmmSelector", "load_selector", "Study", "run_study", "load_study", "SaggriacError", "ConformanceError", "ParameterError", "InputError", "StorageError", "competence", "__version__"]
