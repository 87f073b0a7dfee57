//! Property tests of the teachers behind the ask/tell API: a teacher saved at any point and
//! restored asks exactly the goals it would have asked, and every goal lies in its box.

mod common;

use proptest::prelude::*;

use common::{cases, TestResult};
use saggriac_core::config::teachers::{AdrConfig, GoalGanConfig, PerDimension, PlrConfig, PlrScore, PlrTies, RandomConfig, ReplaySchedule, SaggRiacConfig, SpdlConfig, SpdlCovariance, SpdlForm, Teacher, TsclConfig, TsclPolicy, TsclVariant};
use saggriac_core::high_level::ask_tell::AskTell;
use saggriac_core::high_level::goal_selection::ModeProbabilities;
use saggriac_core::high_level::interest::InterestDivisor;
use saggriac_core::high_level::region_tree::RegionTreeConfig;
use saggriac_core::high_level::teachers::alp_gmm::AlpGmmConfig;
use saggriac_core::high_level::teachers::covar_gmm::CovarGmmConfig;
use saggriac_core::high_level::teachers::discrete_lp::DiscreteLpConfig;
use saggriac_core::high_level::teachers::riac::RiacConfig;
use saggriac_core::high_level::teachers::TeacherSpec;
use saggriac_core::rng::{rng_from_seed, uniform};

/// Any teacher with random parameters over a random box (a task-list teacher ignores the box):
/// one line of `teacher` per teacher.
fn spec() -> impl Strategy<Value = TeacherSpec> {
    let bounds = (1usize..=6)
        .prop_flat_map(|d| proptest::collection::vec((-10.0..10.0f64, 1e-3..10.0f64), d))
        .prop_map(|b| (b.iter().map(|(l, _)| *l).collect::<Vec<f64>>(), b.iter().map(|(l, w)| l + w).collect::<Vec<f64>>()));
    let divisor = prop_oneof![Just(InterestDivisor::Zeta), Just(InterestDivisor::Window)];
    let tree = (2usize..=30, 2usize..=20, divisor)
        .prop_flat_map(|(g_max, zeta, divisor)| (Just(g_max), Just(zeta), 1usize..=g_max.div_ceil(2), Just(divisor)))
        .prop_map(|(g_max, zeta, min_child, divisor)| RegionTreeConfig { g_max, zeta, min_child, divisor });
    let riac = (5usize..=60, 1usize..=20, 0.05..0.5f64, 0.01..0.5f64).prop_map(|(max_region_size, split_attempts, min_child_share, min_dims_range_ratio)| RiacConfig {
        max_region_size,
        split_attempts,
        min_child_share,
        min_dims_range_ratio,
        ..RiacConfig::default()
    });
    let lp = (1usize..=12, 0.01..1.0f64, 0.01..0.99f64).prop_map(|(n_tasks, alpha, theta)| DiscreteLpConfig { n_tasks, alpha, theta });
    let mixture = || {
        (10usize..=60, 2usize..=5, 0.0..1.0f64, 0usize..80).prop_map(|(fit_rate, max_components, random_task_ratio, bootstrap)| AlpGmmConfig {
            fit_rate,
            max_components,
            random_task_ratio,
            bootstrap,
        })
    };
    // Thresholds inside the told competences' range [-1, 0], so that bounds both grow and shrink.
    let adr = (0.0..=1.0f64, 1usize..=12, -1.0..-0.5f64, -0.5..0.0f64, 0.01..0.5f64, 0.0..=1.0f64, 0.0..=1.0f64).prop_map(|(boundary_prob, buffer_size, t_low, t_high, step, initial, initial_width)| AdrConfig {
        boundary_prob,
        buffer_size,
        t_low,
        t_high,
        step,
        initial,
        initial_width,
    });
    let schedule = prop_oneof![Just(ReplaySchedule::Proportionate), Just(ReplaySchedule::Fixed)];
    let score = prop_oneof![Just(PlrScore::Progress), Just(PlrScore::Told)];
    let ties = prop_oneof![Just(PlrTies::Order), Just(PlrTies::Average)];
    let plr = (1usize..=12, 0.01..2.0f64, 0.0..=1.0f64, schedule, 0.0..=1.0f64, score, ties).prop_map(|(n_tasks, temperature, staleness_coef, replay_schedule, replay_prob, score, ties)| PlrConfig {
        n_tasks,
        temperature,
        staleness_coef,
        replay_schedule,
        replay_prob,
        score,
        ties,
    });
    // Updates often, so that the distribution moves (delta inside [-1, 0]) within a case.
    let form = prop_oneof![Just(SpdlForm::Delta), Just(SpdlForm::Alpha)];
    let covariance = prop_oneof![Just(SpdlCovariance::Diagonal), Just(SpdlCovariance::Full)];
    let alpha = (form, covariance, 0usize..=3, 0.0..=2.0f64);
    let spdl = (0.0..=1.0f64, 0.01..0.5f64, 0.0..=1.0f64, 0.05..1.0f64, 0.01..0.5f64, -1.0..0.0f64, 5usize..=50, 0usize..=50, alpha).prop_map(
        |(init_mean, init_std, target_mean, target_std, epsilon, delta, update_every, warmup, (form, covariance, alpha_offset, alpha_zeta))| SpdlConfig {
            init_mean,
            init_std,
            target_mean,
            target_std,
            epsilon,
            delta,
            update_every,
            warmup,
            form,
            covariance,
            alpha_offset,
            alpha_zeta,
        },
    );
    // Small networks and trainings, so that a case trains the GAN a few times quickly.
    // [r_min, r_max] always holds a success rate k / n_rollouts (1/2 or 1/3), as the config requires.
    let goal_gan = (-1.0..0.0f64, 0.0..=0.3f64, 0.7..=1.0f64, 2usize..=3, 2usize..=30, 0usize..=10, 0.0..=1.0f64, 1usize..=4, 1usize..=8).prop_map(|(success_threshold, r_min, r_max, n_rollouts, update_size, gan_iterations, p_old, noise_dim, hidden)| GoalGanConfig {
        success_threshold,
        r_min,
        r_max,
        n_rollouts,
        update_size,
        gan_iterations,
        p_old,
        noise_dim,
        hidden,
        ..GoalGanConfig::default()
    });
    let variant = prop_oneof![Just(TsclVariant::Window), Just(TsclVariant::Sampling)];
    let policy = prop_oneof![Just(TsclPolicy::EpsilonGreedy), Just(TsclPolicy::Boltzmann)];
    let tscl = (1usize..=12, variant, 2usize..=20, policy, 0.0..=1.0f64, 1e-4..1.0f64, any::<bool>()).prop_map(|(n_tasks, variant, window, policy, epsilon, temperature, absolute)| TsclConfig {
        n_tasks,
        variant,
        window,
        policy,
        epsilon,
        temperature,
        absolute,
    });
    let teacher = prop_oneof![
        tree.prop_map(|tree| Teacher::SaggRiac(SaggRiacConfig { tree, modes: ModeProbabilities::default(), ..Default::default() })),
        Just(Teacher::Random(RandomConfig {})),
        riac.prop_map(Teacher::Riac),
        lp.prop_map(Teacher::DiscreteLp),
        mixture().prop_map(Teacher::AlpGmm),
        (mixture(), any::<bool>()).prop_map(|(mixture, absolute_lp)| Teacher::CovarGmm(CovarGmmConfig { mixture, absolute_lp })),
        adr.prop_map(Teacher::Adr),
        plr.prop_map(Teacher::Plr),
        spdl.prop_map(Teacher::Spdl),
        goal_gan.prop_map(Teacher::GoalGan),
        tscl.prop_map(Teacher::Tscl),
    ];
    (bounds, teacher, any::<u64>()).prop_map(|((low, high), teacher, seed)| {
        let (low, high) = if teacher.has_box() { (low, high) } else { (Vec::new(), Vec::new()) };
        // Every other case gives a parameter per dimension (each within its rule).
        let d = low.len();
        let each = |name: &str, v: &dyn Fn(usize) -> f64| PerDimension(vec![(name.to_string(), (0..d).map(v).collect())]);
        let dims = match teacher {
            _ if seed % 2 == 1 => PerDimension::default(),
            Teacher::Adr(c) => each("step", &|i| (c.step * (1.0 + i as f64)).min(1.0)),
            Teacher::Spdl(c) => each("init_mean", &|i| (c.init_mean + 0.3 * i as f64) % 1.0),
            Teacher::GoalGan(c) => each("initial_width", &|i| c.initial_width / (1.0 + i as f64)),
            _ => PerDimension::default(),
        };
        TeacherSpec { teacher, low, high, seed, dims }
    })
}

/// The strategy has an arm for every teacher of the registry.
#[test]
fn every_registered_teacher_is_drawn() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let drawn: std::collections::BTreeSet<&str> = (0..2000).map(|_| spec().new_tree(&mut runner).unwrap().current().kind()).collect();
    let all: std::collections::BTreeSet<&str> = Teacher::all().iter().map(|t| t.kind()).collect();
    assert_eq!(drawn, all);
}

/// A competence with structure (a slope and a noisy patch), from the goal and a generator; a
/// success rate in [0, 1] for the discrete teacher.
fn competence(goal: &[f64], rng: &mut saggriac_core::rng::CoreRng, success: bool) -> f64 {
    let c = (-0.5 - 0.4 * (goal[0] * 0.7).sin() + 0.05 * uniform(rng, -1.0, 1.0)).clamp(-1.0, 0.0);
    if success {
        c + 1.0
    } else {
        c
    }
}

fn run_case(spec: TeacherSpec, before: usize, after: usize, batch: bool, seed: u64) -> TestResult {
    let mut a = AskTell::new(spec.clone()).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let mut rng = rng_from_seed(seed);
    let d = a.dim();
    let success = matches!(spec.teacher, Teacher::DiscreteLp(_));
    let (low, high) = (a.selector().low().to_vec(), a.selector().high().to_vec());
    let step = |t: &mut AskTell, rng: &mut saggriac_core::rng::CoreRng| -> Vec<f64> {
        let g = t.sample().goal;
        let c = competence(&g, rng, success);
        t.update(&g, c).unwrap();
        g
    };
    for _ in 0..before {
        step(&mut a, &mut rng);
    }
    let mut b = AskTell::restore(&a.save().unwrap()).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(b.spec(), &spec);
    prop_assert_eq!(&b.told_competence, &a.told_competence);
    if batch {
        // Batches: the same goals as one at a time, and updates of a whole batch.
        let (ga, gb) = (a.sample_batch(after).unwrap(), b.sample_batch(after).unwrap());
        prop_assert_eq!(&ga, &gb);
        let cs: Vec<f64> = ga.chunks_exact(d).map(|g| competence(g, &mut rng, success)).collect();
        prop_assert_eq!(a.update_batch(&ga, &cs).unwrap(), b.update_batch(&gb, &cs).unwrap());
    }
    for _ in 0..after {
        let mut rb = rng.clone();
        let ga = step(&mut a, &mut rng);
        let gb = step(&mut b, &mut rb);
        prop_assert_eq!(&ga, &gb);
        prop_assert!(ga.iter().zip(low.iter().zip(&high)).all(|(g, (l, h))| g >= l && g <= h), "goal {:?} outside [{:?}, {:?}]", ga, low, high);
    }
    Ok(())
}

proptest! {
    #![proptest_config(cases(32))]

    #[test]
    fn a_restored_teacher_continues_exactly(spec in spec(), before in 0usize..400, after in 1usize..150, batch in any::<bool>(), seed in any::<u64>()) {
        run_case(spec, before, after, batch, seed)?;
    }
}
