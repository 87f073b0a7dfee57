//! Expert knowledge per dimension: a teacher's parameters given one value for each dimension of
//! the box (a start region thin in one parameter and wide in another, as TeachMyAgent takes it),
//! or as a d x d matrix (SPDL's covariances). They sit beside the teacher's parameter struct,
//! which stays `Copy`, of fixed size and one number per parameter; `TeacherSpec` carries both,
//! and a value given per dimension takes the place of that number.

use serde::{Deserialize, Serialize};

use crate::config::rules::{rule_of, Rule};
use crate::config::teachers::TeacherParams;
use crate::error::{invalid, Num, Result};

/// How a parameter is taken per dimension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// One float per dimension, in place of the parameter's single number (same rule for each).
    Vector,
    /// A d x d matrix, row by row, beside the numbers (no single-number form).
    Matrix,
}

/// The parameters given per dimension: (name, values) in the order given, a matrix row by row.
/// Empty: every parameter is its single number.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PerDimension(pub Vec<(String, Vec<f64>)>);

impl PerDimension {
    /// Values as a message prints them: a list, or rows of `cols` values for a matrix.
    pub fn show(values: &[f64], cols: usize) -> String {
        let row = |r: &[f64]| format!("[{}]", r.iter().map(|v| Num(*v).to_string()).collect::<Vec<_>>().join(", "));
        if cols == 0 || values.len() <= cols {
            return row(values);
        }
        format!("[{}]", values.chunks(cols).map(row).collect::<Vec<_>>().join(", "))
    }

    /// The rule of a matrix over `d` dimensions, as a message states it (its teacher's own
    /// rules, such as a covariance's, come after).
    pub fn matrix_rule(d: usize) -> String {
        format!("a {d} x {d} matrix of finite floats: {d} rows of {d} (one row and one column per dimension of the box)")
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The values given for `name`, if any.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice())
    }

    /// The vector `name` over `d` dimensions: the values given, else `single` in each.
    pub fn vector(&self, name: &str, single: f64, d: usize) -> Vec<f64> {
        self.get(name).map_or_else(|| vec![single; d], <[f64]>::to_vec)
    }

    /// Each value's name is one the teacher takes per dimension, given once, of its shape over
    /// `d` dimensions; each value of a vector meets the single number's rule (`RULES`, one
    /// message per bad value: the parameter, the values, the one that breaks the rule and the
    /// rule); a matrix's values are finite (its own rules are its teacher's).
    pub fn check<P: TeacherParams>(&self, d: usize) -> Result<()> {
        let taken: Vec<&str> = P::PER_DIMENSION.iter().map(|(n, _)| *n).collect();
        for (k, (name, values)) in self.0.iter().enumerate() {
            let Some(&(_, shape)) = P::PER_DIMENSION.iter().find(|(n, _)| n == name) else {
                let rule =
                    if taken.is_empty() { "one number (this teacher takes none per dimension)".to_string() } else { format!("one number (only {} take a value per dimension)", taken.join(", ")) };
                return Err(invalid(P::CLASS, name, rule, Self::show(values, values.len())));
            };
            if self.0[..k].iter().any(|(n, _)| n == name) {
                return Err(invalid(P::CLASS, name, "given once", Self::show(values, d.max(1))));
            }
            match shape {
                Shape::Vector => check_vector(P::CLASS, name, rule_of(P::RULES, name).unwrap_or(Rule::Finite), values, d)?,
                Shape::Matrix => {
                    if values.len() != d * d {
                        let cols = (values.len() as f64).sqrt().round().max(1.0) as usize;
                        return Err(invalid(P::CLASS, name, Self::matrix_rule(d), format!("{} ({} values)", Self::show(values, cols), values.len())));
                    }
                    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                        let at = format!("{} ({} at row {}, column {})", Self::show(values, d), Num(values[i]), i / d.max(1), i % d.max(1));
                        return Err(invalid(P::CLASS, name, Self::matrix_rule(d), at));
                    }
                }
            }
        }
        Ok(())
    }
}

/// The values of the vector `name` against its length `d` and, each, the single number's
/// `rule`: refused with the rule as a list states it (`Rule::per_dimension_text`).
fn check_vector(owner: &'static str, name: &str, rule: Rule, values: &[f64], d: usize) -> Result<()> {
    let shown = PerDimension::show(values, values.len());
    if values.len() != d {
        let n = values.len();
        return Err(invalid(owner, name, rule.per_dimension_text(), format!("{shown} ({n} value{} for a box of {d} dimension{})", plural(n), plural(d))));
    }
    match values.iter().enumerate().find(|(_, v)| !rule.holds_float(**v)) {
        Some((i, v)) => Err(invalid(owner, name, rule.per_dimension_text(), format!("{shown} ({} in dimension {i})", Num(*v)))),
        None => Ok(()),
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}
