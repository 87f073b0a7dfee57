//! The worked example of docs/architecture.md: a new low-level controller is one type
//! implementing `LowLevel`. This one reaches each goal in a straight line with the inverse model,
//! without subgoals or exploration phases; where no local model can be fitted yet it babbles one
//! random micro-action instead. It runs inside the same loop as the built-in controllers.

use saggriac_core::assembly::UserParts;
use saggriac_core::high_level::competence::competence;
use saggriac_core::high_level::goal_selection::GoalChoice;
use saggriac_core::low_level::LowLevel;
use saggriac_core::parts::{ActionKind, Parts};
use saggriac_core::rng::uniform;
use saggriac_core::task_space::{desired_step, distance, point};
use saggriac_core::{Learner, RunConfig};

struct StraightLine {
    cfg: RunConfig,
    dtheta: Vec<f64>,
}

impl LowLevel for StraightLine {
    fn rest_due(&self, parts: &Parts) -> bool {
        parts.recorder().goals_done() % 2 == 0
    }
    fn asks_high_level(&self) -> bool {
        true
    }
    fn attempt(&mut self, choice: Option<GoalChoice>, parts: &mut Parts) {
        let choice = choice.unwrap();
        let m = parts.model().task_dim();
        let (goal, start, step_start) = (point(&choice.goal[..m]), parts.body().position(), parts.recorder().steps());
        for _ in 0..self.cfg.reaching.timeout(distance(&goal, &start)) {
            let dx = desired_step(&parts.body().position(), &goal, self.cfg.reaching.v);
            if parts.inverse_here(&dx, &mut self.dtheta).is_err() {
                let b = self.cfg.babble_step;
                self.dtheta.iter_mut().for_each(|d| *d = uniform(parts.rng(), -b, b));
            }
            if parts.micro_action(&mut self.dtheta, ActionKind::Reaching).is_none() || distance(&parts.body().position(), &goal) < 0.1 {
                break;
            }
        }
        let end = parts.body().position();
        let c = competence(&goal, &end, &start, &self.cfg.competence);
        let region = parts.tell(&goal[..m], c);
        parts.record_attempt(1, goal, end, c, region);
        parts.finish_goal(&choice, goal, step_start, start, end, c);
    }
}

fn learner(seed: u64) -> Learner {
    let mut cfg = RunConfig { n_steps: 4000, ..RunConfig::default() };
    cfg.eval.schedule = vec![0, 2000, 4000];
    cfg.eval.n_test_goals = 10;
    cfg.eval.n_test_configs = 10;
    let low = StraightLine { dtheta: vec![0.0; cfg.arm.link_lengths.len()], cfg: cfg.clone() };
    let mut l = Learner::from_parts(cfg, seed, 1, UserParts { low_level: Some(Box::new(low)), ..UserParts::default() }).unwrap();
    assert!(l.run(&mut |_| true));
    l
}

#[test]
fn a_new_controller_runs_in_the_loop() {
    let l = learner(3);
    assert_eq!(l.steps(), 4000);
    assert_eq!(l.memory().len(), 4000, "every micro-action is stored");
    assert_eq!(l.metrics().len(), 3);
    assert!(l.goals().len() > 10 && l.attempts().len() == l.goals().len());
    assert!(l.selector().tree().unwrap().n_measurements() == l.attempts().len(), "the high level heard every goal");
    assert!(l.goals().iter().all(|g| (-1.0..=0.0).contains(&g.competence)));
    let (first, last) = (&l.metrics()[0], &l.metrics()[2]);
    assert!(last.reach_error < first.reach_error, "it learns: {} -> {}", first.reach_error, last.reach_error);
    // Same seed, same run.
    let again = learner(3);
    assert_eq!(again.goals(), l.goals());
    assert_eq!(again.metrics(), l.metrics());
}

/// A controller that calls the other paradigm's time step: `movement` in a run of micro-actions,
/// or `micro_action` in an episodic run.
struct WrongParadigm {
    calls_movement: bool,
}

impl LowLevel for WrongParadigm {
    fn asks_high_level(&self) -> bool {
        false
    }
    fn attempt(&mut self, _choice: Option<GoalChoice>, parts: &mut Parts) {
        let n = parts.body().n_joints();
        if self.calls_movement {
            assert!(parts.movement(&vec![0.1; n]).is_err());
        } else {
            assert!(parts.micro_action(&mut vec![0.01; n], ActionKind::Babbling).is_none());
        }
    }
}

#[test]
fn a_controller_of_the_wrong_paradigm_gets_an_error_not_a_panic() {
    for (episodic, calls_movement, says) in [(false, true, "Parts::movement was called in a run of the micro-action paradigm"), (true, false, "Parts::micro_action was called in a run of the episodic paradigm")] {
        let mut cfg = RunConfig { n_steps: 100, ..RunConfig::default() };
        cfg.eval.schedule = vec![0, 100];
        (cfg.eval.n_test_goals, cfg.eval.n_test_configs) = (5, 5);
        if episodic {
            cfg.paradigm = saggriac_core::config::Paradigm::Episodic;
        }
        let mut l = Learner::from_parts(cfg, 1, 1, UserParts { low_level: Some(Box::new(WrongParadigm { calls_movement })), ..UserParts::default() }).unwrap();
        // The run stops at once, nothing learnt, and says why.
        assert!(!l.run(&mut |_| true));
        assert_eq!(l.steps(), 0);
        let e = l.parts().misuse().expect("an error").to_string();
        assert!(e.contains(says), "{e}");
    }
}
