import pytest

import saggriac
from saggriac.errors import StorageError


@pytest.fixture(scope="session")
def small_config():
    """A short exp1 run that still shows learning (a few seconds)."""
    return saggriac.Config.from_preset("exp1", n_steps=4000, n_test_goals=30, n_test_configs=30, n_evals=20)


@pytest.fixture(scope="session", autouse=True)
def _sb3_logs_in_pytests_tmp(tmp_path_factory):
    """Stable-Baselines3 makes a log folder per learn() in the system temp dir unless told where;
    point it at pytest's own temp dir, which pytest prunes."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SB3_LOGDIR", str(tmp_path_factory.mktemp("sb3-logs")))
        yield


@pytest.fixture
def unwritable_study_runs(monkeypatch):
    """A study whose runs cannot be written: each run finishes, then its writing fails as a full
    disk would, with the result on the error (as the runner's own failures carry it)."""
    from saggriac.study import spec

    real = spec.run

    def unwritable(cfg, seed, out_dir, **kw):
        res = real(cfg, seed=seed, **kw)
        e = StorageError(f"Cannot write the run to {out_dir}: No space left on device (simulated).")
        e.result = res
        raise e

    monkeypatch.setattr(spec, "run", unwritable)
