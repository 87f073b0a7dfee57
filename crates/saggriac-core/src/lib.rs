//! saggriac-core: the SAGG-RIAC system of Baranes & Oudeyer (IROS 2010) in pure Rust.
//!
//! The modules follow the paper's concepts: the arm and its micro-actions, the sensorimotor
//! memory and neighbour index, local models, the reaching controller and exploration phase (low
//! level), competence, interest, the region tree and goal selection (high level), the evaluation,
//! and the run loop tying them together.

pub mod actuator_babbling;
pub mod arm;
pub mod ask_tell;
pub mod block_index;
pub mod body;
pub mod checkpoint;
pub mod competence;
pub mod config;
pub mod episodic;
pub mod error;
pub mod evaluation;
pub mod exploration_phase;
pub mod goal_selection;
pub mod interest;
pub mod kd_tree;
pub mod local_model;
pub mod memory;
pub mod neighbours;
pub mod reaching_controller;
pub mod region_tree;
pub mod rng;
pub mod run_loop;
pub mod task_space;

pub use config::{Condition, RunConfig};
pub use error::{Error, Result};
pub use run_loop::Learner;
