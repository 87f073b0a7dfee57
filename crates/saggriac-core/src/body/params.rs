//! The body as Python's `Config` describes it: by the arm's kind, number of joints and total
//! length (or its link lengths, or a chain's geometry), its limits and noise, and a change of
//! one link during the run. Serialised by those names, so the binding reads them as data; the
//! arm's configuration is built from them here.

use serde::{Deserialize, Serialize};

use crate::body::chain::Chain;
use crate::config::body::{ArmConfig, ArmKind, BodyChange, ChainSpec, DEFAULT_ARM_LENGTH, MAX_JOINTS};
use crate::config::RunConfig;
use crate::error::{invalid, Result};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BodyParams {
    pub body: ArmKind,
    pub n_joints: usize,
    pub arm_length: f64,
    /// Replaces `n_joints` and `arm_length` when given.
    pub link_lengths: Option<Vec<f64>>,
    pub joint_limit: f64,
    pub max_joint_step: f64,
    pub motor_noise: f64,
    pub sensor_noise: f64,
    /// A chain's geometry, flat (`ChainSpec::from_flat`), for body "chain" only.
    pub chain: Option<Vec<f64>>,
    pub body_change_step: Option<u64>,
    pub body_change_link: Option<usize>,
    pub body_change_length: Option<f64>,
}

impl Default for BodyParams {
    /// The default run's arm.
    fn default() -> Self {
        let a = RunConfig::default().arm;
        BodyParams {
            body: a.kind,
            n_joints: a.link_lengths.len(),
            arm_length: DEFAULT_ARM_LENGTH,
            link_lengths: None,
            joint_limit: a.joint_limit,
            max_joint_step: a.max_joint_step,
            motor_noise: a.motor_noise,
            sensor_noise: a.sensor_noise,
            chain: None,
            body_change_step: None,
            body_change_link: None,
            body_change_length: None,
        }
    }
}

impl BodyParams {
    /// The arm and the change of the body these parameters describe (the arm's own rules are
    /// checked with the run's, by `RunConfig::validate`).
    pub fn build(self) -> Result<(ArmConfig, Option<BodyChange>)> {
        let BodyParams { body, n_joints, arm_length, link_lengths, joint_limit, max_joint_step, motor_noise, sensor_noise, chain, .. } = self;
        // Refused before the arm's vectors are allocated.
        if n_joints == 0 {
            return Err(invalid("Run", "n_joints", "an int >= 1", n_joints));
        }
        if n_joints > MAX_JOINTS {
            return Err(invalid("Run", "n_joints", format!("an int in [1, {MAX_JOINTS}]"), n_joints));
        }
        let mut arm = match link_lengths.clone() {
            Some(l) => ArmConfig { link_lengths: l, ..ArmConfig::uniform(1, 1.0, joint_limit, max_joint_step) },
            None => ArmConfig::uniform(n_joints, arm_length, joint_limit, max_joint_step),
        };
        arm.kind = body;
        match (chain, body) {
            (Some(_), ArmKind::Chain) if link_lengths.is_some() => return Err(invalid("Run", "link_lengths", "not given with body 'chain' (the chain's geometry gives its links)", "a list")),
            (Some(flat), ArmKind::Chain) => arm = Chain::arm_config(ChainSpec::from_flat(&flat)?, arm),
            (None, ArmKind::Chain) => return Err(invalid("Run", "chain", "the chain's geometry for body 'chain' (saggriac.bodies.mujoco_arm.MujocoArm.chain() gives it)", "None")),
            (Some(_), _) => return Err(invalid("Run", "chain", format!("None unless body is 'chain' (body is '{}')", body.name()), "a list")),
            (None, _) => {}
        }
        (arm.motor_noise, arm.sensor_noise) = (motor_noise, sensor_noise);
        let change = self.body_change_step.map(|step| BodyChange { step, link: self.body_change_link.unwrap_or(usize::MAX), length: self.body_change_length.unwrap_or(f64::NAN) });
        Ok((arm, change))
    }
}
