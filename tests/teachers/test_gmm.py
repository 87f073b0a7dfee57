"""The teachers' Gaussian-mixture EM against scikit-learn's GaussianMixture from the same start.

ALP-GMM and Covar-GMM refit mixtures all the time; their EM is ours (Rust), so it is held
against the reference implementation on fixed data: same start, same stopping rule, same
regularisation, the same fitted parameters, likelihood and AIC."""

import numpy as np
import pytest

from saggriac import _core

sklearn_mixture = pytest.importorskip("sklearn.mixture", reason="scikit-learn is the reference (pip install '.[test]')")


def data_sets():
    rng = np.random.default_rng(0)
    blobs = np.vstack([rng.normal(c, s, (150, 2)) for c, s in (((0, 0), 0.5), ((4, 4), 1.0), ((0, 5), 0.3))])
    # (task, ALP) pairs as ALP-GMM fits them: 3-D, skewed, one coordinate near zero for many.
    tasks = rng.uniform(0, 1, (250, 2))
    alp = np.abs(rng.normal(0, 0.05, 250)) + 0.3 * (tasks[:, 0] < 0.3)
    alp_data = np.column_stack([tasks, alp])
    # Overlapping components in 5-D.
    overlap = np.vstack([rng.normal(0, 1, (200, 5)), rng.normal(0.8, 1.5, (200, 5))])
    return {"blobs": (blobs, 3), "alp": (alp_data, 4), "overlap": (overlap, 2)}


@pytest.mark.parametrize("name", ["blobs", "alp", "overlap"])
@pytest.mark.parametrize("tol", [1e-3, 1e-8])
def test_em_reaches_scikit_learns_fit_from_the_same_start(name, tol):
    x, k = data_sets()[name]
    rng = np.random.default_rng(1)
    means = x[rng.choice(len(x), k, replace=False)]
    covs = np.stack([np.cov(x.T) + 1e-6 * np.eye(x.shape[1])] * k)
    weights = np.full(k, 1.0 / k)
    ref = sklearn_mixture.GaussianMixture(k, covariance_type="full", tol=tol, reg_covar=1e-6, max_iter=500, weights_init=weights, means_init=means, precisions_init=np.linalg.inv(covs)).fit(x)
    ours = _core.gmm_fit(x, weights, means, covs, max_iter=500, tol=tol, reg_covar=1e-6)
    assert ours["n_iter"] == ref.n_iter_ and ours["converged"] == ref.converged_
    assert np.allclose(ours["weights"], ref.weights_, rtol=1e-7, atol=1e-10)
    assert np.allclose(ours["means"], ref.means_, rtol=1e-7, atol=1e-9)
    assert np.allclose(ours["covariances"], ref.covariances_, rtol=1e-7, atol=1e-9)
    assert ours["lower_bound"] == pytest.approx(ref.lower_bound_, rel=1e-9)
    assert ours["aic"] == pytest.approx(ref.aic(x), rel=1e-9)


def test_bad_shapes_are_refused():
    with pytest.raises(Exception, match="gmm_fit needs"):
        _core.gmm_fit(np.zeros((5, 2)), np.ones(2) / 2, np.zeros((2, 3)), np.stack([np.eye(2)] * 2))
