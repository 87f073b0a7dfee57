"""Fuzzing tiny runs with Hypothesis: every condition, paradigm and small arm finishes with
finite learning curves, or is refused with a ParameterError.

Examples per property: 60 in CI; `SAGGRIAC_FUZZ_EXAMPLES=N` raises it (see
benchmarks/fuzz_campaign.py for the long campaign and its counts).
"""

import math

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import saggriac  # noqa: E402
from tests.fuzzing import FUZZ, Counts  # noqa: E402
from saggriac.errors import ParameterError  # noqa: E402


COUNTS = Counts()
count = COUNTS.count


@FUZZ
@given(
    st.sampled_from(["sagg_riac", "sagg_random", "actuator_random", "actuator_riac"]),
    st.sampled_from(["micro_actions", "episodic"]),
    st.integers(1, 300),
    st.integers(1, 6),
    st.floats(0.05, math.pi),
    st.integers(0, 2**63 - 1),
    st.sampled_from(["exp1", "arm3d"]),
)
def test_tiny_runs_finish_with_finite_curves(condition, paradigm, n_steps, n_joints, limit, seed, preset):
    count("run")
    try:
        cfg = saggriac.Config.from_preset(preset, condition=condition, paradigm=paradigm, n_steps=n_steps, n_joints=n_joints, joint_limit=limit, n_evals=2, n_test_goals=5, n_test_configs=5, k_neighbours=3, g_max=6, zeta=2, min_child=1, episodic_k=2)
    except ParameterError:
        return
    res = saggriac.run(cfg, seed=seed)
    assert res.steps[-1] == n_steps
    assert np.all(np.isfinite(res.reach_error)) and np.all(np.isfinite(res.pred_error))


def teardown_module(module):
    # The campaign script reads this line.
    print(f"\nfuzz examples: {COUNTS}")
