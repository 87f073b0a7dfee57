"""The new teachers' limits (issue 44, items 5 and 10): SPDL's dimension is bounded by what an
update can do in seconds (10^4 dimensions made the optimiser panic, 200 took minutes), ADR forgets
its oldest pending boundary samples in constant time, and the core's messages print floats short.
"""

import time

import numpy as np
import pytest

import saggriac as sg
from saggriac.errors import ParameterError

SPDL_RULE = "bounds of at most 30 dimensions (each update runs COBYLA over 2 x d variables, whose cost grows as the cube of the dimension)"


@pytest.mark.parametrize("d", [31, 200, 10_000])
def test_spdl_beyond_its_bound_is_refused_naming_the_rule(d):
    with pytest.raises(ParameterError) as e:
        sg.SpdlSelector(np.zeros(d), np.ones(d))
    assert str(e.value) == f"The 'low/high' parameter of SpdlSelector must be {SPDL_RULE}. Got {d} dimensions instead."


def test_spdl_at_its_bound_updates_in_seconds():
    t = sg.SpdlSelector(np.zeros(30), np.ones(30), seed=1)
    t0 = time.process_time()
    for _ in range(300):
        t.update(t.sample(), 0.5)
    # 2.4 s CPU on the 2-core development machine (two COBYLA updates).
    assert time.process_time() - t0 < 30


def test_adr_past_its_pending_bound_stays_linear():
    # 1.1 M boundary samples never told: 100,000 of them forgotten (87 s before, each a scan).
    t = sg.AdrSelector([0, 0], [1, 1], boundary_prob=1.0, initial_width=0.5, seed=2)
    t0 = time.process_time()
    goals = t.sample_batch(1_100_000)
    assert time.process_time() - t0 < 30
    # The oldest are forgotten, the newest still credited.
    assert t.update(goals[0], 1.0) is None
    assert t.update(goals[-1], 1.0) is not None


@pytest.mark.parametrize(
    "make, shown",
    [
        (lambda: sg.SpdlSelector([0], [1], init_std=1e308), "Got 1e308 instead."),
        (lambda: sg.SpdlSelector([0], [1], target_mean=-1e300), "Got -1e300 instead."),
        (lambda: sg.SpdlSelector([0], [1], delta=1e300), "Got 1e300 instead."),
        (lambda: sg.PlrSelector(4, temperature=1e-300), "Got 1e-300 instead."),
        (lambda: sg.AdrSelector([0], [1], t_low=-1e300), "Got -1e300 instead."),
        (lambda: sg.AdrSelector([0], [1], t_low=0.9, t_high=1e-200), "(t_high = 1e-200). Got 0.9 instead."),
        (lambda: sg.GoalGanSelector([0], [1], success_threshold=1e300), "Got 1e300 instead."),
    ],
)
def test_core_messages_print_floats_short(make, shown):
    with pytest.raises(ParameterError) as e:
        make()
    assert str(e.value).endswith(shown) and len(str(e.value)) < 300, str(e.value)
