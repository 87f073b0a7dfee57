//! SPDL, self-paced deep RL (Klink, Abdulsamad, Belousov & Peters, NeurIPS 2020; Klink et al.,
//! JMLR 2021, "A probabilistic interpretation of self-paced learning with applications to
//! reinforcement learning"), over Gaussian context distributions p in the box scaled to [0, 1],
//! diagonal or full (Cholesky-parametrised), toward a target mu. Two forms:
//!
//! - delta (the JMLR paper, the default): min_p KL(p || mu) s.t. E_p[competence] >= delta and
//!   KL(p || p_old) <= epsilon. The expectation under a candidate p is the self-normalised
//!   importance-weighted mean of the competences told since the last update (weights
//!   p(x) / p_old(x) at the told goals). Where the mean competence told is below delta, the update
//!   first looks for the p of most competence within the KL bound (the authors' rule until delta
//!   is reached) and, if that one meets delta, solves the problem from there: p moves back toward
//!   easier contexts, so the constraint holds on average instead of being overshot. COBYLA (the
//!   `cobyla` crate: derivative-free, deterministic, each constraint on its own) solves it; the
//!   step taken is the best point it evaluated inside both constraints.
//! - alpha (the NeurIPS paper, as TeachMyAgent runs the authors' code): one natural-gradient step
//!   on E_p[competence] - alpha KL(p || mu) (plain importance weights), scaled to
//!   KL(p_old || p) = epsilon by the Fisher information (conjugate gradient, 10 iterations,
//!   damping 0.01) and halved up to 10 times until KL(p_old || p) <= 1.5 epsilon or the objective
//!   did not fall; alpha = zeta * max(mean competence, 0) / max(KL(p_old || mu), 1e-10), capped at
//!   1e5, and 0 while the update's number (from 1) is below `alpha_offset`.
//!
//! An update runs every `update_every` told goals once `warmup` goals were told. Goals are drawn
//! from p and clipped to the box (as the paper's environments and TeachMyAgent do).

use crate::config::high_level::check_bounds;
use crate::config::teachers::{PerDimension, TeacherParams};
use crate::error::{invalid, Result};
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, GoalSelector, LeafRow, Mode};
use crate::high_level::teachers::gaussian::Gaussian;
use crate::high_level::teachers::mixture::UnitBox;
use crate::rng::{rng_from_seed, CoreRng};

/// A constraint of the COBYLA step: feasible where it is >= 0.
type Constraint<'a> = &'a dyn Fn(&[f64], &mut ()) -> f64;

pub use crate::config::teachers::{SpdlConfig, SpdlCovariance, SpdlForm};

/// The most dimensions SPDL takes: each update runs COBYLA over 2 d variables, whose cost grows
/// as the cube of d (300 told goals, two updates: 2.4 s in 30 dimensions, 11 s in 50, minutes in
/// 200; in 10^4 the crate's workspace size overflows its i32 and it panics).
pub const MAX_SPDL_DIM: usize = 30;

/// The most dimensions of a full covariance: d + d (d + 1) / 2 variables (65 in 10-D, 495 in
/// 30-D, where COBYLA's first simplex alone takes 496 evaluations).
pub const MAX_SPDL_FULL_DIM: usize = 10;

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct SpdlState {
    rng: CoreRng,
    dist: Gaussian,
    /// Goals (unit box, flattened) and competences told since the last update.
    buf_goals: Vec<f64>,
    buf_values: Vec<f64>,
    told: u64,
    updates: u64,
}

/// The state as saggriac 0.6 wrote it before #46: a diagonal Gaussian without `lower`.
#[derive(serde::Deserialize)]
struct SpdlStateV0 {
    rng: CoreRng,
    mean: Vec<f64>,
    log_std: Vec<f64>,
    buf_goals: Vec<f64>,
    buf_values: Vec<f64>,
    told: u64,
    updates: u64,
}

pub struct Spdl {
    cfg: SpdlConfig,
    unit_box: UnitBox,
    target: Gaussian,
    st: SpdlState,
}

/// p's start or its target from the parameters `mean`, `std` (one number each, or per
/// dimension) or `cov` (a d x d covariance in box widths squared, beside them).
fn gaussian(cfg: &SpdlConfig, dims: &PerDimension, d: usize, which: &str, (mean, std): (f64, f64)) -> Result<Gaussian> {
    const OWNER: &str = "SpdlSelector";
    let (mean_name, std_name, cov_name) = (format!("{which}_mean"), format!("{which}_std"), format!("{which}_cov"));
    let full = cfg.covariance == SpdlCovariance::Full;
    let m = dims.vector(&mean_name, mean, d);
    let Some(cov) = dims.get(&cov_name) else {
        return Ok(Gaussian::diagonal(m, &dims.vector(&std_name, std, d), full));
    };
    let shown = PerDimension::show(cov, d);
    // The standard deviations come from the covariance: a std given too would be ignored.
    let default_std = if which == "init" { SpdlConfig::default().init_std } else { SpdlConfig::default().target_std };
    if let Some(v) = dims.get(&std_name) {
        return Err(invalid(OWNER, &std_name, format!("left out with {cov_name} (the covariance gives the standard deviations)"), PerDimension::show(v, d)));
    }
    if std != default_std {
        return Err(invalid(OWNER, &std_name, format!("left at its default with {cov_name} (the covariance gives the standard deviations)"), crate::error::Num(std)));
    }
    let (i, j) = (0..d).flat_map(|i| (0..d).map(move |j| (i, j))).find(|&(i, j)| (cov[i * d + j] - cov[j * d + i]).abs() > 1e-12 * (cov[i * d + j].abs().max(cov[j * d + i].abs()))).unwrap_or((d, d));
    if i < d {
        return Err(invalid(OWNER, &cov_name, format!("a symmetric {d} x {d} matrix (a covariance, in box widths squared; entry ({i}, {j}) differs from ({j}, {i}))"), shown));
    }
    if let Some(i) = (0..d).find(|&i| !(1e-8..=100.0).contains(&cov[i * d + i])) {
        return Err(invalid(OWNER, &cov_name, format!("a {d} x {d} covariance whose diagonal is in [1e-8, 100] (standard deviations of 1e-4 to 10 box widths, as {std_name}; entry ({i}, {i}) is not)"), shown));
    }
    if !full && (0..d).any(|i| (0..d).any(|j| i != j && cov[i * d + j] != 0.0)) {
        return Err(invalid(OWNER, &cov_name, "a diagonal matrix with covariance='diagonal' (p's covariance is then diagonal: set covariance='full' to take correlations)", shown));
    }
    Gaussian::from_covariance(m, cov, full).ok_or_else(|| invalid(OWNER, &cov_name, format!("a positive-definite {d} x {d} matrix (a covariance: its Cholesky factor must exist)"), shown))
}

impl Spdl {
    pub fn new(low: &[f64], high: &[f64], cfg: SpdlConfig, seed: u64) -> Result<Self> {
        Self::with_dims(low, high, cfg, &PerDimension::default(), seed)
    }

    /// SPDL with means, standard deviations or covariances given per dimension where `dims`
    /// has them (their lengths and each value's rule checked by `PerDimension::check`).
    pub fn with_dims(low: &[f64], high: &[f64], cfg: SpdlConfig, dims: &PerDimension, seed: u64) -> Result<Self> {
        check_bounds("SpdlSelector", low, high)?;
        if low.len() > MAX_SPDL_DIM {
            let rule = format!("bounds of at most {MAX_SPDL_DIM} dimensions (each update runs COBYLA over 2 x d variables, whose cost grows as the cube of the dimension)");
            return Err(invalid("SpdlSelector", "bounds", rule, format!("{} dimensions", low.len())));
        }
        cfg.validate()?;
        let d = low.len();
        if cfg.covariance == SpdlCovariance::Full && d > MAX_SPDL_FULL_DIM {
            let rule = format!("'diagonal' for bounds of more than {MAX_SPDL_FULL_DIM} dimensions (a full covariance has d + d (d + 1) / 2 parameters: {} here, too many for an update's optimiser; got {d} dimensions)", d + d * (d + 1) / 2);
            return Err(invalid("SpdlSelector", "covariance", rule, "'full'"));
        }
        let init = gaussian(&cfg, dims, d, "init", (cfg.init_mean, cfg.init_std))?;
        let target = gaussian(&cfg, dims, d, "target", (cfg.target_mean, cfg.target_std))?;
        Ok(Spdl {
            cfg,
            unit_box: UnitBox { low: low.to_vec(), high: high.to_vec() },
            target,
            st: SpdlState { rng: rng_from_seed(seed), dist: init, buf_goals: Vec::new(), buf_values: Vec::new(), told: 0, updates: 0 },
        })
    }

    /// The current context distribution (unit box).
    pub fn distribution(&self) -> &Gaussian {
        &self.st.dist
    }

    /// The target distribution (unit box).
    pub fn target(&self) -> &Gaussian {
        &self.target
    }

    /// Updates that ran (a kept distribution counts as one).
    pub fn n_updates(&self) -> u64 {
        self.st.updates
    }

    fn update_distribution(&mut self) {
        let d = self.unit_box.low.len();
        let goals = std::mem::take(&mut self.st.buf_goals);
        let xs: Vec<&[f64]> = goals.chunks_exact(d).collect();
        let cs = std::mem::take(&mut self.st.buf_values);
        self.st.updates += 1;
        let next = match self.cfg.form {
            SpdlForm::Delta => self.delta_step(&xs, &cs),
            SpdlForm::Alpha => self.alpha_step(&xs, &cs),
        };
        if let Some(p) = next {
            self.st.dist = p;
        }
    }

    /// The delta form's update (Klink et al., JMLR 2021), solved on the goals told since the
    /// last one:
    ///
    ///   min_p KL(p || mu)  s.t.  E_p[competence] >= delta,  KL(p || p_old) <= epsilon.
    ///
    /// Where the constraint holds at p_old (the mean competence told >= delta), COBYLA starts
    /// there. Where it does not, the problem still asks for a p that meets it: first the p of
    /// most estimated competence within the KL bound (the authors' rule before delta is first
    /// reached), then, if that one meets delta, the p nearest mu among those that do. So p moves
    /// back toward easier goals after an update that overshot, and the expected competence
    /// settles at delta instead of below it (with only forward moves, every estimate that came
    /// out high pushed p further and none pulled it back). No competence above the old mean
    /// anywhere in the bound (nothing learnable near p): p is kept.
    fn delta_step(&self, xs: &[&[f64]], cs: &[f64]) -> Option<Gaussian> {
        let old = &self.st.dist;
        let n = cs.len() as f64;
        let old_lp: Vec<f64> = xs.iter().map(|x| old.log_pdf(x)).collect();
        // Self-normalised importance sampling: sum w c / sum w, weights p(x) / p_old(x) capped
        // at exp(20) (a far candidate must not overflow). A constant competence is estimated
        // exactly at every p, so p never chases the weights' own noise.
        let perf = |v: &[f64]| {
            let p = old.with_vars(v);
            let (mut wc, mut w) = (0.0, 0.0);
            for ((x, lo), c) in xs.iter().zip(&old_lp).zip(cs) {
                let wi = (p.log_pdf(x) - lo).min(20.0).exp();
                (wc, w) = (wc + wi * c, w + wi);
            }
            if w > 0.0 { wc / w } else { f64::NEG_INFINITY }
        };
        let (target, delta, eps) = (&self.target, self.cfg.delta, self.cfg.epsilon);
        let c_kl = |v: &[f64], _: &mut ()| eps - old.with_vars(v).kl(old);
        let bounds = old.var_bounds();
        // At p_old every weight is exactly 1: the estimate is the mean competence told.
        let at_old = cs.iter().sum::<f64>() / n;
        let mut start = old.vars();
        let mut moved = None;
        if at_old < delta {
            let most = |v: &[f64], _: &mut ()| -perf(v);
            let (x, f) = best_feasible(&most, &start, &[&c_kl], &bounds)?;
            // Not above the old mean beyond rounding (a constant competence): nothing to gain.
            if -f <= at_old + 1e-12 * (1.0 + at_old.abs()) {
                return None;
            }
            if -f < delta {
                return Some(old.with_vars(&x));
            }
            moved = Some(old.with_vars(&x));
            start = x;
        }
        let objective = |v: &[f64], _: &mut ()| old.with_vars(v).kl(target);
        let c_perf = |v: &[f64], _: &mut ()| perf(v) - delta;
        best_feasible(&objective, &start, &[&c_perf, &c_kl], &bounds).map(|(x, _)| old.with_vars(&x)).or(moved)
    }

    /// The alpha form's update (Klink et al., NeurIPS 2020, as TeachMyAgent runs the authors'
    /// code): one natural-gradient step on L(p) = mean(w c) - alpha KL(p || mu), w = p(x) /
    /// p_old(x), within KL(p_old || p) <= epsilon.
    fn alpha_step(&self, xs: &[&[f64]], cs: &[f64]) -> Option<Gaussian> {
        let old = &self.st.dist;
        let n = cs.len() as f64;
        let mean_c = cs.iter().sum::<f64>() / n;
        let alpha = if self.st.updates < self.cfg.alpha_offset as u64 { 0.0 } else { (self.cfg.alpha_zeta * mean_c.max(0.0) / old.kl(&self.target).max(1e-10)).min(1e5) };
        let old_lp: Vec<f64> = xs.iter().map(|x| old.log_pdf(x)).collect();
        let objective = |p: &Gaussian| xs.iter().zip(&old_lp).zip(cs).map(|((x, lo), c)| (p.log_pdf(x) - lo).exp() * c).sum::<f64>() / n - alpha * p.kl(&self.target);
        // The gradient at p_old, where every weight is 1.
        let mut grad: Vec<f64> = old.grad_kl(&self.target).iter().map(|g| -alpha * g).collect();
        for (x, c) in xs.iter().zip(cs) {
            for (g, v) in grad.iter_mut().zip(old.grad_log_pdf(x)) {
                *g += c * v / n;
            }
        }
        if dot(&grad, &grad).sqrt() < 1e-10 {
            return None;
        }
        let damped = |v: &[f64]| -> Vec<f64> { old.fisher_times(v).iter().zip(v).map(|(f, x)| f + 0.01 * x).collect() };
        let dir = conjugate_gradient(&damped, &grad, 10, 1e-10);
        let shs = 0.5 * dot(&dir, &damped(&dir));
        if !(shs > 0.0 && shs.is_finite()) {
            return None;
        }
        let scale = (self.cfg.epsilon / shs).sqrt();
        let (theta, prev) = (old.vars(), objective(old));
        let mut size = 1.0;
        for _ in 0..10 {
            let v: Vec<f64> = theta.iter().zip(&dir).map(|(t, s)| t + s * scale * size).collect();
            if v.iter().all(|x| x.is_finite()) {
                let p = old.with_vars(&v);
                if old.kl(&p) <= 1.5 * self.cfg.epsilon || objective(&p) - prev >= 0.0 {
                    return Some(p);
                }
            }
            size *= 0.5;
        }
        None
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// x with A x = b by `iters` steps of conjugate gradient from 0 (stopping once the residual's
/// square is below `tol`), A given by its products.
fn conjugate_gradient(a: &dyn Fn(&[f64]) -> Vec<f64>, b: &[f64], iters: usize, tol: f64) -> Vec<f64> {
    let (mut p, mut r, mut x) = (b.to_vec(), b.to_vec(), vec![0.0; b.len()]);
    let mut r2 = dot(&r, &r);
    for _ in 0..iters {
        let z = a(&p);
        let v = r2 / dot(&p, &z);
        x.iter_mut().zip(&p).for_each(|(xi, pi)| *xi += v * pi);
        r.iter_mut().zip(&z).for_each(|(ri, zi)| *ri -= v * zi);
        let r2_new = dot(&r, &r);
        let mu = r2_new / r2;
        p = r.iter().zip(&p).map(|(ri, pi)| ri + mu * pi).collect();
        r2 = r2_new;
        if r2 < tol {
            break;
        }
    }
    x
}

/// COBYLA from `x0` within `bounds`: the point of least `objective` among those it evaluated
/// that meet every constraint (`x0` included), with that value. Not COBYLA's last point: that one
/// may end slightly outside a constraint (which left SPDL still above about 12 dimensions, every
/// candidate refused), while a point it evaluated inside is as good a step. None if no evaluated
/// point meets them. The crate is a translation of C with unwraps inside: a panic there must not
/// reach the caller.
fn best_feasible(objective: Constraint<'_>, x0: &[f64], cons: &[Constraint<'_>], bounds: &[(f64, f64)]) -> Option<(Vec<f64>, f64)> {
    let best: std::cell::RefCell<Option<(Vec<f64>, f64)>> = std::cell::RefCell::new(None);
    let f = |v: &[f64], u: &mut ()| {
        let value = objective(v, u);
        let better = best.borrow().as_ref().is_none_or(|(_, b)| value < *b);
        if better && value.is_finite() && v.iter().all(|x| x.is_finite()) && cons.iter().all(|c| c(v, &mut ()) >= 0.0) {
            *best.borrow_mut() = Some((v.to_vec(), value));
        }
        value
    };
    f(x0, &mut ());
    let tol = cobyla::StopTols { ftol_rel: 1e-8, ftol_abs: 1e-10, xtol_rel: 1e-8, ..Default::default() };
    let run = std::panic::AssertUnwindSafe(|| cobyla::minimize(f, x0, bounds, cons, (), 2000, cobyla::RhoBeg::All(0.05), Some(tol)));
    // COBYLA's own outcome (its last point) is not used; after a panic, the points evaluated
    // before it still stand.
    let _ = std::panic::catch_unwind(run);
    best.into_inner()
}

impl GoalSelector for Spdl {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.unit_box.low, &self.unit_box.high)
    }
    fn sample(&mut self) -> GoalChoice {
        let u = self.st.dist.sample(&mut self.st.rng);
        GoalChoice { goal: self.unit_box.scale_back(&u), mode: Mode::Interest, region: None }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        self.st.buf_goals.extend(self.unit_box.to_unit(point));
        self.st.buf_values.push(competence);
        self.st.told += 1;
        if self.st.told >= self.cfg.warmup as u64 && self.st.buf_values.len() >= self.cfg.update_every {
            self.update_distribution();
        }
        None
    }
    /// One row: the context distribution as the box mean +- one standard deviation (in the
    /// task box), its KL to the target as `interest`, the goals told since the last update.
    fn leaf_table(&self) -> Vec<LeafRow> {
        let d = &self.st.dist;
        let std = d.std();
        let lo: Vec<f64> = d.mean.iter().zip(&std).map(|(m, s)| m - s).collect();
        let hi: Vec<f64> = d.mean.iter().zip(&std).map(|(m, s)| m + s).collect();
        let raw = |u: &[f64]| u.iter().zip(self.unit_box.low.iter().zip(&self.unit_box.high)).map(|(v, (l, h))| l + v * (h - l)).collect();
        vec![LeafRow { low: raw(&lo), high: raw(&hi), interest: d.kl(&self.target), n_measurements: self.st.buf_values.len() }]
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&self.st)
    }
    /// This version's state, or one saggriac 0.6 wrote before #46 (a diagonal Gaussian).
    fn load(&mut self, state: &[u8]) -> bool {
        let st = load_state::<SpdlState>(state).or_else(|| {
            let v0 = load_state::<SpdlStateV0>(state)?;
            let dist = Gaussian { mean: v0.mean, log_std: v0.log_std, lower: Vec::new() };
            Some(SpdlState { rng: v0.rng, dist, buf_goals: v0.buf_goals, buf_values: v0.buf_values, told: v0.told, updates: v0.updates })
        });
        let Some(st) = st else { return false };
        let d = self.unit_box.low.len();
        let lower = if self.cfg.covariance == SpdlCovariance::Full { d * (d - 1) / 2 } else { 0 };
        if st.dist.mean.len() != d || st.dist.log_std.len() != d || st.dist.lower.len() != lower || st.buf_goals.len() != st.buf_values.len() * d {
            return false;
        }
        self.st = st;
        true
    }
}

build_by_new!(SpdlConfig => Spdl, box, per_dimension);

#[cfg(test)]
mod tests;
