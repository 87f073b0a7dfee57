//! One error type for the whole core; the binding maps each variant to a Python exception.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A parameter broke a rule. The message follows scikit-learn's template so that users see
    /// the same wording from the CLI, a TOML file and the Python API.
    #[error("The '{param}' parameter of {owner} must be {rule}. Got {value} instead.")]
    InvalidParameter { owner: &'static str, param: String, rule: String, value: String },
    /// Input data (a point, a goal, a competence) that cannot be used as given.
    #[error("{0}")]
    InvalidInput(String),
}

pub type Result<T> = std::result::Result<T, Error>;

/// Build an `InvalidParameter` error.
pub fn invalid(owner: &'static str, param: &str, rule: impl Into<String>, value: impl std::fmt::Display) -> Error {
    Error::InvalidParameter { owner, param: param.to_string(), rule: rule.into(), value: value.to_string() }
}

/// Check helpers used by every `validate()`: each returns the error with the template filled in.
pub(crate) struct Check {
    pub owner: &'static str,
}

/// The largest count a user may give for anything the core allocates per unit (a window, a
/// region's measurements, tasks, candidate cuts, mixture sizes): beyond it a value is refused up
/// front rather than left to exhaust memory or time.
pub const MAX_COUNT: usize = 1_000_000;

impl Check {
    pub fn positive(&self, name: &str, v: f64) -> Result<()> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(invalid(self.owner, name, "a finite float > 0", v))
        }
    }
    pub fn non_negative(&self, name: &str, v: f64) -> Result<()> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(invalid(self.owner, name, "a finite float >= 0", v))
        }
    }
    pub fn in_open_closed(&self, name: &str, v: f64, lo: f64, hi: f64) -> Result<()> {
        if v.is_finite() && v > lo && v <= hi {
            Ok(())
        } else {
            Err(invalid(self.owner, name, format!("a float in ({lo}, {hi}]"), v))
        }
    }
    pub fn probability(&self, name: &str, v: f64) -> Result<()> {
        if v.is_finite() && (0.0..=1.0).contains(&v) {
            Ok(())
        } else {
            Err(invalid(self.owner, name, "a float in [0, 1]", v))
        }
    }
    /// An int in [min, max].
    pub fn within(&self, name: &str, v: usize, min: usize, max: usize) -> Result<()> {
        if (min..=max).contains(&v) {
            Ok(())
        } else {
            Err(invalid(self.owner, name, format!("an int in [{min}, {max}]"), v))
        }
    }

    pub fn at_least(&self, name: &str, v: usize, min: usize) -> Result<()> {
        if v >= min {
            Ok(())
        } else {
            Err(invalid(self.owner, name, format!("an int >= {min}"), v))
        }
    }
}
