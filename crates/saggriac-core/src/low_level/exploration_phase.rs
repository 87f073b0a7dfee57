//! Exploration phase of the low level (paper III.D.2): q small random micro-actions around the
//! current configuration, so the local model learns (theta, dtheta) -> dx there.

pub use crate::config::low_level::ExplorationConfig;
use crate::parts::{ActionKind, Parts};
use crate::rng::uniform;

/// Run one exploration phase: q micro-actions, each moving to a random configuration in a small
/// box around the theta the phase started from. Staying around that centre (rather than a
/// drifting random walk) keeps the new samples where the local model must be good. Stops early
/// when the run's step budget is spent, or at `deadline` (a time step) if one is given. `d` is
/// the caller's command buffer.
pub fn explore(parts: &mut Parts, cfg: &ExplorationConfig, d: &mut [f64], deadline: Option<u64>) {
    let step = cfg.step;
    let centre = parts.body().theta().to_vec();
    for _ in 0..cfg.q {
        if deadline.is_some_and(|t| parts.recorder().steps() >= t) {
            return;
        }
        // (centre + u) - theta, in the order the sum was always taken.
        for (v, c) in d.iter_mut().zip(&centre) {
            *v = c + uniform(parts.rng(), -step, step);
        }
        for (v, t) in d.iter_mut().zip(parts.body().theta()) {
            *v -= t;
        }
        if parts.micro_action(d, ActionKind::Exploration).is_none() {
            return;
        }
    }
}
