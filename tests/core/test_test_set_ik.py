"""The forward metric's test configurations (test_configs="ik_min_norm") on bodies whose reach
is odd, checked against scipy's maintained solvers (issue 25, item 1): SLSQP for the least-norm
configuration of a goal in reach, bounded least squares for the closest one to a goal out of
reach. No body is ever placed at a non-finite configuration."""

import numpy as np
import pytest

import saggriac as sg
from saggriac import _core
from saggriac.seeding import derive_seeds
scipy_optimize = pytest.importorskip("scipy.optimize")
minimize, least_squares = scipy_optimize.minimize, scipy_optimize.least_squares

class Leg2D:
    def __init__(self, off=0.0): self.off=off; self.joint_space=sg.bodies.environments.Box(-1.0,1.0,(2,)); self.theta=np.zeros(2); self.nan=0
    def f(self, t): a,b=t; r=30+20*np.cos(b+self.off); return np.array([r*np.cos(a), r*np.sin(a)])
    def reset(self,*,seed=None,options=None):
        if options and "theta" in options:
            t=np.asarray(options["theta"],float)
            if not np.all(np.isfinite(t)): self.nan+=1; t=np.zeros(2)
            self.theta=np.clip(t,-1,1)
        else: self.theta=np.zeros(2)
        return self.theta.copy(), self.f(self.theta)
    def step(self,d): self.theta=np.clip(self.theta+np.clip(d,-.02,.02),-1,1); return self.theta.copy(), self.f(self.theta)

def _tests_of(cfg, seed, env=None):
    ls, es = derive_seeds(seed)
    extra = {} if env is None else {"environment": env}
    L = _core.Learner(cfg.core_dict(), ls, es, **extra)
    return L.test_set()

def compare(name, f, lim, ts, tol):
    goals, configs, res = ts["goals"], ts["configs"], ts["ik_residuals"]
    n = configs.shape[1]; rng = np.random.default_rng(0)
    worse = 0; rows = []
    for g, th, r in zip(goals, configs, res):
        starts = [np.full(n, b) for b in (0.05, -0.05, 0.3, -0.3)] + [rng.uniform(-lim, lim, n) for _ in range(4)]
        best_ls = min(np.linalg.norm(least_squares(lambda t: f(t) - g, s, bounds=(-lim, lim)).fun) for s in starts)
        best_norm = np.inf
        for s in starts:
            o = minimize(lambda t: t @ t, s, jac=lambda t: 2 * t, bounds=[(-lim, lim)] * n, constraints=[{"type": "eq", "fun": lambda t: f(t) - g}], method="SLSQP", options={"maxiter": 500, "ftol": 1e-12})
            if np.linalg.norm(f(o.x) - g) <= tol: best_norm = min(best_norm, o.x @ o.x)
        ours_r = np.linalg.norm(f(th) - g)
        if best_norm < np.inf:
            ok = ours_r <= tol and th @ th <= best_norm * (1 + 1e-3) + 1e-6
        else:
            ok = ours_r <= best_ls * (1 + 1e-3) + tol
        worse += not ok
        rows.append((ours_r, best_ls, th @ th, best_norm))
    return worse, int((res > tol).sum()), bool(np.all(np.isfinite(configs)))

def planar(n, L=50.0):
    lengths = np.full(n, L / n)
    def f(t):
        phi = np.cumsum(t); return np.array([np.sum(lengths * np.cos(phi)), np.sum(lengths * np.sin(phi))])
    return f



TOL = _core.IK_TOLERANCE * 50


def test_the_paper_arm_matches_slsqp():
    cfg = sg.Config.from_preset("exp1", n_test_goals=8, n_test_configs=8)
    worse, unreached, finite = compare("built-in", planar(15), cfg.joint_limit, _tests_of(cfg, 0), TOL)
    assert (worse, unreached, finite) == (0, 0, True)


def test_a_one_joint_body_gets_the_closest_configurations():
    # One joint of length 50: its reach is an arc, so (almost) every test goal is out of reach.
    cfg = sg.Config.from_preset("exp1", n_joints=1, n_test_goals=15, n_test_configs=15)
    worse, unreached, finite = compare("1 joint", planar(1), cfg.joint_limit, _tests_of(cfg, 0, sg.bodies.environments.PlanarArm(n_joints=1)), TOL)
    assert worse == 0 and finite and unreached >= 10


@pytest.mark.parametrize("off", [0.0, 0.5])
def test_an_annulus_shaped_reach_gets_no_nan_and_the_closest_configurations(off):
    leg = Leg2D(off)
    cfg = sg.Config.from_preset("exp1", n_joints=2, joint_limit=1.0, max_joint_step=0.02, n_test_goals=20, n_test_configs=20)
    worse, unreached, finite = compare("annulus", leg.f, 1.0, _tests_of(cfg, 0, leg), TOL)
    assert leg.nan == 0, f"{leg.nan} placements at non-finite angles"
    assert worse == 0 and finite and unreached > 0
    # A whole run measures this body (it declares no reach) and draws its test goals where it
    # reaches: none is out of reach, and nothing is NaN.
    res = sg.run(cfg.replace(n_steps=300, n_evals=1), seed=0, environment=Leg2D(off))
    assert res.manifest["scale"]["source"] == "measured"
    assert res.manifest["test_set"]["unreached_goals"] == 0 and np.all(np.isfinite(res.reach_error))
