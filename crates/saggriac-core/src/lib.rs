//! saggriac-core: the SAGG-RIAC system of Baranes & Oudeyer (IROS 2010) in pure Rust.
//!
//! The modules follow the paper's concepts, each part owning its state (docs/architecture.md):
//! the configuration (a leaf), the body (the arm and its micro-actions), the sensorimotor model
//! (memory, neighbour index, local models), the low level (`LowLevel` and its controllers: the
//! SSA reacher, actuator babbling, the episodic paradigm), the high level (competence, interest,
//! region tree, goal selection), the evaluation, the recorder, and the run loop composing them.

pub mod arm;
pub mod ask_tell;
pub mod block_index;
pub mod body;
pub mod chain;
pub mod checkpoint;
pub mod chunked;
pub mod competence;
pub mod config;
pub mod episodic_memory;
pub mod error;
pub mod evaluation;
pub(crate) mod evaluation_pool;
pub mod goal_selection;
pub mod interest;
pub mod kd_tree;
pub mod local_model;
pub mod low_level;
pub mod memory;
pub(crate) mod micro_evaluation;
pub mod min_norm_ik;
pub mod neighbours;
pub mod parts;
pub mod reachable_cloud;
pub mod recorder;
pub mod region_tree;
pub mod rng;
pub mod run_loop;
pub mod sensorimotor_model;
pub mod task_space;
pub mod teachers;
pub mod test_set;

pub use config::{Condition, RunConfig};
pub use error::{Error, Result};
pub use run_loop::Learner;
