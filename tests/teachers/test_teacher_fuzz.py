"""Fuzzing a goal selector with Hypothesis: any sequence of asks and tells gives a result or
a saggriac error, and its leaves keep tiling the box and holding every measurement.

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
from tests.fuzzing import FUZZ, Counts, floats  # noqa: E402
from saggriac.errors import InputError, ParameterError  # noqa: E402


COUNTS = Counts()
count = COUNTS.count




bounds = st.integers(1, 4).flatmap(
    lambda d: st.tuples(
        st.lists(st.floats(-1e6, 1e6), min_size=d, max_size=d),
        st.lists(st.floats(1e-9, 1e6), min_size=d, max_size=d),
    )
)


@FUZZ
@given(
    bounds,
    st.integers(0, 2**63 - 1),
    st.lists(st.tuples(st.sampled_from(["sample", "edge", "corner", "same", "outside", "batch"]), st.one_of(st.floats(-1, 0), floats)), max_size=120),
    st.integers(2, 12),
)
def test_goal_selector_survives_any_sequence(lohw, seed, ops, g_max):
    count("selector")
    lo, width = lohw
    low = np.array(lo)
    high = low + np.array(width)
    if not np.all(high > low):
        return
    try:
        sel = saggriac.SaggRiacSelector(low, high, seed=seed, g_max=g_max, zeta=2, min_child=1)
    except ParameterError:
        return
    told = 0
    for kind, c in ops:
        g = sel.sample()
        assert g.shape == low.shape and np.all(g >= low) and np.all(g <= high)
        if kind == "edge":
            g = g.copy()
            g[0] = high[0]
        elif kind == "corner":
            g = low.copy()
        elif kind == "same":
            g = (low + high) / 2
        elif kind == "outside":
            g = high + 1.0
        try:
            if kind == "batch":
                sel.update_batch(np.array([g, g]), np.array([c, c]))
                told += 2
            else:
                sel.update(g, c)
                told += 1
        except InputError:
            # Refused: a goal outside the box, or a competence beyond the stated range.
            assert kind == "outside" or not (math.isfinite(c) and abs(c) <= 1e100)
            continue
        assert math.isfinite(c) and abs(c) <= 1e100
    h = sel.history()
    assert len(h["told_competence"]) == told
    leaves = sel.leaves()
    # The leaves tile the box and hold every measurement.
    assert int(leaves["n_measurements"].sum()) == told
    vol = np.prod(leaves["high"] - leaves["low"], axis=1).sum()
    assert vol == pytest.approx(np.prod(high - low), rel=1e-9)


def teardown_module(module):
    # The campaign script reads this line.
    print(f"\nfuzz examples: {COUNTS}")
