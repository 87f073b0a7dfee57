"""Expert knowledge per dimension (issue 46, item 3): SPDL's start and target (means, standard
deviations, full covariances), ADR's start box and step, Goal GAN's first goals' box take one
value per dimension of the box; wrong ones are refused naming the parameter, the value and the
rule; a teacher saved with them continues exactly."""

import pickle

import numpy as np
import pytest

import saggriac as sg

BOX3 = ([0.0, 0.0, 0.0], [1.0, 2.0, 4.0])


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: sg.SpdlSelector(*BOX3, init_mean=[0.1, 0.5]), r"^The 'init_mean' parameter of SpdlSelector must be a float in \[0, 1\] \(a position in the box scaled to \[0, 1\]\), or a list of such floats, one per dimension of the box\. Got \[0\.1, 0\.5\] \(2 values for a box of 3 dimensions\) instead\.$"),
        (lambda: sg.SpdlSelector(*BOX3, target_mean=[0.1, 1.5, 0.2]), r"^The 'target_mean' parameter of SpdlSelector must be a float in \[0, 1\] \(a position in the box scaled to \[0, 1\]\), or a list of such floats, one per dimension of the box\. Got \[0\.1, 1\.5, 0\.2\] \(1\.5 in dimension 1\) instead\.$"),
        (lambda: sg.SpdlSelector(*BOX3, init_std=[0.1, 0.0, 0.2]), r"^The 'init_std' parameter of SpdlSelector must be a float in \[0\.0001, 10\] \(box widths\), or a list of such floats, one per dimension of the box\. Got \[0\.1, 0, 0\.2\] \(0 in dimension 1\) instead\.$"),
        (lambda: sg.SpdlSelector(*BOX3, init_std=[0.1, float("nan"), 0.2]), r"^The 'init_std' parameter of SpdlSelector must be a float in \[0\.0001, 10\] \(box widths\), or a list of such floats, one per dimension of the box\. Got \[0\.1, NaN, 0\.2\] \(NaN in dimension 1\) instead\.$"),
        (lambda: sg.SpdlSelector(*BOX3, init_mean="0.1"), r"^The 'init_mean' parameter of SpdlSelector must be a float in \[0, 1\] \(a position in the box scaled to \[0, 1\]\)\. Got '0\.1' instead\.$"),
        (lambda: sg.SpdlSelector(*BOX3, init_mean=[[0.1, 0.2, 0.3]]), r"^The 'init_mean' parameter of SpdlSelector must be a float in \[0, 1\] \(a position in the box scaled to \[0, 1\]\), or a list of such floats, one per dimension of the box\. Got \[\[0\.1, 0\.2, 0\.3\]\] instead\.$"),
        (lambda: sg.SpdlSelector(*BOX3, epsilon=[0.1, 0.1, 0.1]), r"^The 'epsilon' parameter of SpdlSelector must be a finite float > 0\. Got \[0\.1, 0\.1, 0\.1\] instead\.$"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], init_cov=[[0.01, 0.0, 0.0], [0.0, 0.01, 0.0]]), r"^The 'init_cov' parameter of SpdlSelector must be a 2 x 2 matrix of finite floats: 2 rows of 2 \(one row and one column per dimension of the box\)\. Got \[\[0\.01, 0\.0, 0\.0\], \[0\.0, 0\.01, 0\.0\]\] instead\.$"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], init_cov=[0.01, 0.01]), r"^The 'init_cov' parameter of SpdlSelector must be a 2 x 2 matrix of finite floats: 2 rows of 2 \(one row and one column per dimension of the box\)\. Got \[0\.01, 0\.01\] instead\.$"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], covariance="full", target_cov=[[0.01, 0.02], [0.02, 0.01]]), r"^The 'target_cov' parameter of SpdlSelector must be a positive-definite 2 x 2 matrix \(a covariance: its Cholesky factor must exist\)\. Got \[\[0\.01, 0\.02\], \[0\.02, 0\.01\]\] instead\.$"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], covariance="full", target_cov=[[0.01, 0.002], [0.003, 0.01]]), r"^The 'target_cov' parameter of SpdlSelector must be a symmetric 2 x 2 matrix \(a covariance, in box widths squared; entry \(0, 1\) differs from \(1, 0\)\)\. Got"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], target_cov=[[0.01, 0.005], [0.005, 0.01]]), r"^The 'target_cov' parameter of SpdlSelector must be a diagonal matrix with covariance='diagonal' \(p's covariance is then diagonal: set covariance='full' to take correlations\)\. Got \[\[0\.01, 0\.005\], \[0\.005, 0\.01\]\] instead\.$"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], init_cov=[[1000.0, 0.0], [0.0, 0.01]]), r"^The 'init_cov' parameter of SpdlSelector must be a 2 x 2 covariance whose diagonal is in \[1e-8, 100\]"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], init_cov=np.eye(2) * 0.01, init_std=[0.1, 0.1]), r"^The 'init_std' parameter of SpdlSelector must be left out with init_cov \(the covariance gives the standard deviations\)\. Got \[0\.1, 0\.1\] instead\.$"),
        (lambda: sg.SpdlSelector([0, 0], [1, 1], init_cov=np.eye(2) * 0.01, init_std=0.2), r"^The 'init_std' parameter of SpdlSelector must be left at its default with init_cov \(the covariance gives the standard deviations\)\. Got 0\.2 instead\.$"),
        (lambda: sg.SpdlSelector(np.zeros(11), np.ones(11), covariance="full"), r"^The 'covariance' parameter of SpdlSelector must be 'diagonal' for bounds of more than 10 dimensions"),
        (lambda: sg.AdrSelector(*BOX3, step=[0.1, 0.0, 0.1]), r"^The 'step' parameter of AdrSelector must be a float in \(0, 1\], or a list of such floats, one per dimension of the box\. Got \[0\.1, 0, 0\.1\] \(0 in dimension 1\) instead\.$"),
        (lambda: sg.AdrSelector(*BOX3, initial=[0.1, 0.2, 0.3, 0.4]), r"^The 'initial' parameter of AdrSelector must be a float in \[0, 1\], or a list of such floats, one per dimension of the box\. Got \[0\.1, 0\.2, 0\.3, 0\.4\] \(4 values for a box of 3 dimensions\) instead\.$"),
        (lambda: sg.AdrSelector(*BOX3, t_low=[0.1, 0.1, 0.1]), r"^The 't_low' parameter of AdrSelector must be a finite float with \|value\| <= 1e100\. Got \[0\.1, 0\.1, 0\.1\] instead\.$"),
        (lambda: sg.GoalGanSelector(*BOX3, initial_width=[0.5, 1.5, 1.0]), r"^The 'initial_width' parameter of GoalGanSelector must be a float in \[0, 1\], or a list of such floats, one per dimension of the box\. Got \[0\.5, 1\.5, 1\] \(1\.5 in dimension 1\) instead\.$"),
        (lambda: sg.GoalGanSelector(*BOX3, initial=-0.1), r"^The 'initial' parameter of GoalGanSelector must be a float in \[0, 1\]\. Got -0\.1 instead\.$"),
    ],
)
def test_a_wrong_value_per_dimension_names_the_parameter_the_value_and_the_rule(make, message):
    with pytest.raises(sg.ParameterError, match=message):
        make()


def _drive(t, n, competence):
    for _ in range(n):
        g = t.sample()
        t.update(g, competence(g))


def test_spdl_starts_where_each_dimension_says_and_keeps_a_correlated_target():
    t = sg.SpdlSelector(*BOX3, init_mean=[0.1, 0.5, 0.9], init_std=[0.02, 0.1, 0.05])
    r = t.regions()
    assert np.allclose(r["low"][0], [0.08, 0.8, 3.4]) and np.allclose(r["high"][0], [0.12, 1.2, 3.8])
    # A full covariance for the start: its draws have it (box widths squared, here a unit box).
    cov = [[0.01, 0.006], [0.006, 0.01]]
    t = sg.SpdlSelector([0, 0], [1, 1], seed=1, covariance="full", init_mean=[0.5, 0.5], init_cov=cov, target_cov=cov)
    g = t.sample_batch(20_000)
    assert np.allclose(np.cov(g.T), cov, atol=1e-3)
    # Every goal a success and the target its start: p stays near it, correlation included.
    _drive(t, 1000, lambda g: 1.0)
    assert t.regions()["interest"][0] < 0.05
    assert np.corrcoef(t.sample_batch(20_000).T)[0, 1] > 0.45


def test_adr_and_goal_gan_start_where_each_dimension_says():
    a = sg.AdrSelector(*BOX3, initial=[0.1, 0.5, 1.0], initial_width=[0.0, 0.5, 0.0], step=[0.01, 0.1, 0.2])
    assert np.allclose(a.bounds[0], [0.1, 0.5, 4.0]) and np.allclose(a.bounds[1], [0.1, 1.5, 4.0])
    g = sg.GoalGanSelector(*BOX3, initial=[0.1, 0.5, 0.5], initial_width=[0.2, 1.0, 0.1])
    first = np.array([g.sample() for _ in range(300)])
    assert first[:, 0].max() <= 0.2 and first[:, 2].min() >= 1.8 and first[:, 2].max() <= 2.2
    assert first[:, 1].min() < 0.1 and first[:, 1].max() > 1.9


@pytest.mark.parametrize(
    "cls, one, each",
    [
        (sg.SpdlSelector, {"init_mean": 0.2, "init_std": 0.05, "update_every": 30, "warmup": 30}, {"init_mean": [0.2] * 3, "init_std": (0.05, 0.05, 0.05), "target_std": np.full(3, 0.25), "update_every": 30, "warmup": 30}),
        (sg.AdrSelector, {"step": 0.1, "initial": 0.2}, {"step": [0.1] * 3, "initial": np.full(3, 0.2), "initial_width": [0.0] * 3}),
        (sg.GoalGanSelector, {"update_size": 10, "gan_iterations": 5, "hidden": 8}, {"update_size": 10, "gan_iterations": 5, "hidden": 8, "initial": [0.5] * 3, "initial_width": [1.0] * 3}),
    ],
)
def test_the_same_value_in_every_dimension_is_the_single_number(cls, one, each):
    a, b = cls(*BOX3, seed=4, **one), cls(*BOX3, seed=4, **each)
    for k in range(150):
        g, h = a.sample(), b.sample()
        assert np.array_equal(g, h)
        a.update(g, float(k % 3 == 0))
        b.update(h, float(k % 3 == 0))


@pytest.mark.parametrize("how", ["pickle", "file"])
def test_a_teacher_saved_with_values_per_dimension_continues_exactly(how, tmp_path):
    t = sg.SpdlSelector([0, 0], [1, 2], seed=2, form="alpha", covariance="full", init_mean=[0.1, 0.3], init_cov=[[0.01, 0.002], [0.002, 0.02]], update_every=20, warmup=20)
    _drive(t, 70, lambda g: float(g[0] < 0.3))
    u = pickle.loads(pickle.dumps(t)) if how == "pickle" else sg.load_selector(t.save(tmp_path / "t.bin"))
    for _ in range(100):
        g, h = t.sample(), u.sample()
        assert np.array_equal(g, h)
        t.update(g, float(g[0] < 0.3))
        u.update(h, float(h[0] < 0.3))


def test_a_run_takes_single_numbers_and_says_where_lists_go():
    # The single number's rule (a run's), and where a list goes.
    with pytest.raises(sg.ParameterError, match=r"^The 'teacher_params\.init_mean' parameter of Config must be a float in \[0, 1\] \(a position in the box scaled to \[0, 1\]\)\. Got \[0\.1, 0\.5\] \(a value per dimension is taken by the teacher's class, such as saggriac\.SpdlSelector\(init_mean=\[\.\.\.\]\), not by a run\) instead\.$"):
        sg.Config(teacher="spdl", teacher_params={"init_mean": [0.1, 0.5]})
    # A covariance has no single-number form: it is named as the class's, not as unknown.
    for name in ("init_cov", "target_cov"):
        with pytest.raises(sg.ParameterError, match=rf"^The 'teacher_params\.{name}' parameter of Config must be given to the teacher's class, such as saggriac\.SpdlSelector\({name}=\.\.\.\), not to a run, which takes single numbers\. Got \[\[0\.1, 0\.0\], \[0\.0, 0\.1\]\] instead\.$"):
            sg.Config(teacher="spdl", teacher_params={name: [[0.1, 0.0], [0.0, 0.1]]})
    # The alpha form weighs KL by the mean competence clipped at 0: a run's are <= 0.
    with pytest.raises(sg.ParameterError, match=r"^The 'teacher_params\.form' parameter of Config must be 'delta' \(the competences a run tells \(min_c to 0\) lie in \[-1, 0\]; the alpha form weighs KL\(p \|\| mu\) by zeta times the mean competence clipped at 0, so with competences <= 0 it never moves p toward the target\)\. Got 'alpha' instead\.$"):
        sg.Config(teacher="spdl", teacher_params={"form": "alpha"}).validate()


def test_get_params_gives_the_values_per_dimension_and_builds_the_same_teacher():
    t = sg.SpdlSelector([0, 0], [1, 2], seed=2, covariance="full", init_mean=np.array([0.1, 0.3]), init_cov=[[0.01, 0.002], [0.002, 0.02]])
    p = t.get_params()
    assert p["init_mean"] == [0.1, 0.3] and p["init_cov"] == [[0.01, 0.002], [0.002, 0.02]] and p["target_mean"] == 0.5
    u = sg.SpdlSelector([0, 0], [1, 2], seed=2, **p)
    assert np.array_equal(t.sample_batch(50), u.sample_batch(50))
    assert "init_cov" not in sg.SpdlSelector([0, 0], [1, 2]).get_params()
