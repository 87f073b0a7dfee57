"""Evaluating does not change what a run learns: the last evaluation gives the same numbers
whatever the schedule before it. benchmarks/sensitivity.py relies on this to evaluate its runs
only at the end."""

import pytest

import saggriac as sg

CASES = [(p, c) for p in ("exp1", "exp2") for c in ("sagg_riac", "sagg_random", "actuator_random", "actuator_riac")] + [("explauto", "sagg_riac"), ("explauto", "sagg_random")]


@pytest.mark.parametrize("preset,condition", CASES)
def test_the_last_evaluation_does_not_depend_on_the_earlier_ones(preset, condition):
    small = dict(n_steps=1200, n_test_goals=12, n_test_configs=12, condition=condition)
    dense = sg.run(sg.Config.from_preset(preset, n_evals=6, **small), seed=7, threads=1)
    sparse = sg.run(sg.Config.from_preset(preset, n_evals=1, **small), seed=7, threads=1)
    assert len(dense.metrics) == 7 and len(sparse.metrics) == 2
    assert dense.metrics.iloc[-1].to_dict() == sparse.metrics.iloc[-1].to_dict()
    # What the run did is the same too, not only its last row.
    assert dense.goals.equals(sparse.goals)
