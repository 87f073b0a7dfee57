//! The episodic paradigm (explauto, IMGEP): one goal, one whole joint configuration proposed by
//! the inverse model, executed at once, one sample (theta, x). The inverse model is the nearest
//! neighbour of the goal among the reached positions, plus Gaussian exploration noise, and
//! optionally a first-order correction (see `episodic_memory.rs`). One time step is one
//! movement. ACTUATOR-Random draws configurations uniformly; ACTUATOR-RIAC takes them from the
//! region tree over theta, the interest being the forward model's error. The goal selectors and
//! the evaluation's test sets are the same as for micro-actions.

pub use crate::config::low_level::EpisodicConfig;
use crate::config::{Condition, RunConfig};
use crate::high_level::competence::{competence_of, CompetenceConfig};
use crate::high_level::goal_selection::GoalChoice;
use crate::low_level::LowLevel;
use crate::model::neighbours::Neighbour;
use crate::parts::Parts;
use crate::recorder::{AttemptRow, GoalRow};
use crate::rng::{normal, uniform};
use crate::task_space::{distance, point};

pub struct Episodic {
    condition: Condition,
    cfg: EpisodicConfig,
    competence: CompetenceConfig,
    /// The arm's length (the scale of the absolute competence).
    reach: f64,
    joint_limit: f64,
    rcond: f64,
    /// Neighbour scratch of the inverse and forward models.
    nb: Vec<Neighbour>,
}

impl Episodic {
    pub fn new(cfg: &RunConfig) -> Self {
        Episodic {
            condition: cfg.condition,
            cfg: cfg.episodic,
            competence: cfg.competence,
            reach: cfg.arm.link_lengths.iter().sum(),
            joint_limit: cfg.arm.joint_limit,
            rcond: cfg.local.pinv_rcond,
            nb: Vec::new(),
        }
    }
}

impl LowLevel for Episodic {
    fn asks_high_level(&self) -> bool {
        self.condition != Condition::ActuatorRandom
    }
    fn attempts_per_report(&self) -> usize {
        64
    }

    /// One movement: propose, execute at once, store, tell, evaluate if due.
    fn attempt(&mut self, choice: Option<GoalChoice>, parts: &mut Parts) {
        let n = parts.body.n_joints();
        let lim = self.joint_limit;
        let rest = parts.rest_position();
        let m = parts.model.task_dim();
        let mut theta = vec![0.0; n];
        let goal = match (&choice, self.condition.uses_goals()) {
            (Some(c), true) => Some(point(&c.goal[..m])),
            _ => None,
        };
        let mem = parts.model.episodes().expect("the episodic paradigm's model holds movements");
        match (self.condition, &choice) {
            (Condition::ActuatorRandom, _) => theta.iter_mut().for_each(|t| *t = uniform(&mut parts.rng, -lim, lim)),
            (Condition::ActuatorRiac, Some(c)) => theta.copy_from_slice(&c.goal),
            (_, _) => {
                let g = goal.expect("a goal for the SAGG conditions");
                let t1 = std::time::Instant::now();
                // Before any movement the inverse model knows nothing: start from rest.
                mem.inverse(&g, &self.cfg, self.rcond, &mut self.nb, &mut theta);
                parts.recorder.timers.knn += t1.elapsed().as_secs_f64();
                let s = self.cfg.noise;
                if s > 0.0 {
                    theta.iter_mut().for_each(|t| *t += s * normal(&mut parts.rng));
                }
            }
        }
        theta.iter_mut().for_each(|t| *t = t.clamp(-lim, lim));
        // ACTUATOR-RIAC's interest: progress of the forward model's error on this movement.
        let predicted = if self.condition == Condition::ActuatorRiac { mem.predict(&theta, &self.cfg, &mut self.nb) } else { None };
        let step_start = parts.recorder.steps();
        let x = parts.movement(&theta);
        let r = &mut parts.recorder;
        r.counters.babbling_steps += u64::from(goal.is_none());
        r.counters.reaching_steps += u64::from(goal.is_some());
        match (goal, &choice) {
            (Some(g), Some(c)) => {
                let comp = competence_of(&self.competence, self.reach, &g, &x, &rest);
                let region = parts.tell(&g[..m], comp);
                let r = &mut parts.recorder;
                r.attempts.push(AttemptRow { goal_index: r.goals_done(), subgoal: 1, step_end: r.steps(), target: g, end: x, competence: comp, reached: comp == 0.0, region });
                r.goal_done(GoalRow { goal_index: r.goals_done(), step_start, step_end: r.steps(), goal: g, start: rest, end: x, mode: c.mode, region: c.region, competence: comp });
            }
            (None, Some(_)) => {
                if let Some(p) = predicted {
                    let theta_now = parts.body.theta().to_vec();
                    parts.tell(&theta_now, -distance(&p, &x));
                }
            }
            _ => {}
        }
        parts.evaluate_due();
    }
}
