//! A Python dict of flat parameters -> the core's `RunConfig`. Type problems are reported with
//! the parameter's name; the rules themselves are checked once, by the core's `validate()`.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use saggriac_core::body::arm::{ArmConfig, ArmKind};
use saggriac_core::body::chain::{Chain, ChainSpec};
use saggriac_core::config::body::{DEFAULT_ARM_LENGTH, MAX_JOINTS};
use saggriac_core::config::evaluation::TestConfigs;
use saggriac_core::config::high_level::{CompetenceKind, InterestDivisor};
use saggriac_core::config::teachers::Teacher;
use saggriac_core::config::Paradigm;
use saggriac_core::error::invalid;
use saggriac_core::model::memory::IndexKind;
use saggriac_core::{Condition, Error, RunConfig};

use crate::errors::{to_py, wrap};

/// The keys `run_config_from_dict` understands (kept in the order of the parameters page).
#[rustfmt::skip]
pub const KEYS: &[&str] = &[
    "condition", "n_steps", "body", "n_joints", "arm_length", "link_lengths", "joint_limit", "max_joint_step", "goal_low", "goal_high",
    "v", "n_subgoals", "eps_max", "timeout_factor", "timeout_min", "timeout_in_exploration", "q", "explore_step", "k_neighbours", "ridge", "pinv_rcond",
    "bandwidth", "min_c", "eps_c", "competence", "g_max", "zeta", "min_child", "interest_divisor", "p_interest", "p_global", "p_lowest", "reset_every",
    "n_test_goals", "n_test_configs", "test_configs", "eval_tolerance", "eval_patience", "eval_timeout_factor", "eval_timeout_min",
    "eval_schedule", "knn_index", "warm_start_recent", "babble_step", "actuator_candidates", "actuator_reset_every", "paradigm", "episodic_noise", "episodic_refine", "episodic_k", "motor_noise", "sensor_noise", "body_change_step",
    "body_change_link", "body_change_length", "chain", "teacher", "teacher_params",
];

/// The core names a rule's parameter by the struct that owns it (`tolerance` of `Evaluation`);
/// a Python user knows one flat `Config`, so every message names the Config key instead.
pub fn in_config_terms(e: Error) -> Error {
    match e {
        Error::InvalidParameter { owner, param, rule, value } => {
            if param == "goal_selector" {
                // An argument of saggriac.run, not a Config key.
                return Error::InvalidParameter { owner: "run", param, rule, value };
            }
            if owner.ends_with("Selector") {
                // A rule of the teacher chosen by `teacher`, set through `teacher_params`.
                return Error::InvalidParameter { owner: "Config", param: format!("teacher_params.{param}"), rule, value };
            }
            let key = match (owner, param.as_str()) {
                ("Evaluation", "tolerance" | "patience" | "timeout_factor" | "timeout_min" | "schedule") => format!("eval_{param}"),
                ("Exploration", "step") => "explore_step".to_string(),
                ("Run", "bounds") => "goal_low/goal_high".to_string(),
                _ => param,
            };
            Error::InvalidParameter { owner: "Config", param: key, rule, value }
        }
        other => other,
    }
}

fn get<'py, T: FromPyObjectOwned<'py>>(d: &Bound<'py, PyDict>, key: &str, default: T, kind: &str) -> PyResult<T> {
    match d.get_item(key)? {
        None => Ok(default),
        Some(v) if v.is_none() => Ok(default),
        Some(v) => v.extract::<T>().map_err(|_| {
            let shown = v.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
            to_py(d.py(), invalid("Config", key, kind, shown))
        }),
    }
}

/// The configuration `d` describes, checked against every rule (`Config()` checks this way).
pub fn run_config_from_dict(d: &Bound<'_, PyDict>) -> PyResult<RunConfig> {
    let c = parse_config(d)?;
    c.validate().map_err(|e| to_py(d.py(), in_config_terms(e)))?;
    Ok(c)
}

/// The configuration `d` describes, with the type of every value checked but not the rules: a
/// learner built from it checks them itself (`Learner::from_parts`), once per run.
pub fn parse_config(d: &Bound<'_, PyDict>) -> PyResult<RunConfig> {
    let py = d.py();
    for k in d.keys() {
        let k: String = k.extract()?;
        if !KEYS.contains(&k.as_str()) {
            return Err(to_py(py, invalid("Config", &k, format!("one of the known parameters ({})", KEYS.join(", ")), "an unknown key")));
        }
    }
    let mut c = RunConfig::default();
    let condition: String = get(d, "condition", c.condition.name().to_string(), "a str")?;
    c.condition = Condition::parse(&condition).map_err(|e| to_py(py, in_config_terms(e)))?;
    c.n_steps = get(d, "n_steps", c.n_steps, "an int >= 1")?;
    let n_joints: usize = get(d, "n_joints", c.arm.link_lengths.len(), "an int >= 1")?;
    let length: f64 = get(d, "arm_length", DEFAULT_ARM_LENGTH, "a float > 0")?;
    let links: Option<Vec<f64>> = get(d, "link_lengths", None, "a list of floats")?;
    let limit = get(d, "joint_limit", c.arm.joint_limit, "a float")?;
    let max_step = get(d, "max_joint_step", c.arm.max_joint_step, "a float")?;
    if n_joints == 0 || n_joints > MAX_JOINTS {
        // Refused before the arm's vectors are allocated.
        return Err(to_py(py, invalid("Config", "n_joints", format!("an int in [1, {MAX_JOINTS}]"), n_joints)));
    }
    c.arm = match links.clone() {
        Some(l) => ArmConfig { link_lengths: l, ..ArmConfig::uniform(1, 1.0, limit, max_step) },
        None => ArmConfig::uniform(n_joints, length, limit, max_step),
    };
    let body: String = get(d, "body", ArmKind::Planar.name().to_string(), "a str")?;
    c.arm.kind = ArmKind::parse(&body).map_err(|e| to_py(py, in_config_terms(e)))?;
    let chain: Option<Vec<f64>> = get(d, "chain", None, "a list of floats")?;
    match (chain, c.arm.kind) {
        (Some(flat), ArmKind::Chain) => {
            if links.is_some() {
                return Err(to_py(py, invalid("Config", "link_lengths", "not given with body 'chain' (the chain's geometry gives its links)", "a list")));
            }
            let spec = ChainSpec::from_flat(&flat).map_err(|e| to_py(py, in_config_terms(e)))?;
            c.arm = Chain::arm_config(spec, c.arm.clone());
        }
        (None, ArmKind::Chain) => return Err(to_py(py, invalid("Config", "chain", "the chain's geometry for body 'chain' (saggriac.mujoco_arm.MujocoArm.chain() gives it)", "None"))),
        (Some(_), _) => return Err(to_py(py, invalid("Config", "chain", format!("None unless body is 'chain' (body is '{body}')"), "a list"))),
        (None, _) => {}
    }
    c.arm.motor_noise = get(d, "motor_noise", 0.0, "a float")?;
    c.arm.sensor_noise = get(d, "sensor_noise", 0.0, "a float")?;
    let change_step: Option<u64> = get(d, "body_change_step", None, "an int >= 1")?;
    if let Some(step) = change_step {
        let link: usize = get(d, "body_change_link", usize::MAX, "an int >= 0")?;
        let length: f64 = get(d, "body_change_length", f64::NAN, "a float > 0")?;
        c.body_change = Some(saggriac_core::config::BodyChange { step, link, length });
    }
    c.goal_low = get(d, "goal_low", c.goal_low, "a list of floats")?;
    c.goal_high = get(d, "goal_high", c.goal_high, "a list of floats")?;
    c.reaching.v = get(d, "v", c.reaching.v, "a float")?;
    c.reaching.n_subgoals = get(d, "n_subgoals", c.reaching.n_subgoals, "an int >= 1")?;
    c.reaching.eps_max = get(d, "eps_max", c.reaching.eps_max, "a float")?;
    c.reaching.timeout_factor = get(d, "timeout_factor", c.reaching.timeout_factor, "a float")?;
    c.reaching.timeout_min = get(d, "timeout_min", c.reaching.timeout_min, "an int >= 1")?;
    c.reaching.timeout_in_exploration = get(d, "timeout_in_exploration", c.reaching.timeout_in_exploration, "a bool")?;
    c.exploration.q = get(d, "q", c.exploration.q, "an int >= 1")?;
    c.exploration.step = get(d, "explore_step", c.exploration.step, "a float")?;
    c.local.k_neighbours = get(d, "k_neighbours", c.local.k_neighbours, "an int >= 1")?;
    c.local.ridge = get(d, "ridge", c.local.ridge, "a float")?;
    c.local.pinv_rcond = get(d, "pinv_rcond", c.local.pinv_rcond, "a float")?;
    c.local.bandwidth = get(d, "bandwidth", c.local.bandwidth, "a float")?;
    c.competence.min_c = get(d, "min_c", c.competence.min_c, "a float")?;
    c.competence.eps_c = get(d, "eps_c", c.competence.eps_c, "a float")?;
    let teacher: String = get(d, "teacher", "own".to_string(), "a str")?;
    let params = match d.get_item("teacher_params")?.filter(|p| !p.is_none()) {
        Some(p) => Some(p.cast_into::<PyDict>().map_err(|_| to_py(py, invalid("Config", "teacher_params", "a dict of the teacher's parameters", "not a dict")))?),
        None => None,
    };
    c.teacher = match teacher.as_str() {
        "own" => match params.filter(|p| !p.is_empty()) {
            None => None,
            Some(p) => {
                let own: Vec<String> = crate::teachers::params(py, &Teacher::SaggRiac(Default::default()))?.keys().iter().map(|k| k.to_string()).collect();
                let rule = format!("empty with teacher 'own' (SAGG-RIAC's own high level is set by {})", own.join(", "));
                let key = p.keys().get_item(0).map(|k| k.to_string()).unwrap_or_default();
                return Err(to_py(py, invalid("Config", "teacher_params", rule, format!("a dict with key '{key}'"))));
            }
        },
        kind => {
            let default = Teacher::parse("Config", "teacher", kind).map_err(|e| match e {
                Error::InvalidParameter { owner, param, rule, value } => Error::InvalidParameter { owner, param, rule: rule.replacen("one of ", "one of 'own', ", 1), value },
                other => other,
            });
            // The paper's thresholds are for competences in [0, 1]; a run's lie in [min_c, 0].
            let default = wrap(py, default)?.scaled_to_competences(c.competence.min_c, 0.0);
            Some(crate::teachers::teacher(py, default, params.as_ref(), "Config", "teacher_params", "teacher_params.")?)
        }
    };
    let kind: String = get(d, "competence", c.competence.kind.name().to_string(), "a str")?;
    c.competence.kind = CompetenceKind::parse(&kind).ok_or_else(|| to_py(py, invalid("Config", "competence", "one of 'relative', 'absolute'", format!("'{kind}'"))))?;
    c.tree.g_max = get(d, "g_max", c.tree.g_max, "an int >= 2")?;
    c.tree.zeta = get(d, "zeta", c.tree.zeta, "an int >= 2")?;
    c.tree.min_child = get(d, "min_child", c.tree.min_child, "an int >= 1")?;
    let divisor: String = get(d, "interest_divisor", c.tree.divisor.name().to_string(), "a str")?;
    c.tree.divisor = InterestDivisor::parse("Config", &divisor).map_err(|e| to_py(py, e))?;
    c.modes.p_interest = get(d, "p_interest", c.modes.p_interest, "a float")?;
    c.modes.p_global = get(d, "p_global", c.modes.p_global, "a float")?;
    c.modes.p_lowest = get(d, "p_lowest", c.modes.p_lowest, "a float")?;
    c.reset_every = get(d, "reset_every", c.reset_every, "an int >= 1")?;
    c.eval.n_test_goals = get(d, "n_test_goals", c.eval.n_test_goals, "an int >= 1")?;
    c.eval.n_test_configs = get(d, "n_test_configs", c.eval.n_test_configs, "an int >= 1")?;
    let kind: String = get(d, "test_configs", c.eval.test_configs.name().to_string(), "a str")?;
    c.eval.test_configs = TestConfigs::parse(&kind).ok_or_else(|| to_py(py, invalid("Config", "test_configs", "one of 'ik_min_norm', 'uniform'", format!("'{kind}'"))))?;
    c.eval.tolerance = get(d, "eval_tolerance", c.eval.tolerance, "a float")?;
    c.eval.patience = get(d, "eval_patience", c.eval.patience, "an int >= 1")?;
    c.eval.timeout_factor = get(d, "eval_timeout_factor", c.eval.timeout_factor, "a float")?;
    c.eval.timeout_min = get(d, "eval_timeout_min", c.eval.timeout_min, "an int >= 1")?;
    c.eval.schedule = get(d, "eval_schedule", c.eval.schedule, "a list of ints >= 0")?;
    let index: String = get(d, "knn_index", c.index.name().to_string(), "a str")?;
    c.index = IndexKind::parse(&index).ok_or_else(|| to_py(py, invalid("Config", "knn_index", "one of 'blocks', 'brute_force'", format!("'{index}'"))))?;
    c.warm_start_recent = get(d, "warm_start_recent", c.warm_start_recent, "an int >= 0")?;
    c.babble_step = get(d, "babble_step", c.babble_step, "a float")?;
    c.actuator_candidates = get(d, "actuator_candidates", c.actuator_candidates, "an int >= 0")?;
    c.actuator_reset_every = get(d, "actuator_reset_every", c.actuator_reset_every, "an int >= 0")?;
    let paradigm: String = get(d, "paradigm", c.paradigm.name().to_string(), "a str")?;
    c.paradigm = Paradigm::parse(&paradigm).map_err(|e| to_py(py, in_config_terms(e)))?;
    c.episodic.noise = get(d, "episodic_noise", c.episodic.noise, "a float")?;
    c.episodic.refine = get(d, "episodic_refine", c.episodic.refine, "a bool")?;
    c.episodic.k_refine = get(d, "episodic_k", c.episodic.k_refine, "an int >= 1")?;
    Ok(c)
}

/// The core's default configuration in `Config`'s flat terms: the one declaration of every
/// default, which Python's `Config` reads (`_core.config_defaults()`). None where the default is
/// "not given" (lengths that follow the body are given here as the default arm's).
pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let c = RunConfig::default();
    let d = PyDict::new(py);
    d.set_item("condition", c.condition.name())?;
    d.set_item("n_steps", c.n_steps)?;
    d.set_item("body", c.arm.kind.name())?;
    d.set_item("n_joints", c.arm.link_lengths.len())?;
    d.set_item("arm_length", DEFAULT_ARM_LENGTH)?;
    d.set_item("joint_limit", c.arm.joint_limit)?;
    d.set_item("max_joint_step", c.arm.max_joint_step)?;
    d.set_item("motor_noise", c.arm.motor_noise)?;
    d.set_item("sensor_noise", c.arm.sensor_noise)?;
    for k in ["link_lengths", "chain", "body_change_step", "body_change_link", "body_change_length"] {
        d.set_item(k, py.None())?;
    }
    d.set_item("goal_low", c.goal_low.clone())?;
    d.set_item("goal_high", c.goal_high.clone())?;
    let r = c.reaching;
    d.set_item("v", r.v)?;
    d.set_item("n_subgoals", r.n_subgoals)?;
    d.set_item("eps_max", r.eps_max)?;
    d.set_item("timeout_factor", r.timeout_factor)?;
    d.set_item("timeout_min", r.timeout_min)?;
    d.set_item("timeout_in_exploration", r.timeout_in_exploration)?;
    d.set_item("q", c.exploration.q)?;
    d.set_item("explore_step", c.exploration.step)?;
    d.set_item("k_neighbours", c.local.k_neighbours)?;
    d.set_item("ridge", c.local.ridge)?;
    d.set_item("pinv_rcond", c.local.pinv_rcond)?;
    d.set_item("bandwidth", c.local.bandwidth)?;
    d.set_item("min_c", c.competence.min_c)?;
    d.set_item("eps_c", c.competence.eps_c)?;
    d.set_item("competence", c.competence.kind.name())?;
    d.set_item("g_max", c.tree.g_max)?;
    d.set_item("zeta", c.tree.zeta)?;
    d.set_item("min_child", c.tree.min_child)?;
    d.set_item("interest_divisor", c.tree.divisor.name())?;
    d.set_item("p_interest", c.modes.p_interest)?;
    d.set_item("p_global", c.modes.p_global)?;
    d.set_item("p_lowest", c.modes.p_lowest)?;
    d.set_item("reset_every", c.reset_every)?;
    d.set_item("teacher", c.teacher.map(|t| t.kind()).unwrap_or("own"))?;
    d.set_item("teacher_params", PyDict::new(py))?;
    let e = &c.eval;
    d.set_item("n_test_goals", e.n_test_goals)?;
    d.set_item("n_test_configs", e.n_test_configs)?;
    d.set_item("test_configs", e.test_configs.name())?;
    d.set_item("eval_tolerance", e.tolerance)?;
    d.set_item("eval_patience", e.patience)?;
    d.set_item("eval_timeout_factor", e.timeout_factor)?;
    d.set_item("eval_timeout_min", e.timeout_min)?;
    d.set_item("eval_schedule", e.schedule.clone())?;
    d.set_item("knn_index", c.index.name())?;
    d.set_item("warm_start_recent", c.warm_start_recent)?;
    d.set_item("babble_step", c.babble_step)?;
    d.set_item("actuator_candidates", c.actuator_candidates)?;
    d.set_item("actuator_reset_every", c.actuator_reset_every)?;
    d.set_item("paradigm", c.paradigm.name())?;
    d.set_item("episodic_noise", c.episodic.noise)?;
    d.set_item("episodic_refine", c.episodic.refine)?;
    d.set_item("episodic_k", c.episodic.k_refine)?;
    Ok(d)
}
