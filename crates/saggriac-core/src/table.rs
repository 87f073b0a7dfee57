//! Tables as named columns: the one shape in which the recorder's rows, the region tree and
//! run.json's profile leave the core. Each column is named once, beside the rows it reads; the
//! binding turns a column into one numpy array and a one-row table into a dict of scalars
//! without naming any column itself.

use crate::task_space::Point;

/// One column of a table.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// Counts and indices: signed, so that a user's difference of two steps never wraps around
    /// (pandas, polars and Parquet read them as int64). -1 stands for "none".
    Int(Vec<i64>),
    Float(Vec<f64>),
    Bool(Vec<bool>),
    /// One point of `width` coordinates per row, row after row.
    Points { width: usize, values: Vec<f64> },
}

/// Named columns of equal length, in the order a user sees them.
pub type Table = Vec<(&'static str, Column)>;

/// One number of a record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    Count(u64),
    Float(f64),
}

/// Named numbers: a single row that is not part of a table (run.json's profile).
pub type Record = Vec<(&'static str, Number)>;

impl Column {
    pub fn len(&self) -> usize {
        match self {
            Column::Int(v) => v.len(),
            Column::Float(v) => v.len(),
            Column::Bool(v) => v.len(),
            Column::Points { width, values } => values.len().checked_div(*width).unwrap_or(0),
        }
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

pub(crate) fn ints<R>(rows: &[R], f: impl Fn(&R) -> i64) -> Column {
    Column::Int(rows.iter().map(f).collect())
}

pub(crate) fn floats<R>(rows: &[R], f: impl Fn(&R) -> f64) -> Column {
    Column::Float(rows.iter().map(f).collect())
}

pub(crate) fn bools<R>(rows: &[R], f: impl Fn(&R) -> bool) -> Column {
    Column::Bool(rows.iter().map(f).collect())
}

/// The first `width` coordinates of each row's point.
pub(crate) fn points<R>(rows: &[R], width: usize, f: impl Fn(&R) -> &Point) -> Column {
    Column::Points { width, values: rows.iter().flat_map(|r| f(r)[..width].iter().copied()).collect() }
}

/// Rows whose points are slices of `width` numbers (a region's bounds).
pub(crate) fn slices<R>(rows: &[R], width: usize, f: impl Fn(&R) -> &[f64]) -> Column {
    Column::Points { width, values: rows.iter().flat_map(|r| f(r).iter().copied()).collect() }
}

/// An optional index, -1 for none.
pub(crate) fn index_or_none(i: Option<usize>) -> i64 {
    i.map_or(-1, |x| x as i64)
}
