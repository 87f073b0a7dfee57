import pytest

import saggriac


@pytest.fixture(scope="session")
def small_config():
    """A short exp1 run that still shows learning (a few seconds)."""
    return saggriac.Config.from_preset("exp1", n_steps=4000, n_test_goals=30, n_test_configs=30, n_evals=20)
