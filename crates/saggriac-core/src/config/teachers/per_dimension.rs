//! Expert knowledge per dimension: a teacher's parameters given one value for each dimension of
//! the box (a start region thin in one parameter and wide in another, as TeachMyAgent takes it),
//! or as a d x d matrix (SPDL's covariances). They sit beside the teacher's parameter struct,
//! which stays `Copy`, of fixed size and one number per parameter; `TeacherSpec` carries both,
//! and a value given per dimension takes the place of that number.

use serde::{Deserialize, Serialize};

use crate::config::teachers::TeacherParams;
use crate::error::{invalid, Error, Num, Result};

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
    /// `d` dimensions, finite, and each value of a vector meets the parameter's own rule (the
    /// one its single number meets). A matrix's own rules are its teacher's.
    pub fn check<P: TeacherParams>(&self, params: &P, d: usize) -> Result<()> {
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
            let (want, what, finite) = match shape {
                Shape::Vector => (d, format!("a float, or a list of {d} floats (one per dimension of the box)"), format!("a float, or a list of {d} finite floats (one per dimension of the box)")),
                Shape::Matrix => (
                    d * d,
                    format!("a {d} x {d} matrix (one row and one column per dimension of the box)"),
                    format!("a {d} x {d} matrix of finite floats (one row and one column per dimension of the box)"),
                ),
            };
            if values.len() != want {
                let cols = if shape == Shape::Matrix { (values.len() as f64).sqrt().round().max(1.0) as usize } else { values.len() };
                return Err(invalid(P::CLASS, name, what, format!("{} ({} values)", Self::show(values, cols), values.len())));
            }
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(invalid(P::CLASS, name, finite, format!("{} ({} at {})", Self::show(values, d), Num(values[i]), place(shape, i, d))));
            }
            if shape == Shape::Vector {
                for (i, v) in values.iter().enumerate() {
                    let Some(one) = with_value(params, name, *v) else { continue };
                    match one.validate() {
                        Err(Error::InvalidParameter { param, rule, .. }) if param == *name => {
                            return Err(invalid(P::CLASS, name, format!("{rule}, or a list of such floats, one per dimension"), format!("{} ({} in dimension {i})", Self::show(values, d), Num(*v))));
                        }
                        Err(other) => return Err(other),
                        Ok(()) => {}
                    }
                }
            }
        }
        Ok(())
    }
}

/// `params` with its float `name` set to `v` (serde's names), None if it has no such float.
fn with_value<P: TeacherParams>(params: &P, name: &str, v: f64) -> Option<P> {
    let mut json = serde_json::to_value(params).ok()?;
    let field = json.get_mut(name)?;
    if !field.is_f64() {
        return None;
    }
    *field = serde_json::Value::from(v);
    serde_json::from_value(json).ok()
}

/// "dimension i" of a vector, "row r, column c" of a matrix.
fn place(shape: Shape, i: usize, d: usize) -> String {
    match shape {
        Shape::Vector => format!("dimension {i}"),
        Shape::Matrix => format!("row {}, column {}", i / d.max(1), i % d.max(1)),
    }
}
