//! The low level: how the learner acts to learn. One trait, `LowLevel`, and its controllers:
//! the SSA reacher of the paper (reaching phase, exploration phase, timeout), actuator babbling
//! (the ACTUATOR baselines) and the episodic paradigm. The run loop asks a controller whether
//! the body goes back to rest and whether it wants a choice of the high level, then lets it make
//! one attempt through the learner's `Parts`.
//!
//! Adding a controller: a new file here implementing `LowLevel`, and one line in
//! `assembly::low_level_for`, where conditions map to controllers (see docs/architecture.md).

pub mod actuator_babbling;
pub mod episodic;
pub mod exploration_phase;
pub mod ssa_reacher;

use crate::high_level::goal_selection::GoalChoice;
use crate::parts::Parts;

pub trait LowLevel: Send + Sync {
    /// Whether the body goes back to rest before the next attempt (paper: every r goals).
    fn rest_due(&self, _parts: &Parts) -> bool {
        false
    }
    /// Whether the next attempt starts from a choice of the high level (`GoalSelector::sample`).
    fn asks_high_level(&self) -> bool;
    /// One attempt. `choice` is Some exactly when `asks_high_level`. The contract:
    /// - act only through `parts`: `micro_action` (one time step; an evaluation due at that step
    ///   runs inside it) or `movement` (one time step; an evaluation due runs when the attempt
    ///   returns), reading the body and the model, drawing from `parts.rng()`;
    /// - give every measurement to the high level with `parts.tell` and record it with
    ///   `parts.record_attempt`;
    /// - for a goal of the high level, end with `parts.finish_goal` (the next goal's index);
    /// - stop acting once `micro_action` returns None (the budget is spent or a user's part failed).
    fn attempt(&mut self, choice: Option<GoalChoice>, parts: &mut Parts);
    /// Attempts between two reports of new evaluations to the caller of `run` (where a run can
    /// stop, and be checkpointed).
    fn attempts_per_report(&self) -> usize {
        1
    }
    /// The controller's own progress, for a checkpoint (ACTUATOR: micro-actions so far).
    fn saved_progress(&self) -> u64 {
        0
    }
    fn restore_progress(&mut self, _progress: u64) {}
}
