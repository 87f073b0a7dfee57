//! saggriac._core: a thin PyO3 layer over saggriac-core. It converts types and errors only;
//! the algorithm lives in the core crate. One file per core component: config, body (a Python
//! environment), chain (its kinematics), goal_selection (a Python selector, the region tree), ask_tell, competence,
//! evaluation,
//! recorder, run_loop; every error conversion in errors.rs.

use pyo3::prelude::*;

mod ask_tell;
mod body;
mod chain;
mod competence;
mod config;
mod errors;
mod evaluation;
mod gmm;
mod goal_selection;
mod recorder;
mod run_loop;
mod teachers;
mod values;

/// validate_config(config: dict) -> None: raise ParameterError if any parameter breaks a rule.
#[pyfunction]
fn validate_config(config: &Bound<'_, pyo3::types::PyDict>) -> PyResult<()> {
    config::run_config_from_dict(config).map(|_| ())
}

/// config_debug(config: dict) -> str: the core's configuration built from `config` (missing keys
/// take the core's defaults), printed; lets a test check that Python's defaults are the core's.
#[pyfunction]
fn config_debug(config: &Bound<'_, pyo3::types::PyDict>) -> PyResult<String> {
    config::run_config_from_dict(config).map(|c| format!("{c:?}"))
}

/// config_defaults() -> dict: every parameter's default, as the core declares it.
#[pyfunction]
fn config_defaults(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    config::defaults(py)
}

/// teacher_param_rule(kind, name) -> str | None: the rule of the parameter `name` of the teacher
/// `kind`, as its check states it (None for a name it has not).
#[pyfunction]
fn teacher_param_rule(py: Python<'_>, kind: &str, name: &str) -> PyResult<Option<String>> {
    let teacher = errors::wrap(py, saggriac_core::config::teachers::Teacher::parse("teacher_param_rule", "kind", kind))?;
    teachers::rule_text(py, &teacher, name)
}

/// teacher_defaults() -> dict: the default parameters of each teacher a run can take.
#[pyfunction]
fn teacher_defaults(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    teachers::defaults(py)
}

/// teacher_registry() -> list[tuple[str, str, str]]: each teacher of the core's registry as
/// (name, Python class, goal space: "box" or "tasks"), in the registry's order.
#[pyfunction]
fn teacher_registry() -> Vec<(&'static str, &'static str, &'static str)> {
    saggriac_core::config::teachers::Teacher::all().iter().map(|t| (t.kind(), t.class(), if t.has_box() { "box" } else { "tasks" })).collect()
}

/// teacher_per_dimension() -> dict: for each teacher, the parameters it also takes per dimension
/// of the box, by name: "vector" (a list, one value per dimension, in place of the number) or
/// "matrix" (d x d, beside the numbers).
#[pyfunction]
fn teacher_per_dimension(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    teachers::per_dimension_names(py)
}

/// child_seed(parent, stream) -> int: the core's seed of one component (SplitMix64 mixing; stream
/// 1 is the high level, 2 the low level's generator).
#[pyfunction]
fn child_seed(parent: u64, stream: u64) -> u64 {
    saggriac_core::rng::child_seed(parent, stream)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<run_loop::PyLearner>()?;
    m.add_class::<ask_tell::PyAskTell>()?;
    m.add("CONFIG_KEYS", config::keys(m.py())?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("GIT_COMMIT", env!("SAGGRIAC_GIT_COMMIT"))?;
    // A test configuration further than this times the reach from its goal did not reach it.
    m.add("IK_TOLERANCE", saggriac_core::evaluation::test_set::IK_TOLERANCE)?;
    m.add_function(wrap_pyfunction!(validate_config, m)?)?;
    m.add_function(wrap_pyfunction!(config_debug, m)?)?;
    m.add_function(wrap_pyfunction!(config_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(teacher_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(teacher_param_rule, m)?)?;
    m.add_function(wrap_pyfunction!(teacher_registry, m)?)?;
    m.add_function(wrap_pyfunction!(teacher_per_dimension, m)?)?;
    m.add_function(wrap_pyfunction!(child_seed, m)?)?;
    m.add_function(wrap_pyfunction!(competence::competence, m)?)?;
    m.add_function(wrap_pyfunction!(chain::chain_forward, m)?)?;
    m.add_function(wrap_pyfunction!(chain::chain_points, m)?)?;
    m.add_function(wrap_pyfunction!(chain::chain_link_lengths, m)?)?;
    m.add_function(wrap_pyfunction!(chain::chain_cloud, m)?)?;
    m.add_function(wrap_pyfunction!(gmm::gmm_fit, m)?)?;
    Ok(())
}
