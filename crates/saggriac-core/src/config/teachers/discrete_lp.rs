//! The discrete learning-progress teacher's parameters (Kanitscheider et al., 2021).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, TeacherParams};
use crate::config::rules::{check_fields, open_closed, COUNT, Rule};
use crate::error::Result;

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

    const RULES: &'static [(&'static str, Rule)] = &[
        ("n_tasks", COUNT),
        ("alpha", open_closed(0.0, 1.0)),
        // 0.5 makes r the identity; 0 and 1 make it constant.
        ("theta", Rule::Float { lo: 0.0, lo_in: false, hi: 1.0, hi_in: false, note: "" }),
    ];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, int n_tasks, float alpha, float theta);
        Ok(())
    }
}
