"""The progress-niche learner of the teacher benchmark (saggriac.teachers.progress_niches)."""

import numpy as np
import pytest

from saggriac.errors import ParameterError
from saggriac.teachers.progress_niches import LAYOUT, ProgressNiches


def niche_goal(env, k):
    """The centre of niche k (0-based), from the layout."""
    j, i = env.niche_cells[k]
    return env.centre(j * env.nx + i)


def test_niches_open_one_after_another():
    env = ProgressNiches(0, noise_sd=0.0)
    assert env.unlocked == 1 and env.mastery() == 0.0
    # Niche 2 is locked: practising it teaches nothing and gives 0.
    assert env.attempt(niche_goal(env, 1)) == 0.0 and env.skill[1] == 0.0
    tries = 0
    while env.unlocked == 1:
        c = env.attempt(niche_goal(env, 0))
        tries += 1
    # s_n = 1 - 0.98^n reaches 0.6 after ceil(log 0.4 / log 0.98) = 46 tries.
    assert tries == int(np.ceil(np.log(0.4) / np.log(0.98)))
    assert c == pytest.approx(1 - 0.98**tries) and c >= 0.6
    assert env.attempt(niche_goal(env, 1)) == pytest.approx(0.02)
    for k in range(len(env.skill)):
        for _ in range(400):
            env.attempt(niche_goal(env, k))
    assert env.unlocked == 8 and env.mastery() > 0.99


def test_noisy_and_impossible_cells_teach_nothing():
    env = ProgressNiches(3)
    kinds = [env.kind(c) for c in range(env.n_cells)]
    assert kinds.count("niche") == 8 and kinds.count("noisy") == 4 and kinds.count("impossible") == 4
    noisy = [env.attempt(env.centre(c)) for c in range(env.n_cells) if kinds[c] == "noisy" for _ in range(500)]
    impossible = [env.attempt(env.centre(c)) for c in range(env.n_cells) if kinds[c] == "impossible" for _ in range(500)]
    assert env.mastery() == 0.0
    assert 0.45 < np.mean(noisy) < 0.55 and np.std(noisy) > 0.25  # uniform in [0, 1]
    assert np.mean(impossible) < 0.05 and min(impossible) >= 0.0


def test_distractors_change_nothing_and_cells_follow_the_layout():
    a, b = ProgressNiches(7, distractors=0), ProgressNiches(7, distractors=5)
    assert (a.dim, b.dim) == (2, 7)
    rng = np.random.default_rng(1)
    for _ in range(2000):
        g = rng.random(2)
        extra = rng.random(5)
        assert a.cell(g) == b.cell(np.concatenate([g, extra]))
        assert a.attempt(g) == b.attempt(np.concatenate([g, extra]))
    # Bottom-left is niche 1, top-right impossible; the box's upper bound belongs to the last cell.
    assert a.kind(a.cell([0.1, 0.1])) == "niche" and a.niche_cells[0] == (0, 0)
    assert a.kind(a.cell([1.0, 1.0])) == "impossible" and a.cell([1.0, 1.0]) == 15
    assert a.kind(a.cell([0.99, 0.3])) == "noisy" and LAYOUT[1][3] == "N"


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(layout=("12", "3")), "equal-length rows"),
        (dict(layout=("1Q", "NX")), "'Q'"),
        (dict(layout=("13", "NX")), "numbered 1, 2"),
        (dict(layout=("1X", "N2")), "touch niche 1"),
        (dict(learning_rate=0.0), "'learning_rate'.*in \\(0, 1\\]"),
        (dict(unlock_at=1.5), "'unlock_at'"),
        (dict(noise_sd=-0.1), "'noise_sd'.*in \\[0, 1\\]"),
        (dict(distractors=-1), "'distractors'"),
        (dict(distractors=True), "'distractors'"),
    ],
)
def test_bad_parameters_are_refused_with_the_rule(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        ProgressNiches(0, **kwargs)


def test_a_goal_of_the_wrong_shape_is_refused():
    env = ProgressNiches(0, distractors=1)
    with pytest.raises(ParameterError, match="3 finite floats"):
        env.attempt([0.5, 0.5])
    with pytest.raises(ParameterError, match="3 finite floats"):
        env.attempt([0.5, np.nan, 0.5])
