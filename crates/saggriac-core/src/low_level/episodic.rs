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

    /// One movement: propose, execute at once, store, tell.
    fn attempt(&mut self, choice: Option<GoalChoice>, parts: &mut Parts) {
        let n = parts.body().n_joints();
        let lim = self.joint_limit;
        let rest = parts.rest_position();
        let m = parts.model().task_dim();
        let mut theta = vec![0.0; n];
        let goal = match (&choice, self.condition.uses_goals()) {
            (Some(c), true) => Some(point(&c.goal[..m])),
            _ => None,
        };
        match (self.condition, &choice) {
            (Condition::ActuatorRandom, _) => theta.iter_mut().for_each(|t| *t = uniform(parts.rng(), -lim, lim)),
            (Condition::ActuatorRiac, Some(c)) => theta.copy_from_slice(&c.goal),
            (_, _) => {
                let g = goal.expect("a goal for the SAGG conditions");
                let t1 = std::time::Instant::now();
                // Before any movement the inverse model knows nothing: start from rest.
                // (No memory of movements: a run of the other paradigm, refused by `movement`.)
                if let Some(e) = parts.model().episodes() {
                    e.inverse(&g, &self.cfg, self.rcond, &mut self.nb, &mut theta);
                }
                parts.timers_mut().knn += t1.elapsed().as_secs_f64();
                let s = self.cfg.noise;
                if s > 0.0 {
                    theta.iter_mut().for_each(|t| *t += s * normal(parts.rng()));
                }
            }
        }
        theta.iter_mut().for_each(|t| *t = t.clamp(-lim, lim));
        // ACTUATOR-RIAC's interest: progress of the forward model's error on this movement.
        let predicted = if self.condition == Condition::ActuatorRiac { parts.model().episodes().and_then(|e| e.predict(&theta, &self.cfg, &mut self.nb)) } else { None };
        let step_start = parts.recorder().steps();
        let Ok(x) = parts.movement(&theta) else { return };
        let c = parts.counters_mut();
        c.babbling_steps += u64::from(goal.is_none());
        c.reaching_steps += u64::from(goal.is_some());
        match (goal, &choice) {
            (Some(g), Some(c)) => {
                let comp = competence_of(&self.competence, self.reach, &g, &x, &rest);
                let region = parts.tell(&g[..m], comp);
                parts.record_attempt(1, g, x, comp, region);
                parts.finish_goal(c, g, step_start, rest, x, comp);
            }
            (None, Some(_)) => {
                if let Some(p) = predicted {
                    let theta_now = parts.body().theta().to_vec();
                    parts.tell(&theta_now, -distance(&p, &x));
                }
            }
            _ => {}
        }
    }
}
