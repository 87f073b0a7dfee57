//! What the learner acts on: the built-in arm (planar, spatial or a chain; `arm.rs`, which
//! implements `Body` for it), or a user's environment (the Python binding wraps one). The run loop, the exploration phase and the evaluation only see this
//! trait.

pub mod arm;
pub mod chain;
pub mod params;

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
    /// `forward` at `theta` with joint i set to `values[i]`, for every joint i, into `out[i]`,
    /// each with the bits `forward` gives it (a finite-difference Jacobian's positions, cheaper
    /// together); false if the body cannot, and then nothing is written.
    fn forward_moved(&self, _theta: &[f64], _values: &[f64], _out: &mut [Point]) -> bool {
        false
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
    /// The body's state for a checkpoint, in the body's own encoding (None: this body cannot
    /// be checkpointed).
    fn save(&self) -> Option<Vec<u8>> {
        None
    }
    /// Put back the state `save` gave; false if the bytes are not this kind of body's.
    fn load(&mut self, _state: &[u8]) -> bool {
        false
    }
    /// True once the body has failed (a user's environment raised or returned bad values); the
    /// run loop stops at the next step.
    fn failed(&self) -> bool {
        false
    }
}
