//! The body's parameters: which arm, its geometry and limits, noise, and a change during a run.

use crate::error::{invalid, Check, Result};

/// Which kinematics the arm has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArmKind {
    /// The paper's arm: every joint turns about z, the task space is the plane (x, y).
    Planar,
    /// An arm in space: joint i turns about its link frame's z axis for even i and its y axis
    /// for odd i; the task space is (x, y, z).
    Spatial,
}

impl ArmKind {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "planar_arm" => Ok(ArmKind::Planar),
            "spatial_arm" => Ok(ArmKind::Spatial),
            _ => Err(invalid("Run", "body", "one of 'planar_arm', 'spatial_arm'", format!("'{s}'"))),
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            ArmKind::Planar => "planar_arm",
            ArmKind::Spatial => "spatial_arm",
        }
    }
    /// Dimension of the arm's task space.
    pub fn task_dim(&self) -> usize {
        match self {
            ArmKind::Planar => 2,
            ArmKind::Spatial => 3,
        }
    }
}

/// Geometry and actuation limits of a serial arm.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmConfig {
    pub kind: ArmKind,
    /// Length of each link; the number of joints is its length.
    pub link_lengths: Vec<f64>,
    /// Symmetric joint limit: every joint angle stays in [-joint_limit, joint_limit] (radians).
    pub joint_limit: f64,
    /// Largest absolute change of any joint in one micro-action (radians).
    pub max_joint_step: f64,
    /// Standard deviation of Gaussian noise added to each joint's executed change (radians).
    pub motor_noise: f64,
    /// Standard deviation of Gaussian noise on each coordinate of every position reading.
    pub sensor_noise: f64,
    /// Seed of the noise (set by the learner from the run's seed).
    pub noise_seed: u64,
}

impl ArmConfig {
    /// `n` equal links summing to `total_length`.
    pub fn uniform(n: usize, total_length: f64, joint_limit: f64, max_joint_step: f64) -> Self {
        ArmConfig { kind: ArmKind::Planar, link_lengths: vec![total_length / n as f64; n], joint_limit, max_joint_step, motor_noise: 0.0, sensor_noise: 0.0, noise_seed: 0 }
    }

    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "Arm" };
        if self.link_lengths.is_empty() {
            return Err(invalid("Arm", "link_lengths", "a non-empty list of floats > 0", "[]"));
        }
        for &l in &self.link_lengths {
            if !(l.is_finite() && l > 0.0) {
                return Err(invalid("Arm", "link_lengths", "a list of finite floats > 0", format!("{:?}", self.link_lengths)));
            }
        }
        c.in_open_closed("joint_limit", self.joint_limit, 0.0, std::f64::consts::PI)?;
        c.positive("max_joint_step", self.max_joint_step)?;
        c.non_negative("motor_noise", self.motor_noise)?;
        c.non_negative("sensor_noise", self.sensor_noise)?;
        Ok(())
    }
}

/// A body that changes during a run: at time step `step`, link `link` takes length `length`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyChange {
    pub step: u64,
    pub link: usize,
    pub length: f64,
}
