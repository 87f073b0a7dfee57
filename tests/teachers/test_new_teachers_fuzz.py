"""Fuzzing the teachers of the field (ADR, SPDL, Goal GAN, PLR, discrete LP) with Hypothesis: any
constructor arguments (sizes, numpy scalars, bools, NaN, infinities, strings) and any sequence of
calls (batches of any size, goals outside the box, wrong shapes, competences of any float) give a
result or a saggriac error, never another exception, a Rust panic or a goal outside the space.

Examples per property: 60 in CI; ``SAGGRIAC_FUZZ_EXAMPLES=N`` raises it.
"""

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import saggriac  # noqa: E402
from saggriac.errors import SaggriacError  # noqa: E402
from tests.fuzzing import FUZZ, Counts, floats  # noqa: E402

COUNTS = Counts()
count = COUNTS.count

BOX = {
    saggriac.AdrSelector: ["boundary_prob", "buffer_size", "t_low", "t_high", "step", "initial", "initial_width"],
    saggriac.SpdlSelector: ["init_mean", "init_std", "target_mean", "target_std", "epsilon", "delta", "update_every", "warmup", "form", "covariance", "alpha_offset", "alpha_zeta", "init_cov", "target_cov"],
    saggriac.GoalGanSelector: ["success_threshold", "r_min", "r_max", "n_rollouts", "update_size", "gan_iterations", "p_old", "noise_dim", "hidden", "learning_rate", "initial", "initial_width"],
}
LISTS = {
    saggriac.PlrSelector: ["temperature", "staleness_coef", "replay_schedule", "replay_prob", "score", "ties"],
    saggriac.DiscreteLpSelector: ["alpha", "theta"],
}

#: Any value a user may pass: numbers of every kind and size, numpy scalars, and nonsense.
values = st.one_of(
    floats,
    st.integers(-(2**70), 2**70),
    st.sampled_from([0, 1, 2, -1, 3, 10, 1000, 2**31, 2**63, True, False, None, "1", "", "value_l1", "proportionate", "progress", "order", "average", "alpha", "full", [1.0], (0.5,), [[0.01, 0.0], [0.0, 0.01]], [[1.0, 2.0], [2.0, 1.0]], [[0.5]], [["a"]]]),
    st.lists(st.one_of(floats, st.floats(0, 1)), max_size=4),
    st.builds(np.int64, st.integers(-(2**40), 2**40)),
    st.builds(np.float32, st.floats(width=32, allow_nan=True)),
    st.builds(np.float64, floats),
    st.sampled_from([np.bool_(True), np.int8(3), np.uint64(2**63), np.array(0.5), np.array([0.5, 0.5])]),
)
sizes = st.one_of(
    st.integers(-3, 40),
    st.sampled_from([True, 1.5, np.int64(5), np.float64(2.0), "3", None, 10**7 + 1, 2**63, -(2**63)]),
)
ops = st.lists(
    st.tuples(st.sampled_from(["sample", "batch", "update", "update_batch", "outside", "shape", "history"]), sizes, st.one_of(st.floats(0, 1), floats)),
    max_size=60,
)


def _call(fn, *args):
    """The call's result, or None when it raised a saggriac error; anything else fails the test
    (a PanicException is a BaseException, so it is caught here too)."""
    try:
        return fn(*args)
    except SaggriacError:
        count("refused")
        return None
    except BaseException as e:  # noqa: BLE001 - the point of the test
        pytest.fail(f"{fn} raised {type(e).__name__}: {e}")


def _drive(t, space, steps):
    low, high = space
    goal = None
    for kind, n, c in steps:
        if kind == "sample":
            goal = _call(t.sample)
            if goal is not None:
                goal = np.asarray(goal, dtype=float)
                assert np.all(goal >= low) and np.all(goal <= high), (goal, low, high)
        elif kind == "batch":
            batch = _call(t.sample_batch, n)
            if batch is not None:
                batch = np.asarray(batch, dtype=float)
                assert len(batch) == int(n) and np.all(batch >= low) and np.all(batch <= high)
        elif kind == "update" and goal is not None:
            _call(t.update, goal.reshape(np.shape(goal)), c)
        elif kind == "update_batch" and goal is not None:
            k = n if isinstance(n, int) and not isinstance(n, bool) and 0 <= n <= 40 else 2
            _call(t.update_batch, np.repeat(np.atleast_1d(goal)[None, :], k, axis=0) if np.ndim(goal) else np.full(k, goal), np.full(k, c))
        elif kind == "outside":
            _call(t.update, np.atleast_1d(high) + 1.0 if np.ndim(high) else high + 1, c)
        elif kind == "shape":
            _call(t.update, np.zeros(7), c)
        elif kind == "history":
            h = _call(t.history)
            assert h is None or isinstance(h, dict)


@FUZZ
@given(st.sampled_from(sorted(BOX, key=lambda c: c.__name__)), st.integers(1, 4), st.data(), st.integers(0, 2**64 + 5), ops)
def test_a_box_teacher_survives_any_arguments_and_calls(cls, dim, data, seed, steps):
    count(cls.__name__)
    params = {name: data.draw(values, label=name) for name in data.draw(st.lists(st.sampled_from(BOX[cls]), unique=True, max_size=3), label="names")}
    low, high = np.zeros(dim), np.ones(dim)
    t = _call(lambda: cls(low, high, seed=seed, **params))
    if t is None:
        return
    count(f"{cls.__name__} built")
    _drive(t, (low, high), steps)


@FUZZ
@given(st.sampled_from(sorted(LISTS, key=lambda c: c.__name__)), st.one_of(st.integers(-2, 12), values), st.data(), st.integers(0, 2**64 + 5), ops)
def test_a_task_list_teacher_survives_any_arguments_and_calls(cls, n_tasks, data, seed, steps):
    count(cls.__name__)
    params = {name: data.draw(values, label=name) for name in data.draw(st.lists(st.sampled_from(LISTS[cls]), unique=True, max_size=3), label="names")}
    t = _call(lambda: cls(n_tasks, seed=seed, **params))
    if t is None:
        return
    count(f"{cls.__name__} built")
    _drive(t, (0, t.n_tasks - 1), steps)


@FUZZ
@given(st.sampled_from(sorted(BOX, key=lambda c: c.__name__)), st.one_of(st.integers(0, 3), st.sampled_from([101, 1000, 10**4, 10**6])), st.sampled_from([np.nan, np.inf, -np.inf, 1e308, -1e308]))
def test_a_box_of_any_size_or_with_non_finite_bounds_is_built_or_refused(cls, dim, bad):
    low, high = np.zeros(dim), np.ones(dim)
    _call(lambda: cls(low, high))  # too many dimensions: refused with the bound, never a panic or a long wait
    if dim:
        low2 = low.copy()
        low2[0] = bad
        assert _call(lambda: cls(low2, high)) is None or bad == -1e308


def test_the_fuzz_met_every_teacher():
    if COUNTS:  # run after the properties in this file
        for cls in list(BOX) + list(LISTS):
            assert COUNTS.get(cls.__name__, 0) > 0, COUNTS


def teardown_module(module):
    # The campaign script reads this line.
    print(f"\nfuzz examples: {COUNTS}")
