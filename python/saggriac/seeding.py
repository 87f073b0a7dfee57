"""Seeds. One root seed per run; the learner's and the evaluation's seeds derive from it with
numpy's SeedSequence, so the test sets depend only on the experiment seed, not the condition."""

from __future__ import annotations

import numpy as np

from .errors import ParameterError


def check_seed(seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= int(seed) < 2**63:
        raise ParameterError(f"The 'seed' parameter must be an int in [0, 2**63). Got {seed!r} instead.", "seed", repr(seed))
    return int(seed)


def environment_seed(seed: int) -> int:
    """Seed passed once to a user's environment's ``reset(seed=...)``: a third child of the root
    seed, independent of the learner's and the evaluation's."""
    child = np.random.SeedSequence(check_seed(seed)).spawn(3)[2]
    return int(child.generate_state(1, np.uint64)[0])


def derive_seeds(seed: int) -> tuple[int, int]:
    """(learner_seed, eval_seed) for a root seed."""
    learner, evaluation = np.random.SeedSequence(check_seed(seed)).spawn(2)
    return int(learner.generate_state(1, np.uint64)[0]), int(evaluation.generate_state(1, np.uint64)[0])


def selector_seed(seed: int) -> int:
    """The seed a run with root seed ``seed`` gives its own high level (SAGG-RIAC's region tree,
    SAGG-Random's draws, or a ``Config(teacher=...)``): a selector built with it and the run's
    parameters, passed as ``goal_selector=``, chooses exactly the run's own goals."""
    from . import _core

    return int(_core.child_seed(derive_seeds(seed)[0], 1))
