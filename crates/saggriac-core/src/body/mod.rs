//! What the learner acts on: the built-in arm (planar or spatial), or a user's environment (the Python
//! binding wraps one). The run loop, the exploration phase and the evaluation only see this
//! trait.

pub mod arm;
pub mod chain;

use crate::body::arm::{Arm, ArmState};
use crate::task_space::Point;

pub trait Body: Send + Sync {
    fn n_joints(&self) -> usize;
    fn theta(&self) -> &[f64];
    /// Dimension of the task space (1 to `MAX_TASK_DIM`).
    fn task_dim(&self) -> usize;
    /// End-effector position in the task space (coordinates past `task_dim` are 0).
    fn position(&self) -> Point;
    /// Back to the rest pose. Not a time step.
    fn reset(&mut self);
    /// Put the body in a configuration at once: a whole movement in the episodic paradigm, a
    /// placement during evaluation.
    fn set_theta(&mut self, theta: &[f64]);
    /// The noise-free position of a configuration, if the body knows its kinematics (the
    /// built-in arms do); None makes callers place the body and read its position instead.
    fn forward(&self, _theta: &[f64]) -> Option<Point> {
        None
    }
    /// The Jacobian of `forward` at `theta` (task_dim x n_joints, row-major, into `out`) if the
    /// body has it in closed form; false makes callers use finite differences.
    fn jacobian(&self, _theta: &[f64], _out: &mut [f64]) -> bool {
        false
    }
    /// One micro-action: writes the realised joint change into `dtheta`, returns the realised dx.
    fn step(&mut self, dtheta: &mut [f64]) -> Point;
    /// An independent copy for the evaluation's test reaches, if the body can make one. Without
    /// it the evaluation runs on this body and puts it back where it was.
    fn scratch(&self) -> Option<Box<dyn Body>> {
        None
    }
    /// Whether `reset` brings the body back to a state that does not depend on what it did
    /// before (no noise generator running on, say). Then evaluations can run on copies of it
    /// on other threads, with the same results.
    fn forgets_on_reset(&self) -> bool {
        false
    }
    /// Change one link's length during a run (re-adaptation studies). False if the body cannot.
    fn set_link_length(&mut self, _link: usize, _length: f64) -> bool {
        false
    }
    /// The body's state for a checkpoint (None: this body cannot be checkpointed).
    fn save(&self) -> Option<ArmState> {
        None
    }
    fn load(&mut self, _state: &ArmState) -> bool {
        false
    }
    /// True once the body has failed (a user's environment raised or returned bad values); the
    /// run loop stops at the next step.
    fn failed(&self) -> bool {
        false
    }
}

impl Body for Arm {
    fn n_joints(&self) -> usize {
        Arm::n_joints(self)
    }
    fn theta(&self) -> &[f64] {
        Arm::theta(self)
    }
    fn task_dim(&self) -> usize {
        Arm::task_dim(self)
    }
    fn position(&self) -> Point {
        Arm::position(self)
    }
    fn reset(&mut self) {
        Arm::reset(self)
    }
    fn set_theta(&mut self, theta: &[f64]) {
        Arm::set_theta(self, theta)
    }
    fn forward(&self, theta: &[f64]) -> Option<Point> {
        // Within the limits, as a placement would be.
        let lim = self.config().joint_limit;
        if theta.iter().all(|t| t.abs() <= lim) {
            return Some(Arm::forward(self, theta));
        }
        let clipped: Vec<f64> = theta.iter().map(|t| t.clamp(-lim, lim)).collect();
        Some(Arm::forward(self, &clipped))
    }
    fn jacobian(&self, theta: &[f64], out: &mut [f64]) -> bool {
        // Only inside the limits, where placements do not clip.
        let lim = self.config().joint_limit;
        theta.iter().all(|t| t.abs() < lim) && Arm::jacobian(self, theta, out)
    }
    fn step(&mut self, dtheta: &mut [f64]) -> Point {
        Arm::step(self, dtheta)
    }
    fn scratch(&self) -> Option<Box<dyn Body>> {
        Some(Box::new(self.clone()))
    }
    fn forgets_on_reset(&self) -> bool {
        // Noise draws advance the arm's generator: the next evaluation depends on this one's.
        self.config().motor_noise == 0.0 && self.config().sensor_noise == 0.0
    }
    fn set_link_length(&mut self, link: usize, length: f64) -> bool {
        if self.config().kind == crate::body::arm::ArmKind::Chain {
            return false;
        }
        Arm::set_link_length(self, link, length);
        true
    }
    fn save(&self) -> Option<ArmState> {
        Some(Arm::save(self))
    }
    fn load(&mut self, state: &ArmState) -> bool {
        Arm::load(self, state)
    }
}
