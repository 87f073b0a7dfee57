//! The core's tables and records as Python dicts of numpy arrays. No column is named here: the
//! core names each beside its rows (saggriac_core::recorder).

use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::table::{Column, Number, Record, Table};
use saggriac_core::task_space::Point;

/// Task-space points as an (n, m) array: the first m coordinates of each.
pub fn xy<'py>(py: Python<'py>, v: Vec<Point>, m: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = v.len();
    let flat: Vec<f64> = v.into_iter().flat_map(|p| p.into_iter().take(m)).collect();
    flat.into_pyarray(py).reshape([n, m])
}

fn array<'py>(py: Python<'py>, c: Column) -> PyResult<Bound<'py, PyAny>> {
    let n = c.len();
    Ok(match c {
        Column::Int(v) => v.into_pyarray(py).into_any(),
        Column::Float(v) => v.into_pyarray(py).into_any(),
        Column::Bool(v) => v.into_pyarray(py).into_any(),
        Column::Points { width, values } => values.into_pyarray(py).reshape([n, width])?.into_any(),
    })
}

/// A table as a dict of arrays, one per column.
pub fn table<'py>(py: Python<'py>, t: Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, c) in t {
        d.set_item(name, array(py, c)?)?;
    }
    Ok(d)
}

/// A table's first row as a dict of Python scalars (a point as a 1-D array).
pub fn first_row<'py>(py: Python<'py>, t: Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, c) in t {
        match c {
            Column::Int(v) => d.set_item(name, v[0])?,
            Column::Float(v) => d.set_item(name, v[0])?,
            Column::Bool(v) => d.set_item(name, v[0])?,
            Column::Points { width, values } => d.set_item(name, values[..width].to_vec().into_pyarray(py))?,
        }
    }
    Ok(d)
}

/// A record as a dict of Python ints and floats.
pub fn record<'py>(py: Python<'py>, r: Record) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, x) in r {
        match x {
            Number::Count(v) => d.set_item(name, v)?,
            Number::Float(v) => d.set_item(name, v)?,
        }
    }
    Ok(d)
}
