"""Fuzzing Config with Hypothesis: any keys and values give a configuration the core accepts,
or a ParameterError naming the parameter; never a crash or another exception.

Examples per property: 60 in CI; `SAGGRIAC_FUZZ_EXAMPLES=N` raises it (see
benchmarks/fuzz_campaign.py for the long campaign and its counts).
"""


import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import saggriac  # noqa: E402
from tests.fuzzing import FUZZ, Counts, floats  # noqa: E402
from saggriac.errors import ParameterError, SaggriacError  # noqa: E402


COUNTS = Counts()
count = COUNTS.count


anything = st.one_of(floats, st.integers(-(2**70), 2**70), st.booleans(), st.none(), st.text(max_size=5), st.lists(floats, max_size=4))
FIELDS = sorted(f for f in saggriac.Config.__dataclass_fields__ if f not in ("condition", "paradigm"))


@FUZZ
@given(st.dictionaries(st.sampled_from(FIELDS + ["bogus", "condition", "paradigm"]), anything, max_size=4))
def test_config_accepts_or_names_the_parameter(overrides):
    count("config")
    try:
        cfg = saggriac.Config.from_preset("exp1", **overrides)
    except ParameterError as e:
        assert e.param, str(e)
        return
    except SaggriacError as e:  # any other saggriac error is a defect here
        raise AssertionError(f"unexpected {type(e).__name__}: {e}")
    # Accepted: the core agrees, and the schedule is valid.
    saggriac._core.validate_config(cfg.core_dict())
    s = cfg.schedule()
    assert s == sorted(set(s)) and s[-1] <= cfg.n_steps


def teardown_module(module):
    # The campaign script reads this line.
    print(f"\nfuzz examples: {COUNTS}")
