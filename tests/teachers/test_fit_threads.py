"""The mixture teachers' refit on several threads (issue 49 item 4): the goals a user gets, and
what a saved teacher holds, do not depend on the threads; SAGGRIAC_FIT_THREADS caps them and a
bad value is refused when the teacher is built, naming the variable, the value and the rule."""

import numpy as np
import pytest

import saggriac as sg

MIXTURES = [sg.AlpGmmSelector, sg.CovarGmmSelector]


def goals_and_saved(cls, d, n, path):
    t = cls([0.0] * d, [1.0] * d, seed=7)
    goals = []
    for i in range(n):
        g = np.asarray(t.sample())
        t.update(g, float(np.clip(0.8 * g[0] + 0.2 * np.cos(5 * g[-1]) + 0.001 * (i % 13), 0, 1)))
        goals.append(g)
    return np.array(goals), t.save(path).read_bytes()


@pytest.mark.parametrize("cls", MIXTURES)
@pytest.mark.parametrize("d", [2, 10])
def test_goals_and_saved_teacher_are_the_same_on_any_number_of_threads(cls, d, monkeypatch, tmp_path):
    # 800 updates: three refits of the 250-row window, large enough to run on threads.
    monkeypatch.delenv("SAGGRIAC_FIT_THREADS", raising=False)
    free, free_saved = goals_and_saved(cls, d, 800, tmp_path / "free.bin")
    runs = {}
    for cap in ("1", "2", "9"):
        monkeypatch.setenv("SAGGRIAC_FIT_THREADS", cap)
        runs[cap] = goals_and_saved(cls, d, 800, tmp_path / f"cap{cap}.bin")
    for cap, (goals, saved) in runs.items():
        assert goals.tobytes() == free.tobytes(), f"goals differ with SAGGRIAC_FIT_THREADS={cap}"
        assert saved == free_saved, f"saved teacher differs with SAGGRIAC_FIT_THREADS={cap}"


@pytest.mark.parametrize("cls", MIXTURES)
@pytest.mark.parametrize("bad", ["0", "-1", "two", "1.5", ""])
def test_a_bad_cap_is_refused_naming_variable_value_and_rule(cls, bad, monkeypatch):
    monkeypatch.setenv("SAGGRIAC_FIT_THREADS", bad)
    with pytest.raises(sg.ParameterError, match=rf"The 'SAGGRIAC_FIT_THREADS' parameter of {cls.__name__} must be a whole number >= 1 when set .* Got \"{bad}\" instead"):
        cls([0.0, 0.0], [1.0, 1.0], seed=0)


def test_pool_workers_take_their_share_of_the_cores_unless_the_user_capped_them(monkeypatch):
    """The bench's and the studies' worker processes run share_cores: N workers side by side
    each give a refit cores // N threads (at least 1), and a cap the user set is kept."""
    from saggriac.runs import resources

    monkeypatch.setattr(resources, "usable_cores", lambda: 8)
    for workers, want in [(1, "8"), (2, "4"), (3, "2"), (8, "1"), (16, "1")]:
        monkeypatch.delenv("SAGGRIAC_FIT_THREADS", raising=False)
        resources.share_cores(workers)
        assert resources.os.environ["SAGGRIAC_FIT_THREADS"] == want, workers
    monkeypatch.setenv("SAGGRIAC_FIT_THREADS", "3")
    resources.share_cores(2)
    assert resources.os.environ["SAGGRIAC_FIT_THREADS"] == "3"


def _cap_here():
    import os

    return os.environ.get("SAGGRIAC_FIT_THREADS")


def test_a_study_pool_worker_starts_with_its_share(monkeypatch):
    """The studies' pool initializer, in a real spawned worker: 2 workers, each half the cores."""
    import concurrent.futures as cf
    import multiprocessing
    import os

    from saggriac.runs.resources import usable_cores
    from saggriac.study import backends

    monkeypatch.delenv("SAGGRIAC_FIT_THREADS", raising=False)
    with cf.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"), initializer=backends._die_with_parent, initargs=(os.getpid(), 2)) as pool:
        assert pool.submit(_cap_here).result() == str(max(1, usable_cores() // 2))
    assert "SAGGRIAC_FIT_THREADS" not in os.environ  # the parent's own environment is left alone
