"""Saving and restoring teachers: pickle, copy, a file; each continues with the same goals."""

import copy
import functools
import pickle

import numpy as np
import pytest

import saggriac as sg

# Every registered teacher, with its slow parameters made quick where it has them.
QUICK = {
    "sagg_riac": {"g_max": 12, "zeta": 6},
    "riac": {"max_region_size": 20, "split_attempts": 10},
    "alp_gmm": {"fit_rate": 40, "bootstrap": 40, "max_components": 4},
    "covar_gmm": {"fit_rate": 40, "bootstrap": 40, "max_components": 4},
    "adr": {"buffer_size": 3, "t_low": 0.3, "t_high": 0.6},
    "spdl": {"update_every": 20, "warmup": 20, "delta": -0.6},
    "goal_gan": {"update_size": 10, "gan_iterations": 10, "hidden": 8, "success_threshold": -0.5},
}
TEACHERS = [functools.partial(sg.testing.example_teacher, kind, seed, **QUICK.get(kind, {})) for seed, kind in enumerate(sg.teachers.available(), start=3)]
TEACHERS += [
    lambda: sg.SaggRiacSelector([0.0, -1.0, 5.0], [1.0, 1.0, 6.0], seed=7, g_max=12, zeta=6),
    lambda: sg.CovarGmmSelector([0.0], [3.0], seed=6, fit_rate=40, bootstrap=40, max_components=4),
    lambda: sg.PlrSelector(5, seed=11, score="told", replay_schedule="fixed", staleness_coef=0.3),
]


def test_the_quick_settings_name_registered_teachers():
    assert set(QUICK) <= set(sg.teachers.available())


def competence(g, teacher=None):
    c = float(np.clip(-0.5 + 0.3 * np.sin(4 * g[0]), -1, 0))
    return c + 1.0 if teacher is not None and teacher.competence_range[0] == 0.0 else c


@pytest.mark.parametrize("make", TEACHERS)
@pytest.mark.parametrize("how", ["pickle", "deepcopy", "file"])
def test_a_restored_teacher_asks_the_same_goals(make, how, tmp_path):
    t = make()
    for _ in range(150):
        g = t.sample()
        t.update(g, competence(g, t))
    if how == "pickle":
        u = pickle.loads(pickle.dumps(t))
    elif how == "deepcopy":
        u = copy.deepcopy(t)
    else:
        u = sg.load_selector(t.save(tmp_path / "teacher.bin"))
    assert type(u) is type(t) and u.seed == t.seed
    for k, v in t.history().items():
        assert np.array_equal(u.history()[k], v)
    for _ in range(150):
        g, h = t.sample(), u.sample()
        assert np.array_equal(g, h) and t.last_mode == u.last_mode
        t.update(g, competence(g, t))
        u.update(h, competence(h, u))
    assert np.array_equal(t.sample_batch(20), u.sample_batch(20))


@pytest.mark.parametrize("make", TEACHERS)
def test_check_goal_selector_covers_restoring(make):
    sg.testing.check_goal_selector(make())


class Forgetful(sg.RandomSelector):
    """Restores to a fresh generator: not the same goals."""

    def __setstate__(self, state):
        super().__setstate__(state)
        self._inner = sg._core.AskTell("random", [0.0], [2.0], 1234)


def test_a_teacher_that_forgets_on_restore_fails_the_check():
    with pytest.raises(sg.ConformanceError, match="restored by pickle must ask the same goals"):
        sg.testing.check_goal_selector(Forgetful([0.0], [2.0], seed=9))


def test_saving_never_overwrites_or_misreads(tmp_path):
    t = sg.SaggRiacSelector([0, 0], [1, 1], seed=1)
    mine = tmp_path / "notes.txt"
    mine.write_text("my notes")
    with pytest.raises(sg.StorageError, match="exists; pass overwrite=True"):
        t.save(mine)
    assert mine.read_text() == "my notes"
    with pytest.raises(sg.StorageError, match="is a folder"):
        t.save(tmp_path)
    with pytest.raises(sg.InputError, match="not a teacher saved by saggriac"):
        sg.load_selector(mine)
    path = t.save(tmp_path / "t.bin")
    data = path.read_bytes()
    damaged = tmp_path / "damaged.bin"
    damaged.write_bytes(data[:-9] + bytes([data[-9] ^ 0xFF]) + data[-8:])
    with pytest.raises(sg.InputError, match="damaged"):
        sg.load_selector(damaged)
    with pytest.raises(sg.StorageError, match="Cannot read"):
        sg.load_selector(tmp_path / "missing.bin")
    t.save(path, overwrite=True)
    assert sg.load_selector(path).sample().shape == (2,)
    # No temporary file is left behind.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["damaged.bin", "notes.txt", "t.bin"]


def test_riac_focuses_where_competence_progresses():
    t = sg.RiacSelector([0.0, 0.0], [1.0, 1.0], seed=1, max_region_size=60)
    for k in range(3000):
        g = t.sample()
        # Competence rises over time for x < 0.3 only.
        t.update(g, min(0.0, -1.0 + k / 3000.0) if g[0] < 0.3 else -0.5)
    leaves = t.leaves()
    assert t.n_regions > 1 and np.all(leaves["high"] - leaves["low"] >= 1 / 6 - 1e-12)
    late = t.history()["asked_goal"][-1000:]
    assert np.mean(late[:, 0] < 0.3) > 0.45  # uniform would give 0.3


def test_discrete_lp_prefers_the_task_being_learnt():
    t = sg.DiscreteLpSelector(5, seed=2)
    rng = np.random.default_rng(0)
    learnt = np.zeros(5)
    for _ in range(2000):
        i = t.sample_task()
        learnt[i] += 1
        # Task 3 is learnable: its success grows with practice. The others stay at 0 or 1.
        p = {3: min(1.0, learnt[3] / 300.0), 0: 1.0}.get(i, 0.0)
        t.update(i, float(rng.random() < p))
    counts = np.bincount(t.history()["asked_goal"][:1500, 0].astype(int), minlength=5)
    assert counts[3] == counts.max() and counts.min() > 0, counts
    with pytest.raises(sg.InputError, match="whole number in \\[0, 5\\)"):
        t.update(2.5, 0.5)
    with pytest.raises(sg.InputError, match="success rate in \\[0, 1\\]"):
        t.update(2, -0.5)
    with pytest.raises(sg.ParameterError, match="'n_tasks' parameter of DiscreteLpSelector"):
        sg.DiscreteLpSelector(0)


@pytest.mark.parametrize("cls", [sg.AlpGmmSelector, sg.CovarGmmSelector])
def test_mixture_teachers_focus_where_competence_progresses(cls):
    t = cls([0.0, 0.0], [1.0, 1.0], seed=2, fit_rate=150, bootstrap=150)
    for k in range(3000):
        g = t.sample()
        t.update(g, min(0.0, -1.0 + k / 1500.0) if g[0] < 0.3 else -0.5)
    # While competence still rises there (it saturates at goal 1500).
    during = t.history()["asked_goal"][500:1500]
    assert np.mean(during[:, 0] < 0.3) > 0.5  # uniform would give 0.3
    assert np.all((t.history()["asked_goal"] >= 0) & (t.history()["asked_goal"] <= 1))


@pytest.mark.parametrize(
    "make, param",
    [
        (lambda: sg.AlpGmmSelector([0], [1], max_components=300), "max_components"),
        (lambda: sg.AlpGmmSelector([0], [1], random_task_ratio=2.0), "random_task_ratio"),
        (lambda: sg.CovarGmmSelector([0], [1], absolute_lp="yes"), "absolute_lp"),
        (lambda: sg.CovarGmmSelector([1], [0]), "low/high"),
        (lambda: sg.RiacSelector([0], [1], split_attempts=0), "split_attempts"),
        (lambda: sg.AdrSelector([0], [1], t_low=0.9, t_high=0.5), "t_low"),
        (lambda: sg.AdrSelector([0], [1], step=0.0), "step"),
        (lambda: sg.AdrSelector([0], [1], initial=1.5), "initial"),
        (lambda: sg.AdrSelector([0], [1], boundary_prob=-0.1), "boundary_prob"),
        (lambda: sg.PlrSelector(4, temperature=0.0), "temperature"),
        (lambda: sg.PlrSelector(4, staleness_coef=1.5), "staleness_coef"),
        (lambda: sg.PlrSelector(4, replay_schedule="sometimes"), "replay_schedule"),
        (lambda: sg.PlrSelector(4, score="value"), "score"),
    ],
)
def test_teacher_parameters_are_checked(make, param):
    with pytest.raises(sg.ParameterError) as e:
        make()
    assert e.value.param == param


RUN_PARAMS = {"adr": {"t_low": -0.9, "t_high": -0.3, "buffer_size": 3}}


@pytest.mark.parametrize("teacher", ["riac", "alp_gmm", "covar_gmm", "adr"])
def test_a_teacher_chooses_the_goals_of_a_run(teacher, tmp_path):
    cfg = sg.Config.from_preset("exp1", teacher=teacher, teacher_params=RUN_PARAMS.get(teacher, {}), n_steps=3000, n_evals=2)
    a = sg.run(cfg, seed=4)
    own = sg.run(cfg.replace(teacher="own", teacher_params={}), seed=4)
    assert not a.goals[["goal_x", "goal_y"]].equals(own.goals[["goal_x", "goal_y"]])
    # Deterministic, and the same when the run is checkpointed as it goes.
    b = sg.run(cfg, seed=4, out_dir=tmp_path / "b", checkpoint_every=1000)
    assert a.attempts.equals(b.attempts) and np.array_equal(a.reach_error, b.reach_error)
    assert sg.RunResult.load(tmp_path / "b").config.teacher == teacher


@pytest.mark.parametrize("teacher", ["riac", "alp_gmm", "covar_gmm"])
@pytest.mark.parametrize("kw", [dict(g_max=40), dict(zeta=10), dict(p_interest=0.6, p_global=0.3), dict(interest_divisor="window")])
def test_sagg_riac_parameters_are_refused_under_another_teacher(teacher, kw):
    """They set SAGG-RIAC's own high level, which another teacher replaces: ignoring them
    silently (as before) would run something else than asked."""
    with pytest.raises(sg.ParameterError, match=f"'{next(iter(kw))}' parameter of Config must be left at its default with teacher '{teacher}'"):
        sg.Config(teacher=teacher, **kw)
    assert sg.Config(teacher=teacher).teacher == teacher


def test_plr_refuses_goals_that_are_not_levels_and_changes_nothing():
    t = sg.PlrSelector(4, seed=0)
    for bad in (4, -1, 1.5, [0, 1]):
        with pytest.raises(sg.InputError):
            t.update(bad, 0.5)
    with pytest.raises(sg.InputError, match="finite"):
        t.update(2, float("nan"))
    assert len(t.history()["told_competence"]) == 0


def test_plr_draws_every_level_before_replaying_and_replays_by_score():
    """New levels first (the proportionate schedule replays with probability |seen| / n); once
    every level is seen, replays follow the rank of the told scores."""
    t = sg.PlrSelector(8, seed=3, score="told", staleness_coef=0.0)
    first = [t.sample_task() for _ in range(3)]
    assert len(set(first)) == 3  # the first draws are new levels (|seen| / 8 <= 2/8)
    for k in range(8):
        t.update(k, 1.0 if k == 5 else 0.1 * k / 8)
    counts = np.bincount([t.sample_task() for _ in range(2000)], minlength=8)
    # Rank 1 gets 1 / (1 + 2^-10 + ...) of the replays.
    assert counts[5] > 0.99 * 2000


def test_adr_bounds_grow_where_competence_is_high_and_shrink_where_low():
    """The paper's behaviour: a bound whose boundary competence is >= t_high moves outwards,
    <= t_low inwards; goals stay in the current ranges, inside the box."""
    t = sg.AdrSelector([0.0, 0.0], [1.0, 1.0], seed=2, buffer_size=5, step=0.05)
    assert np.array_equal(t.bounds[0], [0.5, 0.5]) and np.array_equal(t.bounds[1], [0.5, 0.5])
    for _ in range(6000):
        g = t.sample()
        lo, hi = t.bounds
        assert np.all(g >= lo) and np.all(g <= hi)
        t.update(g, 1.0 if g[0] <= 0.75 else 0.0)  # learnable below x = 0.75 only
    lo, hi = t.bounds
    assert lo[0] == 0.0 and 0.7 <= hi[0] <= 0.8 + 1e-9 and lo[1] == 0.0 and hi[1] == 1.0
