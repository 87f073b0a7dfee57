"""saggriac.analysis.teacher_readings: what each teacher's paper plots, read from its history and
regions (issue 46, item 4), with known answers built by telling chosen competences."""

import numpy as np
import pytest

import saggriac as sg
from saggriac.analysis import teacher_readings
from saggriac.analysis.readings import READERS, SHARES, attempts_per_goal
from saggriac.teachers import MODES, available
from saggriac.testing import example_teacher

#: What each teacher's readings hold besides the counts, after 400 coin-flip tells.
PAPER = {
    "sagg_riac": {"regions", "interest_max", "interest_mean", "interest", "uniform_share", "interest_share", "lowest_share"},
    "random": {"uniform_share"},
    "riac": {"regions", "interest_max", "interest", "uniform_share", "alp_share", "worst_share"},
    "discrete_lp": {"tasks_told", "task_0/share", "task_5/last_told"},
    "alp_gmm": {"components_drawn", "uniform_share", "mixture_share"},
    "covar_gmm": {"components_drawn", "uniform_share", "mixture_share"},
    "adr": {"low_0", "low_1", "high_0", "high_1", "range_share", "boundary_share"},
    "plr": {"tasks_told", "task_0/share", "task_5/last_told", "new_share", "replay_share"},
    "spdl": {"mean_0", "mean_1", "std_0", "std_1", "kl_to_target"},
    "goal_gan": {"goid_share", "labelled", "uniform_share", "generated_share", "replay_share"},
    "tscl": {"tasks_told", "task_0/share", "task_5/last_told", "untried_share", "uniform_share", "bandit_share"},
}


def _taught(kind, n=400, seed=0):
    t = example_teacher(kind, seed=seed)
    rng = np.random.default_rng(seed)
    for _ in range(n):
        t.update(t.sample(), float(rng.random() < 0.5))
    return t


def test_every_registered_teacher_has_a_reader_and_its_modes_named():
    assert set(READERS) == set(SHARES) == set(available()) == set(PAPER)
    for kind, names in SHARES.items():
        assert set(names) <= set(MODES.values()), kind


@pytest.mark.parametrize("kind", list(available()))
def test_each_teacher_reads_what_its_paper_plots(kind):
    t = _taught(kind)
    r = teacher_readings(t, 200, 200)
    h = t.history()
    assert r["asked"] == len(h["asked_goal"]) == 400 and r["told"] == len(h["told_goal"]) == 400
    assert r["competence"] == pytest.approx(h["told_competence"][200:].mean())
    assert PAPER[kind] <= set(r), sorted(PAPER[kind] - set(r))
    shares = {SHARES[kind][m] for m in SHARES[kind]}
    assert sum(r[s] for s in shares) <= 1.0 + 1e-12
    for key, value in r.items():
        assert isinstance(value, (int, float, np.ndarray)), (key, type(value))


def test_the_shares_are_those_of_the_window_and_sum_to_one_where_every_mode_is_named():
    t = _taught("sagg_riac")
    modes = np.array([MODES[int(m)] for m in t.history()["asked_mode"][300:]])
    r = teacher_readings(t, asked_from=300, told_from=300)
    assert r["uniform_share"] == pytest.approx(np.isin(modes, ["initial", "global"]).mean())
    assert r["uniform_share"] + r["interest_share"] + r["lowest_share"] == pytest.approx(1.0)
    assert "uniform_share" not in teacher_readings(t, asked_from=400, told_from=400)  # an empty window


def test_adr_reads_its_ranges_and_its_boundary_draws():
    t = sg.AdrSelector([0.0, 0.0], [10.0, 20.0], seed=0, boundary_prob=0.25, buffer_size=2, step=0.1)
    for _ in range(300):
        t.update(t.sample(), 1.0)  # every boundary succeeds: the ranges grow
    r = teacher_readings(t)
    lo, hi = t.bounds
    assert [r["low_0"], r["low_1"], r["high_0"], r["high_1"]] == [lo[0], lo[1], hi[0], hi[1]]
    assert r["range_share"] == pytest.approx(np.mean((hi - lo) / [10.0, 20.0])) and r["range_share"] > 0
    modes = t.history()["asked_mode"]
    assert r["boundary_share"] == pytest.approx(np.mean([MODES[int(m)] == "interest" for m in modes]))
    assert 0.15 < r["boundary_share"] < 0.35


def test_spdl_reads_its_gaussian_and_the_competence_since_its_last_update():
    t = sg.SpdlSelector([0.0], [4.0], seed=0, update_every=20, warmup=20, delta=0.1)
    rng = np.random.default_rng(0)
    for _ in range(130):
        t.update(t.sample(), float(rng.random()))
    reg = t.regions()
    r = teacher_readings(t)
    assert r["mean_0"] == pytest.approx((reg["low"][0, 0] + reg["high"][0, 0]) / 2)
    assert r["std_0"] == pytest.approx((reg["high"][0, 0] - reg["low"][0, 0]) / 2)
    assert r["kl_to_target"] == reg["interest"][0]
    n = int(reg["n_measurements"][0])
    assert n == 10  # 130 tells, an update every 20
    assert r["expected_competence"] == pytest.approx(t.history()["told_competence"][-n:].mean())


def test_goal_gan_reads_the_share_of_goals_of_intermediate_difficulty():
    """Two attempts per goal: goals told (1, 0) have rate 0.5 (intermediate), goals told (1, 1)
    rate 1 (too easy); every third goal intermediate gives a share of 1/3."""
    t = sg.GoalGanSelector([0.0, 0.0], [1.0, 1.0], seed=0, n_rollouts=2, update_size=1000)
    for k in range(60):
        g = t.sample()
        assert np.array_equal(t.sample(), g)  # asked twice in a row
        t.update(g, 1.0)
        t.update(g, 0.0 if k % 3 == 0 else 1.0)
    assert attempts_per_goal(t.history()["asked_goal"]) == 2
    r = teacher_readings(t)
    assert r["goid_share"] == pytest.approx(1 / 3) and r["labelled"] == 60
    assert teacher_readings(t, told_from=60)["goid_share"] == pytest.approx(10 / 30)  # the last 30 goals
    # A goal with one of its two attempts told is not labelled yet.
    g = t.sample()
    t.update(g, 0.5)
    assert "goid_share" not in teacher_readings(t, told_from=120)
    assert teacher_readings(t)["labelled"] == 60


def test_goal_gan_reads_no_share_for_competences_outside_0_1():
    t = sg.GoalGanSelector([0.0], [1.0], seed=0, success_threshold=-0.5)
    for _ in range(20):
        t.update(t.sample(), -1.0)
    assert "goid_share" not in teacher_readings(t)


@pytest.mark.parametrize("kind", [k for k, c in available().items() if "tasks" in c.spaces])
def test_a_task_list_reads_each_tasks_share_and_last_value_told(kind):
    t = _taught(kind, n=300)
    h = t.history()
    r = teacher_readings(t, asked_from=100)
    asked = h["asked_goal"][100:, 0].astype(int)
    for i in range(t.n_tasks):
        assert r[f"task_{i}/share"] == pytest.approx(np.mean(asked == i))
        told = h["told_competence"][h["told_goal"][:, 0] == i]
        assert r[f"task_{i}/last_told"] == told[-1]
    assert sum(r[f"task_{i}/share"] for i in range(t.n_tasks)) == pytest.approx(1.0)
    assert r["tasks_told"] == t.n_tasks


def test_a_task_never_told_reads_nan():
    t = sg.PlrSelector(5, seed=0)
    t.update(2, 0.7)
    r = teacher_readings(t)
    assert r["task_2/last_told"] == 0.7 and np.isnan(r["task_0/last_told"]) and r["tasks_told"] == 1


def test_a_teacher_that_is_not_saggriacs_reads_nothing():
    class Mine:
        def sample(self):
            return np.zeros(1)

    assert teacher_readings(Mine()) == {}


@pytest.mark.parametrize("name, bad", [("asked_from", -1), ("told_from", 1.5), ("asked_from", True)])
def test_window_positions_are_checked(name, bad):
    with pytest.raises(sg.errors.ParameterError, match=rf"The '{name}' parameter of teacher_readings must be an int >= 0 .*Got {bad!r} instead"):
        teacher_readings(sg.RandomSelector([0.0], [1.0]), **{name: bad})


@pytest.mark.parametrize("dim", [1, 2, 5])
def test_goal_rates_against_a_scan_of_every_tell(dim):
    from saggriac.analysis.readings import goal_rates

    rng = np.random.default_rng(dim)
    distinct = rng.normal(size=(40, dim))
    told = distinct[rng.integers(40, size=300)]
    comp = rng.random(300)
    goals, counts, rates, inverse = goal_rates(told, comp)
    assert len(goals) == 40 and np.array_equal(goals[inverse], told.astype(np.float32))
    for k, g in enumerate(goals):
        mine = np.all(told.astype(np.float32) == g, axis=1)
        assert counts[k] == mine.sum() and rates[k] == pytest.approx(np.mean(comp[mine] >= 0.5))
