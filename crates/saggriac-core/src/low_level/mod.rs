//! The low level: how the learner acts to learn. One trait, `LowLevel`, and its controllers:
//! the SSA reacher of the paper (reaching phase, exploration phase, timeout), actuator babbling
//! (the ACTUATOR baselines) and the episodic paradigm. The run loop asks a controller whether
//! the body goes back to rest and whether it wants a choice of the high level, then lets it make
//! one attempt through the learner's `Parts`.
//!
//! Adding a controller: a new file here implementing `LowLevel`, and one line in
//! `run_loop::low_level_for`, where conditions map to controllers (see docs/architecture.md).

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
    /// One attempt: act through `parts` (micro-actions or a movement), record its rows, and tell
    /// the high level what was measured. `choice` is Some exactly when `asks_high_level`.
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
