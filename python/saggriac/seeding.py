"""Seeds: every random stream of a run and where it comes from, in one place.

One root seed per run (``run(config, seed)``, ``Learner(config, seed)``). Its tree:

    root seed
    |- learner      SeedSequence(root).spawn(2)[0]   the core's learner; from it, by SplitMix64
    |  |                                             (rng.rs child_seed(parent, stream)):
    |  |- selector      stream 1  the high level: SAGG-RIAC's region tree, SAGG-Random's draws,
    |  |                          Config(teacher=...), ACTUATOR-RIAC's tree (selector_seed)
    |  |                          (a teacher's own helper stream, RIAC's cuts and the mixture
    |  |                          teachers' EM, is child 1 of that in turn)
    |  |- learning      stream 2  the low level's draws: exploration, babbling, episodic noise
    |  '- arm noise     stream 3  the built-in arm's motor and sensor noise
    |- evaluation   SeedSequence(root).spawn(2)[1]   the test sets (goals, configurations):
    |                                                 the same for every condition of a seed
    '- environment  SeedSequence(root).spawn(3)[2]   a user's environment's reset(seed=...)

Fixed streams, the same for every run (they describe a body or a method, not a run):
:data:`FIXED` (the IK's random restarts, the sample of a chain's reachable set for ACTUATOR's
reset period, a user's body's measure, the placement check).
:func:`seed_tree` gives every seed above for a root seed.
"""

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


#: Streams that do not depend on the run's seed.
FIXED = {
    "min_norm_ik_restarts": 0x1C0F_F1E5,  # evaluation/min_norm_ik.rs: random restarts of the test-set IK
    "actuator_reset_cloud": 0x5EED_C4A1,  # low_level/actuator_babbling.rs: a chain's reachable sample for the reset period
    "body_measure": 0x5CA1E,  # saggriac.bodies.scale: the placements that measure a user's body
    "placement_check": 20101018,  # saggriac.testing: the two configurations of the placement check
}


def seed_tree(seed: int) -> dict[str, int]:
    """Every seed a run with root ``seed`` uses (the tree in this module's text)."""
    from . import _core

    learner, evaluation = derive_seeds(seed)
    return {
        "root": check_seed(seed),
        "learner": learner,
        "selector": int(_core.child_seed(learner, 1)),
        "learning": int(_core.child_seed(learner, 2)),
        "arm_noise": int(_core.child_seed(learner, 3)),
        "evaluation": evaluation,
        "environment": environment_seed(seed),
    }


def selector_seed(seed: int) -> int:
    """The seed a run with root seed ``seed`` gives its own high level (SAGG-RIAC's region tree,
    SAGG-Random's draws, or a ``Config(teacher=...)``): a selector built with it and the run's
    parameters, passed as ``goal_selector=``, chooses exactly the run's own goals."""
    from . import _core

    return int(_core.child_seed(derive_seeds(seed)[0], 1))
