//! Wall time spent in each part of a run, in seconds (run.json's split). A leaf: the model and
//! the controllers add to it without reaching up into the recorder that keeps it.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Timers {
    pub knn: f64,
    pub fit: f64,
    pub goal_selection: f64,
    pub evaluation: f64,
    pub total: f64,
}
