//! The paper's low level (III.D), inspired by SSA. A goal is reached through l subgoals on the
//! line from the start; each is one attempt: from the current position, ask for a displacement of
//! length v towards the target, execute dtheta = J+ dx with J fitted on the nearest stored
//! samples, and run an exploration phase when the realised displacement misses (or no local
//! model exists yet), until the target is reached or the attempt times out. Each subgoal's
//! competence goes to the high level.

pub use crate::config::low_level::ReachingConfig;
use crate::config::low_level::{ExplorationConfig, ExplorationTrigger};
use crate::config::RunConfig;
use crate::high_level::competence::{clip, cost_of, CompetenceConfig};
use crate::high_level::goal_selection::GoalChoice;
use crate::low_level::exploration_phase::explore;
use crate::low_level::LowLevel;
use crate::parts::{ActionKind, Parts};
pub use crate::task_space::desired_step;
use crate::task_space::{distance, lerp, point, Point};

/// Result of one (sub)goal attempt.
#[derive(Debug, Clone, PartialEq)]
pub struct AttemptOutcome {
    pub start: Point,
    pub end: Point,
    pub competence: f64,
    pub reached: bool,
    /// The run's step budget ran out during the attempt: its competence is not a measurement.
    pub interrupted: bool,
}

pub struct SsaReacher {
    reaching: ReachingConfig,
    exploration: ExplorationConfig,
    competence: CompetenceConfig,
    /// The arm's length (the scale of the absolute competence).
    reach: f64,
    reset_every: u64,
    /// The command buffer of every micro-action.
    dtheta: Vec<f64>,
}

impl SsaReacher {
    pub fn new(cfg: &RunConfig) -> Self {
        let n = cfg.arm.link_lengths.len();
        SsaReacher {
            reaching: cfg.reaching,
            exploration: cfg.exploration,
            competence: cfg.competence,
            reach: cfg.arm.link_lengths.iter().sum(),
            reset_every: cfg.reset_every as u64,
            dtheta: vec![0.0; n],
        }
    }

    /// One attempt to reach `target` from where the body is.
    pub fn reach(&mut self, target: Point, parts: &mut Parts) -> AttemptOutcome {
        let (rc, comp) = (self.reaching, self.competence);
        let start = parts.body().position();
        let timeout = rc.timeout(distance(&target, &start)) as u64;
        let step0 = parts.recorder().steps();
        // Algorithm 1 checks the timeout between phases; the option also ends an exploration
        // phase at it.
        let deadline = rc.timeout_in_exploration.then_some(step0 + timeout);
        let mut interrupted = false;
        loop {
            let x = parts.body().position();
            if cost_of(&comp, self.reach, &target, &x, &start) > comp.eps_c {
                break;
            }
            if parts.recorder().steps() - step0 >= timeout {
                break;
            }
            if parts.budget_spent() || parts.failed() {
                interrupted = true;
                break;
            }
            let dx_des = desired_step(&x, &target, rc.v);
            match parts.inverse_here(&dx_des, &mut self.dtheta) {
                Ok(()) => match parts.micro_action(&mut self.dtheta, ActionKind::Reaching) {
                    None => {
                        interrupted = true;
                        break;
                    }
                    Some(dx) => {
                        // By default compare with what the model expected of the command actually
                        // executed, so a command cut by the joint-step bound or a joint limit is no
                        // fault of the model; `Desired` compares with the desired step, as printed.
                        // Both are counted, so a run measures how often they disagree.
                        let expected = parts.model().expected_dx(&self.dtheta);
                        let (on_executed, on_desired) = (distance(&dx, &expected) > rc.eps_max, distance(&dx, &dx_des) > rc.eps_max);
                        let counters = parts.counters_mut();
                        counters.trigger_only_executed += (on_executed && !on_desired) as u64;
                        counters.trigger_only_desired += (on_desired && !on_executed) as u64;
                        counters.trigger_gap_sum += distance(&expected, &dx_des);
                        let fire = match rc.trigger {
                            ExplorationTrigger::Executed => on_executed,
                            ExplorationTrigger::Desired => on_desired,
                        };
                        if fire {
                            parts.counters_mut().explorations += 1;
                            explore(parts, &self.exploration, &mut self.dtheta, deadline);
                        }
                    }
                },
                Err(_) => {
                    // No usable local model here yet: explore to build one.
                    let counters = parts.counters_mut();
                    counters.fit_failures += 1;
                    counters.explorations += 1;
                    explore(parts, &self.exploration, &mut self.dtheta, deadline);
                }
            }
        }
        let end = parts.body().position();
        let c = clip(cost_of(&comp, self.reach, &target, &end, &start), &comp);
        AttemptOutcome { start, end, competence: c, reached: c == 0.0, interrupted: interrupted && c != 0.0 }
    }
}

impl LowLevel for SsaReacher {
    fn rest_due(&self, parts: &Parts) -> bool {
        parts.recorder().goals_done() % self.reset_every == 0
    }
    fn asks_high_level(&self) -> bool {
        true
    }

    /// The goal through l subgoals x_i = x_start + (i / l)(x_g - x_start), the last one the goal
    /// itself; the high level gets each subgoal's competence.
    fn attempt(&mut self, choice: Option<GoalChoice>, parts: &mut Parts) {
        let choice = choice.expect("the SSA reacher reaches goals of the high level");
        let m = parts.model().task_dim();
        let g = point(&choice.goal[..m]);
        let start = parts.body().position();
        let step_start = parts.recorder().steps();
        let l = self.reaching.n_subgoals;
        let mut last_c = f64::NAN;
        for i in 1..=l {
            let f = i as f64 / l as f64;
            let target = if i == l { g } else { lerp(&start, &g, f) };
            let out = self.reach(target, parts);
            if out.interrupted {
                break;
            }
            let region = parts.tell(&target[..m], out.competence);
            parts.record_attempt(i as u32, target, out.end, out.competence, region);
            if i == l {
                last_c = out.competence;
            }
        }
        let end = parts.body().position();
        parts.finish_goal(&choice, g, step_start, start, end, last_c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timeout_grows_with_distance() {
        let rc = ReachingConfig::default();
        assert_eq!(rc.timeout(0.0), 10);
        assert_eq!(rc.timeout(5.0), 30);
    }
}
