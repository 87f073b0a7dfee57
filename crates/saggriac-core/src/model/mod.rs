//! The sensorimotor model (paper III.B): the memory of what was done and what happened
//! (`memory`, stored in chunks, `chunked`), its exact nearest-neighbour index (`neighbours`,
//! `block_index`, their distance kernels in `block_distances`; the k-d tree `kd_tree` indexes the
//! episodic memory's movements and ALP-GMM's history), the local linear models fitted to the neighbours (`local_model`, its kernels in `gram`), one query of the inverse model through them (`local_query`,
//! shared by the learner and the evaluator), the episodic paradigm's memory of whole movements
//! (`episodic_memory`), and the model the learner and the evaluator use through them
//! (`sensorimotor_model`).

pub(crate) mod block_distances;
pub mod block_index;
pub mod chunked;
pub mod episodic_memory;
pub(crate) mod gram;
pub mod kd_tree;
pub mod local_model;
pub mod local_query;
pub mod memory;
pub mod neighbours;
pub mod sensorimotor_model;
