//! What the task-list teachers (discrete LP, PLR, TSCL) share: their goals are task indices,
//! given as one-coordinate points.

use crate::error::{Error, Num, Result};

/// The task a goal names: a whole number in [0, n).
pub fn task_of(goal: &[f64], n: usize) -> Option<usize> {
    let g = goal[0];
    (g.fract() == 0.0 && g >= 0.0 && g < n as f64).then_some(g as usize)
}

/// `task_of`, or the error that names the rule.
pub fn check_task(goal: &[f64], n: usize) -> Result<usize> {
    task_of(goal, n).ok_or_else(|| Error::InvalidInput(format!("goal must be a task index, a whole number in [0, {n}); got {}.", Num(goal[0]))))
}
