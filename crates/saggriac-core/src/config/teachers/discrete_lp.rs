//! The discrete learning-progress teacher's parameters (Kanitscheider et al., 2021).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, TeacherParams};
use crate::error::{invalid, Check, Num, Result, MAX_COUNT};

/// Parameters of the discrete learning-progress teacher.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DiscreteLpConfig {
    pub n_tasks: usize,
    /// Step of both moving averages (the paper's and Syllabus's 0.1).
    pub alpha: f64,
    /// theta of the reweighting (0.1 in the paper); 0.5 makes r the identity.
    pub theta: f64,
}

impl Default for DiscreteLpConfig {
    /// The paper's alpha and theta; `n_tasks` has no default worth the name (the Python class
    /// requires it), 1 is the least valid.
    fn default() -> Self {
        DiscreteLpConfig { n_tasks: 1, alpha: 0.1, theta: 0.1 }
    }
}

impl TeacherParams for DiscreteLpConfig {
    const HAS_BOX: bool = false;

    fn validate(&self) -> Result<()> {
        let c = Check { owner: Self::CLASS };
        c.within("n_tasks", self.n_tasks, 1, MAX_COUNT)?;
        c.in_open_closed("alpha", self.alpha, 0.0, 1.0)?;
        if !(self.theta.is_finite() && self.theta > 0.0 && self.theta < 1.0) {
            return Err(invalid(Self::CLASS, "theta", "a float in (0, 1)", Num(self.theta)));
        }
        Ok(())
    }
}
