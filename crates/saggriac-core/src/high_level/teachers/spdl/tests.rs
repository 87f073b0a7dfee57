//! SPDL's unit tests: known answers of both forms, values per dimension, saving.

use super::*;

fn run(cfg: SpdlConfig, skill: impl Fn(&[f64], usize) -> f64, n: usize) -> (Spdl, Vec<Gaussian>) {
    let mut t = Spdl::new(&[0.0, 0.0], &[1.0, 1.0], cfg, 3).unwrap();
    let mut traj = vec![t.distribution().clone()];
    for k in 0..n {
        let g = t.sample().goal;
        let u = t.n_updates();
        t.update(&g, skill(&g, k));
        if t.n_updates() > u {
            traj.push(t.distribution().clone());
        }
    }
    (t, traj)
}

#[test]
fn moves_to_the_target_when_every_context_is_easy_within_the_kl_bound() {
    let cfg = SpdlConfig { init_mean: 0.2, init_std: 0.05, update_every: 50, warmup: 50, ..SpdlConfig::default() };
    let (t, traj) = run(cfg, |_, _| 1.0, 5000);
    for w in traj.windows(2) {
        assert!(w[1].kl(&w[0]) <= cfg.epsilon + 1e-6, "{}", w[1].kl(&w[0]));
    }
    let kls: Vec<f64> = traj.iter().map(|p| p.kl(t.target())).collect();
    assert!(kls.windows(2).all(|w| w[1] <= w[0] + 1e-9));
    assert!(*kls.last().unwrap() < 1e-2 * kls[0], "{kls:?}");
}

#[test]
fn stays_where_competence_is_below_delta_and_moves_as_it_grows() {
    let cfg = SpdlConfig { init_mean: 0.2, init_std: 0.05, update_every: 50, warmup: 50, ..SpdlConfig::default() };
    // Competence 1 within radius r(k) of the corner, 0 beyond; r grows with practice.
    let skill = |g: &[f64], k: usize| {
        let r = 0.3 + k as f64 / 4000.0;
        if (g[0].powi(2) + g[1].powi(2)).sqrt() < r { 1.0 } else { 0.0 }
    };
    let (t, traj) = run(cfg, skill, 4000);
    let kls: Vec<f64> = traj.iter().map(|p| p.kl(t.target())).collect();
    assert!(kls.last().unwrap() < &(0.5 * kls[0]), "{kls:?}");
    // Never told to harder contexts than the learner can do on average: the performance at
    // each accepted distribution was estimated >= delta; here the mean moves outward slowly.
    let (t2, _) = run(cfg, |_, _| 0.2, 2000);
    assert_eq!(t2.distribution(), &Gaussian { mean: vec![0.2; 2], log_std: vec![0.05f64.ln(); 2], lower: vec![] });
}

/// Phi, the standard normal CDF (Abramowitz & Stegun 7.1.26, error below 1.5e-7).
fn phi(z: f64) -> f64 {
    let x = z.abs() / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.3275911 * x);
    let poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    let erf = 1.0 - poly * (-x * x).exp();
    if z >= 0.0 { 0.5 * (1.0 + erf) } else { 0.5 * (1.0 - erf) }
}

/// Known optima on [0, 1]^d: start N(0.1, 0.05^2), target N(0.5, 0.25^2) in every dimension,
/// delta 0.5, an update every `every` goals. `competence` of the goal. Returns the
/// distribution after each update of the last half of `n` goals.
fn settle(d: usize, every: usize, seed: u64, n: usize, competence: impl Fn(&[f64]) -> f64) -> Vec<Gaussian> {
    let cfg = SpdlConfig { init_mean: 0.1, init_std: 0.05, update_every: every, warmup: every, ..SpdlConfig::default() };
    let mut t = Spdl::new(&vec![0.0; d], &vec![1.0; d], cfg, seed).unwrap();
    let mut out = Vec::new();
    for k in 0..n {
        let g = t.sample().goal;
        let u = t.n_updates();
        t.update(&g, competence(&g));
        if k >= n / 2 && t.n_updates() > u {
            out.push(t.distribution().clone());
        }
    }
    out
}

#[test]
fn holds_its_constraint_on_a_learnable_slab_in_2_and_5_dimensions() {
    // Competence 1 where x0 < 0.3: the problem's optimum is x0 ~ N(0.3, 0.25^2), the other
    // dimensions at the target, where E_p[competence] = Phi((0.3 - m0) / s0) = delta. Each
    // update sees 100 goals (a binary mean's sampling error 0.05): averaged over the last
    // half of the run and over seeds, E_p is delta within it. saggriac 0.6.0 (only forward
    // moves) settled at 0.40 (2-D) and 0.41 (5-D) here.
    for (d, seeds) in [(2, 0..4), (5, 0..2)] {
        let mut means = Vec::new();
        for seed in seeds {
            let traj = settle(d, 100, seed, 6000, |g| if g[0] < 0.3 { 1.0 } else { 0.0 });
            let e: Vec<f64> = traj.iter().map(|p| phi((0.3 - p.mean[0]) / p.log_std[0].exp())).collect();
            let mean = e.iter().sum::<f64>() / e.len() as f64;
            assert!((0.42..=0.58).contains(&mean), "d {d} seed {seed}: E_p {mean}");
            means.push(mean);
            // The other dimensions reach the target.
            let last = traj.last().unwrap();
            for i in 1..d {
                assert!((last.mean[i] - 0.5).abs() < 0.1 && (last.log_std[i].exp() - 0.25).abs() < 0.05, "{last:?}");
            }
        }
        let all = means.iter().sum::<f64>() / means.len() as f64;
        assert!((all - 0.5).abs() <= 0.05, "d {d}: E_p {all} over seeds {means:?}");
    }
}

#[test]
fn stays_where_nothing_is_learnable_and_reaches_the_target_where_everything_is() {
    for d in [2, 5] {
        for p in settle(d, 100, 1, 3000, |_| 0.0) {
            assert_eq!(p, Gaussian { mean: vec![0.1; d], log_std: vec![0.05f64.ln(); d], lower: vec![] });
        }
        let traj = settle(d, 100, 1, 6000, |_| 1.0);
        let target = Gaussian { mean: vec![0.5; d], log_std: vec![0.25f64.ln(); d], lower: vec![] };
        assert!(traj.last().unwrap().kl(&target) < 1e-3, "{:?}", traj.last());
    }
}

#[test]
fn moves_beyond_twelve_dimensions() {
    // saggriac 0.6.0 took no step from 15 dimensions on (COBYLA's last point, just outside a
    // constraint, was refused), which left p where it started.
    let d = 16;
    let cfg = SpdlConfig { init_mean: 0.2, init_std: 0.05, update_every: 100, warmup: 100, ..SpdlConfig::default() };
    let mut t = Spdl::new(&vec![0.0; d], &vec![1.0; d], cfg, 0).unwrap();
    let before = t.distribution().kl(t.target());
    let mut last = t.distribution().clone();
    for _ in 0..300 {
        let g = t.sample().goal;
        t.update(&g, 1.0);
        assert!(t.distribution().kl(&last) <= cfg.epsilon + 1e-9);
        last = t.distribution().clone();
    }
    assert_eq!(t.n_updates(), 3);
    assert!(t.distribution().kl(t.target()) < before - 1.0, "{before} -> {}", t.distribution().kl(t.target()));
}

#[test]
fn the_alpha_form_stays_without_competence_and_walks_to_the_target_in_natural_steps() {
    let cfg = SpdlConfig { init_mean: 0.1, init_std: 0.05, update_every: 50, warmup: 50, form: SpdlForm::Alpha, alpha_zeta: 0.5, ..SpdlConfig::default() };
    for covariance in [SpdlCovariance::Diagonal, SpdlCovariance::Full] {
        let cfg = SpdlConfig { covariance, ..cfg };
        // No competence: alpha = 0 and a zero gradient, so no step (TeachMyAgent skips it too).
        let mut t = Spdl::new(&[0.0, 0.0], &[1.0, 1.0], cfg, 2).unwrap();
        let start = t.distribution().clone();
        for _ in 0..500 {
            let g = t.sample().goal;
            t.update(&g, 0.0);
        }
        assert_eq!((t.n_updates(), t.distribution()), (10, &start));
        // Every goal a success: each step within 1.5 epsilon of KL(p_old || p), toward mu.
        let mut t = Spdl::new(&[0.0, 0.0], &[1.0, 1.0], cfg, 2).unwrap();
        let mut last = t.distribution().clone();
        for _ in 0..4000 {
            let g = t.sample().goal;
            t.update(&g, 1.0);
            assert!(last.kl(t.distribution()) <= 1.5 * cfg.epsilon + 1e-12);
            last = t.distribution().clone();
        }
        assert_eq!(t.distribution().lower.len(), if covariance == SpdlCovariance::Full { 1 } else { 0 });
        assert!(t.distribution().kl(t.target()) < 0.1, "{covariance:?}: {:?}", t.distribution());
    }
}

#[test]
fn values_per_dimension_and_a_full_covariance_are_the_start_and_the_target() {
    let dims = PerDimension(vec![
        ("init_mean".into(), vec![0.1, 0.8]),
        ("init_std".into(), vec![0.05, 0.2]),
        ("target_cov".into(), vec![0.04, 0.03, 0.03, 0.09]),
    ]);
    let cfg = SpdlConfig { covariance: SpdlCovariance::Full, update_every: 100, warmup: 100, ..SpdlConfig::default() };
    let mut t = Spdl::with_dims(&[0.0, 0.0], &[1.0, 2.0], cfg, &dims, 5).unwrap();
    assert_eq!(t.distribution().mean, vec![0.1, 0.8]);
    assert!((t.distribution().std()[1] - 0.2).abs() < 1e-12);
    let c = t.target().covariance();
    assert!((c[(0, 1)] - 0.03).abs() < 1e-12 && (c[(1, 1)] - 0.09).abs() < 1e-12);
    // Every goal a success: p takes the target's correlation on.
    for _ in 0..6000 {
        let g = t.sample().goal;
        t.update(&g, 1.0);
    }
    assert!(t.distribution().kl(t.target()) < 1e-3, "{:?}", t.distribution());
    // A covariance with correlations needs a full p; a diagonal one is taken either way.
    let diag = SpdlConfig { covariance: SpdlCovariance::Diagonal, ..cfg };
    let e = Spdl::with_dims(&[0.0, 0.0], &[1.0, 2.0], diag, &dims, 5).err().unwrap().to_string();
    assert!(e.starts_with("The 'target_cov' parameter of SpdlSelector must be a diagonal matrix with covariance='diagonal'"), "{e}");
    let ok = PerDimension(vec![("target_cov".into(), vec![0.04, 0.0, 0.0, 0.09])]);
    let std = Spdl::with_dims(&[0.0, 0.0], &[1.0, 2.0], diag, &ok, 5).unwrap().target().std();
    assert!((std[0] - 0.2).abs() < 1e-12 && (std[1] - 0.3).abs() < 1e-12, "{std:?}");
}

#[test]
fn more_dimensions_than_an_update_can_afford_are_refused() {
    let d = MAX_SPDL_DIM + 1;
    let e = Spdl::new(&vec![0.0; d], &vec![1.0; d], SpdlConfig::default(), 0).err().unwrap().to_string();
    assert!(e.starts_with("The 'bounds' parameter of SpdlSelector must be bounds of at most 30 dimensions (each update runs COBYLA"), "{e}");
    assert!(e.ends_with("Got 31 dimensions instead."), "{e}");
    // At the bound an update runs and keeps both constraints.
    let cfg = SpdlConfig { update_every: 60, warmup: 60, ..SpdlConfig::default() };
    let mut t = Spdl::new(&vec![0.0; MAX_SPDL_DIM], &vec![1.0; MAX_SPDL_DIM], cfg, 1).unwrap();
    let before = t.distribution().clone();
    for _ in 0..60 {
        let g = t.sample().goal;
        t.update(&g, 1.0);
    }
    assert_eq!(t.n_updates(), 1);
    assert!(t.distribution().kl(&before) <= cfg.epsilon + 1e-6);
}

#[test]
fn save_and_load_continue_exactly() {
    let cfg = SpdlConfig { update_every: 20, warmup: 20, ..SpdlConfig::default() };
    let mut a = Spdl::new(&[-1.0, 0.0, 2.0], &[1.0, 3.0, 5.0], cfg, 9).unwrap();
    for k in 0..95 {
        let g = a.sample().goal;
        a.update(&g, (k % 3) as f64 / 2.0);
    }
    let mut b = Spdl::new(&[-1.0, 0.0, 2.0], &[1.0, 3.0, 5.0], cfg, 0).unwrap();
    assert!(b.load(&a.save().unwrap()));
    for k in 0..100 {
        let (ga, gb) = (a.sample().goal, b.sample().goal);
        assert_eq!(ga, gb);
        assert!(ga.iter().zip([-1.0, 0.0, 2.0].iter().zip([1.0, 3.0, 5.0])).all(|(g, (l, h))| *l <= *g && *g <= h));
        a.update(&ga, (k % 4) as f64 / 3.0);
        b.update(&gb, (k % 4) as f64 / 3.0);
    }
    assert!(!b.load(&[1, 2, 3]));
}
