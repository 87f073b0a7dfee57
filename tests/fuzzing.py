"""What the Hypothesis fuzz tests share: how many examples a property gets (60 in CI;
``SAGGRIAC_FUZZ_EXAMPLES=N`` raises it, see benchmarks/fuzz_campaign.py), settings that make a run
repeatable, and the count of cases each property met (printed by each file for the campaign)."""

import math
import os

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

EXAMPLES = int(os.environ.get("SAGGRIAC_FUZZ_EXAMPLES", "60"))


def fuzz_settings(examples: int = EXAMPLES) -> settings:
    return settings(max_examples=examples, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck), database=None)


FUZZ = fuzz_settings()

#: Any float, the edges drawn often: zeros of both signs, the tiniest and huge ones, NaN, inf.
floats = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-300, -1e-300, 1e300, 5e-324, 0.5, 1.0, 2.0, math.pi]),
)


class Counts(dict):
    """Cases met per kind."""

    def count(self, name: str) -> None:
        self[name] = self.get(name, 0) + 1
