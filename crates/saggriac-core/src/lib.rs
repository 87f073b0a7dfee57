//! saggriac-core: the SAGG-RIAC system of Baranes & Oudeyer (IROS 2010) in pure Rust.
//!
//! The modules follow the paper's concepts, each part owning its state (docs/architecture.md):
//! the configuration (a leaf), the body (the arm and its micro-actions), the sensorimotor model
//! (memory, neighbour index, local models), the low level (`LowLevel` and its controllers: the
//! SSA reacher, actuator babbling, the episodic paradigm), the high level (competence, interest,
//! region tree, goal selection), the evaluation, the recorder, and the run loop composing them.

pub mod assembly;
pub mod body;
pub mod checkpoint;
pub mod config;
pub mod error;
pub mod evaluation;
pub mod high_level;
pub mod low_level;
pub mod model;
pub mod parts;
pub mod recorder;
pub mod rng;
pub mod run_loop;
pub mod table;
pub mod task_space;
pub mod timers;

pub use config::{Condition, RunConfig};
pub use error::{Error, Result};
pub use run_loop::Learner;
