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

/// A float as a message prints it: as Rust's `Display` for ordinary magnitudes (0.5, 50, 1e-3 as
/// 0.001), in exponent form beyond them (1e300, not a 301-digit integer; 1e-300, not 300 zeros).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if self.0.is_finite() && a != 0.0 && !(1e-5..1e16).contains(&a) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

/// A float to six significant digits, as C's `%g` prints it (1.5708, 50, 1e300): for the
/// numbers a rule quotes as context (a limit, a reach), where the last digits are noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct G(pub f64);

impl std::fmt::Display for G {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let rounded = if self.0.is_finite() { format!("{:.5e}", self.0).parse().unwrap_or(self.0) } else { self.0 };
        write!(f, "{}", Num(rounded))
    }
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
            Err(invalid(self.owner, name, "a finite float > 0", Num(v)))
        }
    }
    pub fn non_negative(&self, name: &str, v: f64) -> Result<()> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(invalid(self.owner, name, "a finite float >= 0", Num(v)))
        }
    }
    pub fn in_open_closed(&self, name: &str, v: f64, lo: f64, hi: f64) -> Result<()> {
        if v.is_finite() && v > lo && v <= hi {
            Ok(())
        } else {
            Err(invalid(self.owner, name, format!("a float in ({}, {}]", Num(lo), Num(hi)), Num(v)))
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

#[cfg(test)]
mod tests {
    use super::Num;

    #[test]
    fn numbers_print_short() {
        assert_eq!(Num(1e300).to_string(), "1e300");
        assert_eq!(Num(-2.5e-300).to_string(), "-2.5e-300");
        assert_eq!(Num(50.0).to_string(), "50");
        assert_eq!(Num(0.001).to_string(), "0.001");
        assert_eq!(Num(f64::NAN).to_string(), "NaN");
        assert_eq!(Num(f64::INFINITY).to_string(), "inf");
        assert_eq!(super::G(9.999999999999998).to_string(), "10");
        assert_eq!(super::G(std::f64::consts::FRAC_PI_2).to_string(), "1.5708");
        assert_eq!(super::G(-1.234567e-300).to_string(), "-1.23457e-300");
    }
}
