//! The body's parameters: which arm, its geometry and limits, noise, and a change during a run.

use crate::error::{invalid, Check, Num, Result};

/// Which kinematics the arm has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ArmKind {
    /// The paper's arm: every joint turns about z, the task space is the plane (x, y).
    #[serde(rename = "planar_arm")]
    Planar,
    /// An arm in space: joint i turns about its link frame's z axis for even i and its y axis
    /// for odd i; the task space is (x, y, z).
    #[serde(rename = "spatial_arm")]
    Spatial,
    /// A serial chain of hinges given by fixed transforms (`ArmConfig::chain`), such as a
    /// MuJoCo model's arm; the task space is (x, y, z) and each joint's coordinate in [-1, 1]
    /// spans its range.
    #[serde(rename = "chain")]
    Chain,
}

impl ArmKind {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "planar_arm" => Ok(ArmKind::Planar),
            "spatial_arm" => Ok(ArmKind::Spatial),
            "chain" => Ok(ArmKind::Chain),
            _ => Err(invalid("Run", "body", "one of 'planar_arm', 'spatial_arm', 'chain'", format!("'{s}'"))),
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            ArmKind::Planar => "planar_arm",
            ArmKind::Spatial => "spatial_arm",
            ArmKind::Chain => "chain",
        }
    }
    /// Dimension of the arm's task space.
    pub fn task_dim(&self) -> usize {
        match self {
            ArmKind::Planar => 2,
            ArmKind::Spatial | ArmKind::Chain => 3,
        }
    }
}

/// Geometry and actuation limits of a serial arm.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmConfig {
    pub kind: ArmKind,
    /// Length of each link; the number of joints is its length. For a chain, the distances
    /// between consecutive joint anchors and from the last to the end effector (`Chain::link_lengths`).
    pub link_lengths: Vec<f64>,
    /// The chain's geometry (`ArmKind::Chain` only).
    pub chain: Option<ChainSpec>,
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
        ArmConfig { kind: ArmKind::Planar, link_lengths: vec![total_length / n as f64; n], chain: None, joint_limit, max_joint_step, motor_noise: 0.0, sensor_noise: 0.0, noise_seed: 0 }
    }

    pub fn validate(&self) -> Result<()> {
        let c = Check { owner: "Arm" };
        match (&self.chain, self.kind) {
            (Some(chain), ArmKind::Chain) => {
                // Consecutive joints may share an anchor (a zero-length link); the whole chain may not.
                let lengths_ok = self.link_lengths.iter().all(|l| l.is_finite() && *l >= 0.0) && self.link_lengths.iter().sum::<f64>() > 0.0;
                if self.link_lengths.len() != chain.joints.len() || !lengths_ok {
                    return Err(invalid("Arm", "chain", "a chain whose end effector is away from its first joint (link lengths from its geometry)", format!("{:?}", self.link_lengths)));
                }
                c.in_open_closed("joint_limit", self.joint_limit, 0.0, 1.0)
                    .map_err(|_| invalid("Arm", "joint_limit", "a float in (0, 1] for body 'chain' (a share of each joint's half-range)", Num(self.joint_limit)))?;
                c.positive("max_joint_step", self.max_joint_step)?;
                c.non_negative("motor_noise", self.motor_noise)?;
                return c.non_negative("sensor_noise", self.sensor_noise);
            }
            (None, ArmKind::Chain) => return Err(invalid("Arm", "chain", "the chain's geometry for body 'chain'", "none")),
            (Some(_), _) => return Err(invalid("Arm", "body", "'chain' when a chain is given", format!("'{}'", self.kind.name()))),
            (None, _) => {}
        }
        if self.link_lengths.is_empty() {
            return Err(invalid("Arm", "link_lengths", "a non-empty list of floats > 0", "[]"));
        }
        if self.link_lengths.len() > MAX_JOINTS {
            return Err(invalid("Arm", "n_joints", format!("an int in [1, {MAX_JOINTS}]"), self.link_lengths.len()));
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

/// Numbers per joint in the flat form of a chain: pos (3), quat (w, x, y, z: 4), anchor (3),
/// axis (3), low, high.
pub const CHAIN_JOINT_LEN: usize = 15;
/// The most joints an arm may have: a bound of the configuration, the same on every machine
/// (whether a run of so many fits in memory is checked where the run starts).
/// The paper's arm: its length (the sum of its links), the default of a run.
pub const DEFAULT_ARM_LENGTH: f64 = 50.0;

pub const MAX_JOINTS: usize = 1_000_000;

/// One hinge of a chain (`crate::body::chain` has the kinematics): the fixed transform from the
/// previous joint's frame to this joint's body, the hinge's anchor and unit axis in that body,
/// and its range (radians, measured from the model's rest angle).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainJointSpec {
    pub pos: [f64; 3],
    /// Unit quaternion (w, x, y, z).
    pub quat: [f64; 4],
    pub anchor: [f64; 3],
    pub axis: [f64; 3],
    pub low: f64,
    pub high: f64,
}

/// A serial chain of hinges: its joints from the base, then the end effector in the last one's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainSpec {
    pub joints: Vec<ChainJointSpec>,
    pub tip: [f64; 3],
}

impl ChainSpec {
    /// The chain of its flat form: `CHAIN_JOINT_LEN` numbers per joint, then the tip (3).
    pub fn from_flat(v: &[f64]) -> Result<Self> {
        let rule = format!("a list of {CHAIN_JOINT_LEN} n + 3 finite floats (n >= 1 joints of pos[3], quat[4], anchor[3], axis[3], low, high; then the tip[3])");
        if v.len() < CHAIN_JOINT_LEN + 3 || (v.len() - 3) % CHAIN_JOINT_LEN != 0 || !v.iter().all(|x| x.is_finite()) {
            return Err(invalid("Arm", "chain", rule, format!("{} numbers", v.len())));
        }
        let n = (v.len() - 3) / CHAIN_JOINT_LEN;
        let unit = |x: &[f64]| -> Option<Vec<f64>> {
            let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            (norm > 0.0).then(|| x.iter().map(|v| v / norm).collect())
        };
        let mut joints = Vec::with_capacity(n);
        for (j, c) in v[..n * CHAIN_JOINT_LEN].chunks_exact(CHAIN_JOINT_LEN).enumerate() {
            let quat = unit(&c[3..7]).ok_or_else(|| invalid("Arm", "chain", "a non-zero quaternion for every joint", format!("joint {j}: {:?}", &c[3..7])))?;
            let axis = unit(&c[10..13]).ok_or_else(|| invalid("Arm", "chain", "a non-zero axis for every joint", format!("joint {j}: {:?}", &c[10..13])))?;
            let (low, high) = (c[13], c[14]);
            if low >= high {
                return Err(invalid("Arm", "chain", "low < high for every joint's range", format!("joint {j}: [{}, {}]", Num(low), Num(high))));
            }
            joints.push(ChainJointSpec { pos: [c[0], c[1], c[2]], quat: [quat[0], quat[1], quat[2], quat[3]], anchor: [c[7], c[8], c[9]], axis: [axis[0], axis[1], axis[2]], low, high });
        }
        let t = &v[n * CHAIN_JOINT_LEN..];
        Ok(ChainSpec { joints, tip: [t[0], t[1], t[2]] })
    }
}
