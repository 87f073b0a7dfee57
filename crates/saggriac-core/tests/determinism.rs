//! Reproducibility of whole runs.
//!
//! A run is a pure function of (config, seed, eval_seed): two learners built alike must agree
//! bit for bit. The evaluation only reads the memory, so how often it runs (and with which test
//! set) must not change the training trajectory. The neighbour searches are exact, so the choice
//! of index and of warm or cold search must not change it either.
//!
//! Floats are compared through `to_bits`, so NaN (the competence of a goal interrupted by the
//! step budget) compares equal to itself and -0.0 differs from 0.0.

use saggriac_core::model::memory::IndexKind;
use saggriac_core::recorder::{AttemptRow, Counters, GoalRow, MetricRow};
use saggriac_core::task_space::{Point, MAX_TASK_DIM};
use saggriac_core::{Condition, Learner, RunConfig};

use std::sync::OnceLock;

const N_STEPS: u64 = 3000;

/// A small run: 3000 micro-actions, 20 test goals and 20 test configurations.
fn small_config(condition: Condition, schedule: Vec<u64>) -> RunConfig {
    let mut cfg = RunConfig { condition, n_steps: N_STEPS, ..RunConfig::default() };
    cfg.eval.n_test_goals = 20;
    cfg.eval.n_test_configs = 20;
    cfg.eval.schedule = schedule;
    cfg
}

/// The same run with a lighter evaluation (4 test goals, 4 test configurations), for the tests
/// about the training trajectory: an evaluation costs more than 3000 training steps.
fn light_config(schedule: Vec<u64>) -> RunConfig {
    let mut cfg = small_config(Condition::SaggRiac, schedule);
    cfg.eval.n_test_goals = 4;
    cfg.eval.n_test_configs = 4;
    cfg
}

const LIGHT_SEED: u64 = 13;
const LIGHT_EVAL_SEED: u64 = 14;

/// `light_config(vec![N_STEPS])` run with LIGHT_SEED: the reference trajectory, run once and
/// shared by the tests below.
fn light_reference() -> &'static Learner {
    static RUN: OnceLock<Learner> = OnceLock::new();
    RUN.get_or_init(|| run(light_config(vec![N_STEPS]), LIGHT_SEED, LIGHT_EVAL_SEED))
}

fn default_schedule() -> Vec<u64> {
    vec![0, N_STEPS / 2, N_STEPS]
}

fn run(cfg: RunConfig, seed: u64, eval_seed: u64) -> Learner {
    let mut l = Learner::new(cfg, seed, eval_seed).expect("valid config");
    assert!(l.run(&mut |_| true), "the run must complete");
    assert_eq!(l.steps(), N_STEPS);
    l
}

fn bits(v: &Point) -> [u64; MAX_TASK_DIM] {
    v.map(f64::to_bits)
}

type MetricKey = (u64, u64, u64, u64, u64, u64);
fn metric_key(m: &MetricRow) -> MetricKey {
    (m.step, m.n_samples, m.reach_error.to_bits(), m.pred_error.to_bits(), m.n_goals, m.n_regions)
}

type GoalKey = (u64, u64, u64, [u64; MAX_TASK_DIM], [u64; MAX_TASK_DIM], [u64; MAX_TASK_DIM], u8, Option<usize>, u64);
fn goal_key(g: &GoalRow) -> GoalKey {
    (g.goal_index, g.step_start, g.step_end, bits(&g.goal), bits(&g.start), bits(&g.end), g.mode as u8, g.region, g.competence.to_bits())
}

type AttemptKey = (u64, u32, u64, [u64; MAX_TASK_DIM], [u64; MAX_TASK_DIM], u64, bool, Option<usize>);
fn attempt_key(a: &AttemptRow) -> AttemptKey {
    (a.goal_index, a.subgoal, a.step_end, bits(&a.target), bits(&a.end), a.competence.to_bits(), a.reached, a.region)
}

fn metrics(l: &Learner) -> Vec<MetricKey> {
    l.metrics().iter().map(metric_key).collect()
}
fn goals(l: &Learner) -> Vec<GoalKey> {
    l.goals().iter().map(goal_key).collect()
}
fn attempts(l: &Learner) -> Vec<AttemptKey> {
    l.attempts().iter().map(attempt_key).collect()
}

/// Every stored sample (theta, dtheta, dx, x), as bits.
fn memory_bits(l: &Learner) -> Vec<u64> {
    let m = l.memory();
    let mut out = Vec::new();
    for i in 0..m.len() {
        for part in [&m.theta(i)[..], m.dtheta(i), m.dx(i), m.x(i)] {
            out.extend(part.iter().map(|v| v.to_bits()));
        }
    }
    out
}

/// The counters that describe training only (test_steps belongs to the evaluation).
fn training_counters(l: &Learner) -> Counters {
    Counters { test_steps: 0, ..l.counters().clone() }
}

/// Everything that describes what was learnt, independent of the evaluation.
fn assert_same_training(a: &Learner, b: &Learner, what: &str) {
    assert_eq!(goals(a), goals(b), "{what}: goals differ");
    assert_eq!(attempts(a), attempts(b), "{what}: attempts differ");
    assert_eq!(a.memory().len(), b.memory().len(), "{what}: memory sizes differ");
    assert!(memory_bits(a) == memory_bits(b), "{what}: stored samples differ");
    assert_eq!(training_counters(a), training_counters(b), "{what}: training counters differ");
    let (ta, tb): (Vec<u64>, Vec<u64>) = (a.body().theta().iter().map(|v| v.to_bits()).collect(), b.body().theta().iter().map(|v| v.to_bits()).collect());
    assert_eq!(ta, tb, "{what}: final arm configurations differ");
}

fn assert_sane(l: &Learner) {
    assert!(!l.goals().is_empty(), "a 3000-step run attempts some goals");
    assert!(!l.attempts().is_empty());
    assert_eq!(l.memory().len() as u64, N_STEPS, "every micro-action is stored");
    let c = l.counters();
    assert_eq!(c.reaching_steps + c.exploration_steps, N_STEPS);
}

#[test]
fn same_seed_same_run_sagg_riac() {
    let cfg = small_config(Condition::SaggRiac, default_schedule());
    let a = run(cfg.clone(), 11, 1011);
    let b = run(cfg, 11, 1011);
    assert_sane(&a);
    assert_eq!(a.metrics().len(), 3);
    assert_eq!(metrics(&a), metrics(&b), "metrics differ");
    assert_eq!(a.metrics().iter().map(|m| m.step).collect::<Vec<_>>(), default_schedule());
    assert_same_training(&a, &b, "same seed");
    assert_eq!(a.counters(), b.counters());
    // The region tree grew the same way.
    let (ta, tb) = (a.selector().tree().unwrap(), b.selector().tree().unwrap());
    assert_eq!(ta.leaves(), tb.leaves());
    assert_eq!(ta.n_measurements(), tb.n_measurements());
}

#[test]
fn same_seed_same_run_sagg_random() {
    let mut cfg = light_config(default_schedule());
    cfg.condition = Condition::SaggRandom;
    let a = run(cfg.clone(), 5, 6);
    let b = run(cfg, 5, 6);
    assert_sane(&a);
    assert_eq!(metrics(&a), metrics(&b), "metrics differ");
    assert_same_training(&a, &b, "same seed (sagg_random)");
}

#[test]
fn different_seed_different_goals() {
    let a = light_reference();
    let b = run(light_config(vec![N_STEPS]), LIGHT_SEED + 1, LIGHT_EVAL_SEED);
    let ga: Vec<[u64; MAX_TASK_DIM]> = a.goals().iter().map(|g| bits(&g.goal)).collect();
    let gb: Vec<[u64; MAX_TASK_DIM]> = b.goals().iter().map(|g| bits(&g.goal)).collect();
    assert_ne!(ga, gb, "seeds {} and {} chose the same goals", LIGHT_SEED, LIGHT_SEED + 1);
    // Not just one stray goal: the very first goal already differs.
    assert_ne!(ga[0], gb[0], "seeds {} and {} chose the same first goal", LIGHT_SEED, LIGHT_SEED + 1);
    // Same eval seed: both met the same test set.
    assert_eq!(a.test_set().goals, b.test_set().goals);
}

#[test]
fn evaluation_frequency_does_not_change_learning() {
    // Many evaluation points, at odd steps that fall in the middle of goal attempts and
    // exploration phases, against the single final one of the reference.
    let dense: Vec<u64> = (0..=N_STEPS).step_by(211).chain([N_STEPS]).collect();
    let a = run(light_config(dense.clone()), LIGHT_SEED, LIGHT_EVAL_SEED);
    let b = light_reference();
    assert_eq!(a.metrics().len(), dense.len());
    assert_eq!(b.metrics().len(), 1);
    assert_same_training(&a, b, "dense vs final-only evaluation");
    // The final evaluation reads the same memory with the same test set: same numbers.
    assert_eq!(metric_key(a.metrics().last().unwrap()), metric_key(&b.metrics()[0]));
    assert!(a.counters().test_steps > b.counters().test_steps, "the dense schedule did evaluate more");
}

#[test]
fn evaluation_test_set_does_not_change_learning() {
    let a = light_reference();
    let b = run(light_config(vec![N_STEPS]), LIGHT_SEED, LIGHT_EVAL_SEED + 1);
    assert_same_training(a, &b, "different eval seeds");
    assert_ne!(a.test_set().goals, b.test_set().goals, "different eval seeds drew the same test goals");
    assert_ne!(metrics(a), metrics(&b), "different test sets gave bit-identical metrics");
}

#[test]
fn stopping_and_resuming_does_not_change_learning() {
    // Stop at every evaluation callback, then call run() again until it reports completion.
    let schedule: Vec<u64> = (0..=N_STEPS).step_by(500).collect();
    let cfg = light_config(schedule);
    let mut pieces = Learner::new(cfg, LIGHT_SEED, LIGHT_EVAL_SEED).unwrap();
    let mut calls = 0;
    let mut seen = Vec::new();
    loop {
        calls += 1;
        assert!(calls < 100, "run() does not make progress when stopped on every row");
        let done = pieces.run(&mut |m| {
            seen.push(m.step);
            false
        });
        if done || pieces.steps() >= N_STEPS {
            break;
        }
    }
    assert!(calls > 2, "run() was stopped and resumed");
    assert_same_training(light_reference(), &pieces, "stopped and resumed");
    assert_eq!(seen, pieces.metrics().iter().map(|m| m.step).collect::<Vec<_>>(), "every row shown exactly once");
    assert_eq!(pieces.metrics().len(), 7);
    assert_eq!(metric_key(pieces.metrics().last().unwrap()), metric_key(&light_reference().metrics()[0]));
}

#[test]
fn exact_neighbour_search_variants_learn_the_same() {
    // Warm-started and cold searches, over the default index or the full scan, are all exact
    // and break ties by id, so they must drive the arm through the very same trajectory.
    let reference = light_reference();
    assert_eq!((reference.config().index, reference.config().warm_start_recent), (IndexKind::Blocks, 8));
    for (index, warm) in [(IndexKind::Blocks, 0), (IndexKind::Blocks, 1), (IndexKind::BruteForce, 8), (IndexKind::BruteForce, 0)] {
        let mut cfg = light_config(vec![N_STEPS]);
        cfg.index = index;
        cfg.warm_start_recent = warm;
        let name = format!("{} warm={warm}", index.name());
        let l = run(cfg, LIGHT_SEED, LIGHT_EVAL_SEED);
        assert_same_training(reference, &l, &name);
        assert_eq!(metrics(reference), metrics(&l), "{name}: metrics differ");
    }
}

#[test]
fn same_seed_same_run_actuator_conditions() {
    for condition in [Condition::ActuatorRandom, Condition::ActuatorRiac] {
        let mut cfg = light_config(default_schedule());
        cfg.condition = condition;
        let a = run(cfg.clone(), 5, 6);
        let b = run(cfg.clone(), 5, 6);
        assert_eq!(metrics(&a), metrics(&b), "metrics differ for {condition:?}");
        assert_eq!(a.counters(), b.counters());
        assert_eq!(a.counters().babbling_steps, N_STEPS);
        let th = |l: &Learner| (0..l.memory().len()).flat_map(|i| l.memory().theta(i).iter().map(|v| v.to_bits()).collect::<Vec<_>>()).collect::<Vec<_>>();
        assert_eq!(th(&a), th(&b), "stored configurations differ for {condition:?}");
        let c = run(cfg, 7, 6);
        assert_ne!(th(&a), th(&c), "seeds 5 and 7 babbled identically for {condition:?}");
    }
}

/// Stop at every evaluation, save a checkpoint, drop the learner, restore it from the bytes and
/// go on: the result must be the uninterrupted run's, bit for bit, evaluations included.
fn assert_checkpoints_are_invisible(cfg: RunConfig, seed: u64, eval_seed: u64) {
    let reference = {
        let mut l = Learner::new(cfg.clone(), seed, eval_seed).unwrap();
        assert!(l.run(&mut |_| true));
        l
    };
    let mut l = Learner::new(cfg.clone(), seed, eval_seed).unwrap();
    let mut restores = 0;
    while !l.run(&mut |_| false) {
        let bytes = l.checkpoint().expect("built-in parts can be saved");
        drop(l);
        l = Learner::restore(cfg.clone(), &bytes).expect("a fresh checkpoint restores");
        restores += 1;
        assert!(restores < 1000);
    }
    assert!(restores > 2, "the run was checkpointed and restored several times");
    let what = format!("{:?} {:?} after {restores} restores", cfg.condition, cfg.paradigm);
    assert_eq!(metrics(&l), metrics(&reference), "{what}: metrics differ");
    assert_same_training(&l, &reference, &what);
    assert_eq!(l.selector().tree().map(|t| t.regions().len()), reference.selector().tree().map(|t| t.regions().len()), "{what}: trees differ");
}

#[test]
fn checkpoint_and_restore_change_nothing() {
    let schedule: Vec<u64> = (0..=N_STEPS).step_by(300).collect();
    for condition in [Condition::SaggRiac, Condition::SaggRandom, Condition::ActuatorRandom, Condition::ActuatorRiac] {
        let mut cfg = light_config(schedule.clone());
        cfg.condition = condition;
        assert_checkpoints_are_invisible(cfg, 21, 22);
    }
    // Noise and a body change mid-run, in both paradigms.
    for paradigm in [saggriac_core::config::Paradigm::MicroActions, saggriac_core::config::Paradigm::Episodic] {
        let mut cfg = light_config(schedule.clone());
        cfg.paradigm = paradigm;
        cfg.arm.motor_noise = 0.003;
        cfg.arm.sensor_noise = 0.02;
        cfg.body_change = Some(saggriac_core::config::BodyChange { step: 1234, link: 3, length: 7.0 });
        assert_checkpoints_are_invisible(cfg, 5, 6);
    }
}

/// The light configuration with the arm in space and a 3-D goal space.
fn spatial(mut cfg: RunConfig) -> RunConfig {
    cfg.arm.kind = saggriac_core::body::arm::ArmKind::Spatial;
    cfg.goal_low = vec![0.0, -50.0, -50.0];
    cfg.goal_high = vec![50.0, 50.0, 50.0];
    cfg
}

#[test]
fn spatial_arm_runs_are_reproducible_and_checkpoints_invisible() {
    let schedule: Vec<u64> = (0..=N_STEPS).step_by(500).collect();
    for condition in [Condition::SaggRiac, Condition::ActuatorRiac] {
        let mut cfg = spatial(light_config(schedule.clone()));
        cfg.condition = condition;
        let (a, b) = (run(cfg.clone(), 3, 4), run(cfg.clone(), 3, 4));
        assert_eq!(metrics(&a), metrics(&b));
        assert_eq!(goals(&a), goals(&b));
        assert_eq!(attempts(&a), attempts(&b));
        if condition == Condition::SaggRiac {
            assert_sane(&a);
        }
        assert_checkpoints_are_invisible(cfg, 3, 4);
    }
    let mut cfg = spatial(light_config(schedule));
    cfg.paradigm = saggriac_core::config::Paradigm::Episodic;
    cfg.arm.sensor_noise = 0.02;
    assert_checkpoints_are_invisible(cfg, 7, 8);
}

#[test]
fn spatial_goals_use_all_three_coordinates() {
    let l = light_reference_spatial();
    assert!(!l.goals().is_empty());
    for g in l.goals() {
        assert!(g.goal[0] >= 0.0 && g.goal[0] <= 50.0 && g.goal[1].abs() <= 50.0 && g.goal[2].abs() <= 50.0, "{:?}", g.goal);
    }
    // The arm leaves the plane z = 0.
    assert!(l.goals().iter().any(|g| g.end[2].abs() > 1.0));
    assert_eq!(l.task_dim(), 3);
    assert_eq!(l.memory().task_dim(), 3);
}

fn light_reference_spatial() -> Learner {
    run(spatial(light_config(vec![N_STEPS])), LIGHT_SEED, LIGHT_EVAL_SEED)
}

#[test]
fn the_goal_space_must_match_the_body() {
    let mut cfg = light_config(vec![N_STEPS]);
    cfg.goal_low = vec![0.0, -50.0, -50.0];
    cfg.goal_high = vec![50.0, 50.0, 50.0];
    let e = Learner::new(cfg, 1, 2).err().expect("a 3-D goal space for the planar arm is refused").to_string();
    assert_eq!(e, "The 'goal_low' parameter of Run must be a list of 2 floats (the planar arm's task space is 2-D). Got [0.0, -50.0, -50.0] instead.");
    let mut cfg = spatial(light_config(vec![N_STEPS]));
    cfg.goal_low = vec![0.0; 4];
    cfg.goal_high = vec![1.0; 4];
    let e = Learner::new(cfg, 1, 2).err().expect("4-D is refused").to_string();
    assert!(e.contains("'goal_low'") && e.contains("1 to 3 floats"), "{e}");
}

#[test]
fn a_checkpoint_only_restores_its_own_run() {
    let mut l = Learner::new(light_config(vec![0, 1000, N_STEPS]), 1, 2).unwrap();
    l.run(&mut |m| m.step < 1000);
    let bytes = l.checkpoint().unwrap();
    let mut other = light_config(vec![0, 1000, N_STEPS]);
    other.tree.g_max = 40;
    let e = Learner::restore(other, &bytes).err().expect("another configuration is refused").to_string();
    assert!(e.contains("another configuration"), "{e}");
    let e = Learner::restore(light_config(vec![0, 1000, N_STEPS]), &bytes[..bytes.len() / 2]).err().expect("a truncated checkpoint is refused").to_string();
    assert!(e.contains("damaged"), "{e}");
    let mut longer = bytes.clone();
    longer.push(0);
    let e = Learner::restore(light_config(vec![0, 1000, N_STEPS]), &longer).err().expect("trailing bytes are refused").to_string();
    assert!(e.contains("damaged"), "{e}");
}

#[test]
fn a_checkpoint_with_any_flipped_byte_is_refused() {
    let cfg = light_config(vec![0, 1000, N_STEPS]);
    let mut l = Learner::new(cfg.clone(), 1, 2).unwrap();
    l.run(&mut |m| m.step < 1000);
    let bytes = l.checkpoint().unwrap();
    assert!(Learner::restore(cfg.clone(), &bytes).is_ok());
    // Every position near both ends (header, checksum) and 200 spread over the body, with a
    // one-bit and an all-bits change each.
    let n = bytes.len();
    let mut positions: Vec<usize> = (0..64.min(n)).chain(n.saturating_sub(64)..n).collect();
    positions.extend((0..200).map(|i| i * n / 200));
    for &pos in &positions {
        for mask in [0x01u8, 0xFF] {
            let mut bad = bytes.clone();
            bad[pos] ^= mask;
            let e = Learner::restore(cfg.clone(), &bad).err().unwrap_or_else(|| panic!("byte {pos} ^ {mask:#x} of {n} was resumed")).to_string();
            assert!(e.contains("damaged") || e.contains("another configuration") || e.contains("format"), "byte {pos}: {e}");
            assert!(e.contains("without --resume") || e.contains("another configuration") || e.contains("format"), "byte {pos}: {e}");
        }
    }
}

/// `cfg` run with evaluations on `threads` threads.
fn run_on_threads(cfg: RunConfig, threads: usize, seed: u64) -> Learner {
    let mut l = Learner::new(cfg, seed, seed + 1).expect("valid config");
    l.set_threads(threads);
    assert!(l.run(&mut |_| true), "the run must complete");
    l
}

#[test]
fn evaluations_on_other_threads_give_the_same_run() {
    let schedule: Vec<u64> = (0..=N_STEPS).step_by(250).collect();
    let mut changed = small_config(Condition::SaggRiac, schedule.clone());
    changed.body_change = Some(saggriac_core::config::BodyChange { step: 1234, link: 3, length: 6.0 });
    let mut noisy = small_config(Condition::SaggRiac, schedule.clone());
    noisy.arm.motor_noise = 0.01;
    let cases = [
        (small_config(Condition::SaggRiac, schedule.clone()), true),
        (small_config(Condition::ActuatorRandom, schedule.clone()), true),
        (small_config(Condition::ActuatorRiac, schedule.clone()), true),
        (changed, true),
        // The arm's noise generator runs on between evaluations: they stay in this thread.
        (noisy, false),
    ];
    for (cfg, elsewhere) in cases {
        let one = run_on_threads(cfg.clone(), 1, 21);
        assert_eq!(one.parts().evaluator().evaluations_elsewhere(), 0);
        for threads in [2, 3] {
            let many = run_on_threads(cfg.clone(), threads, 21);
            let what = format!("{:?} on {threads} threads", cfg.condition);
            assert_eq!(many.parts().evaluator().evaluations_elsewhere() > 0, elsewhere, "{what}");
            assert_eq!(metrics(&many), metrics(&one), "{what}: metrics differ");
            assert!(many.metrics().iter().all(|m| m.reach_error.is_finite() && m.pred_error.is_finite()), "{what}: a row was not filled in");
            assert_same_training(&many, &one, &what);
            assert_eq!(many.counters().test_steps, one.counters().test_steps, "{what}: test steps differ");
        }
    }
}

#[test]
fn checkpoints_between_threaded_evaluations_change_nothing() {
    let cfg = small_config(Condition::ActuatorRandom, (0..=N_STEPS).step_by(300).collect());
    let reference = run_on_threads(cfg.clone(), 1, 5);
    let mut l = Learner::new(cfg.clone(), 5, 6).unwrap();
    l.set_threads(2);
    let mut restores = 0;
    let mut seen = Vec::new();
    while !l.run(&mut |row| {
        seen.push(row.step);
        false
    }) {
        let bytes = l.checkpoint().expect("built-in parts can be saved");
        l = Learner::restore(cfg.clone(), &bytes).expect("a fresh checkpoint restores");
        l.set_threads(2);
        restores += 1;
    }
    assert!(restores > 2);
    // Every row was shown once, in order, and the run is the uninterrupted one.
    assert_eq!(seen, reference.metrics().iter().map(|m| m.step).collect::<Vec<_>>());
    assert_eq!(metrics(&l), metrics(&reference));
    assert_same_training(&l, &reference, "checkpointed on 2 threads");
}
