//! Goals uniform in the box (SAGG-Random): no parameter.

use serde::{Deserialize, Serialize};

use crate::config::teachers::TeacherParams;
use crate::config::rules::Rule;
use crate::error::Result;

/// Goals uniform in the box: no parameter.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RandomConfig {}

impl TeacherParams for RandomConfig {
    const RULES: &'static [(&'static str, Rule)] = &[];

    fn validate(&self) -> Result<()> {
        Ok(())
    }
}
