//! A serial chain of hinge joints given by fixed transforms, the way a MuJoCo model's kinematic
//! tree describes an arm (each body's `pos` and `quat` in its parent, each hinge's `pos` and
//! `axis` in its body). `saggriac.bodies.mujoco_arm` reads one out of any model; the run loop then moves
//! it natively, with no call into Python or MuJoCo per micro-action.
//!
//! Joint j sees saggriac's coordinate theta_j in [-1, 1] as the hinge angle
//! mid_j + half_j theta_j, its range [low_j, high_j] scaled so that rest (theta = 0) is the middle
//! of every range. Forward kinematics, from the base frame (the world's):
//!   p <- p + R pos_j;  R <- R rot_j;                      (the fixed transform to joint j's body)
//!   a <- p + R anchor_j;  R <- R Rot(axis_j, angle_j);  p <- a - R anchor_j;   (the hinge)
//! and the end effector is p + R tip. This is MuJoCo's `mj_kinematics` for hinges whose angle is
//! measured from the model's `qpos0` (the range is given relative to it).

use crate::config::body::{ArmConfig, ArmKind};
pub use crate::config::body::{ChainSpec, CHAIN_JOINT_LEN as JOINT_LEN};
use crate::error::Result;
use crate::rng::{uniform, CoreRng};
use crate::task_space::Point;

type Vec3 = [f64; 3];
/// A rotation matrix, row-major.
type Mat3 = [[f64; 3]; 3];

const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

#[derive(Debug, Clone, PartialEq)]
pub struct ChainJoint {
    pub pos: Vec3,
    pub rot: Mat3,
    pub anchor: Vec3,
    /// Unit axis in the joint's body frame.
    pub axis: Vec3,
    pub mid: f64,
    pub half: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    pub joints: Vec<ChainJoint>,
    /// The end effector in the last joint's body frame.
    pub tip: Vec3,
}

fn mat_vec(r: &Mat3, v: &Vec3) -> Vec3 {
    std::array::from_fn(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
}

fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j]))
}

fn add(a: &Vec3, b: &Vec3) -> Vec3 {
    std::array::from_fn(|i| a[i] + b[i])
}

fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// The rotation of a unit quaternion (w, x, y, z), normalised first.
fn quat_matrix(q: [f64; 4]) -> Mat3 {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let [w, x, y, z] = q.map(|v| v / n);
    [
        [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)],
        [2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)],
        [2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)],
    ]
}

/// Rotation by `angle` about the unit vector `u` (Rodrigues).
fn axis_angle(u: &Vec3, angle: f64) -> Mat3 {
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    let [x, y, z] = *u;
    [[t * x * x + c, t * x * y - s * z, t * x * z + s * y], [t * x * y + s * z, t * y * y + c, t * y * z - s * x], [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]
}

/// Where every joint is in the base frame at one configuration.
struct Frames {
    anchors: Vec<Vec3>,
    axes: Vec<Vec3>,
    tip: Vec3,
}

impl Chain {
    /// The kinematics of a validated chain description.
    pub fn new(spec: &ChainSpec) -> Self {
        let joints =
            spec.joints.iter().map(|j| ChainJoint { pos: j.pos, rot: quat_matrix(j.quat), anchor: j.anchor, axis: j.axis, mid: (j.low + j.high) / 2.0, half: (j.high - j.low) / 2.0 }).collect();
        Chain { joints, tip: spec.tip }
    }

    /// The chain of its flat form (`ChainSpec::from_flat`).
    pub fn from_flat(v: &[f64]) -> Result<Self> {
        Ok(Chain::new(&ChainSpec::from_flat(v)?))
    }

    /// An arm configuration for this chain: its links from the geometry, body kind `Chain`.
    pub fn arm_config(spec: ChainSpec, base: ArmConfig) -> ArmConfig {
        let link_lengths = Chain::new(&spec).link_lengths();
        ArmConfig { kind: ArmKind::Chain, link_lengths, chain: Some(spec), ..base }
    }

    pub fn n_joints(&self) -> usize {
        self.joints.len()
    }

    /// Distances between consecutive joint anchors, then from the last anchor to the tip: the
    /// same at every configuration (each anchor lies on its joint's axis), and their sum bounds
    /// the distance from the first anchor to the end effector.
    pub fn link_lengths(&self) -> Vec<f64> {
        let f = self.frames(&vec![0.0; self.n_joints()]);
        let mut pts = f.anchors;
        pts.push(f.tip);
        pts.windows(2).map(|w| (0..3).map(|i| (w[1][i] - w[0][i]).powi(2)).sum::<f64>().sqrt()).collect()
    }

    fn frames(&self, theta: &[f64]) -> Frames {
        let n = self.n_joints();
        let (mut p, mut r) = ([0.0; 3], IDENTITY);
        let (mut anchors, mut axes) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for (j, t) in self.joints.iter().zip(theta) {
            p = add(&p, &mat_vec(&r, &j.pos));
            r = mat_mul(&r, &j.rot);
            let a = add(&p, &mat_vec(&r, &j.anchor));
            axes.push(mat_vec(&r, &j.axis));
            r = mat_mul(&r, &axis_angle(&j.axis, j.mid + j.half * t));
            let back = mat_vec(&r, &j.anchor);
            p = std::array::from_fn(|i| a[i] - back[i]);
            anchors.push(a);
        }
        Frames { anchors, axes, tip: add(&p, &mat_vec(&r, &self.tip)) }
    }

    /// The end effector at `theta` (saggriac's coordinates, not clipped here).
    pub fn forward(&self, theta: &[f64]) -> Point {
        self.frames(theta).tip
    }

    /// Every joint's anchor and the end effector at `theta` (for drawing the arm).
    pub fn points(&self, theta: &[f64]) -> Vec<Point> {
        let f = self.frames(theta);
        let mut pts = f.anchors;
        pts.push(f.tip);
        pts
    }

    /// d x / d theta (3 x n, row-major): for a hinge, axis x (tip - anchor) per radian, times the
    /// half-range per unit of theta.
    pub fn jacobian(&self, theta: &[f64], out: &mut [f64]) {
        let n = self.n_joints();
        let f = self.frames(theta);
        for (j, (a, w)) in f.anchors.iter().zip(&f.axes).enumerate() {
            let arm: Vec3 = std::array::from_fn(|i| f.tip[i] - a[i]);
            let d = cross(w, &arm);
            for (row, v) in d.iter().enumerate() {
                out[row * n + j] = v * self.joints[j].half;
            }
        }
    }
}

/// End-effector positions at `n` configurations drawn uniformly within +-`limit`: a sample of
/// the chain's reachable set.
pub fn reachable_cloud(chain: &Chain, limit: f64, n: usize, rng: &mut CoreRng) -> Vec<Point> {
    let mut theta = vec![0.0; chain.n_joints()];
    (0..n)
        .map(|_| {
            theta.iter_mut().for_each(|t| *t = uniform(rng, -limit, limit));
            chain.forward(&theta)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::rng_from_seed;
    use nalgebra::{Rotation3, Unit, UnitQuaternion, Vector3};

    /// A chain with tilted frames, offset anchors and one joint with no offset from the last.
    fn flat() -> Vec<f64> {
        let mut v = Vec::new();
        // pos, quat, anchor, axis, low, high.
        type Row = ([f64; 3], [f64; 4], [f64; 3], [f64; 3], f64, f64);
        let joints: [Row; 4] = [
            ([0.0, -0.6, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], -2.28, 0.71),
            ([0.1, 0.0, 0.0], [0.9, 0.1, -0.3, 0.2], [0.0, 0.05, 0.0], [0.0, 1.0, 0.0], -0.52, 1.96),
            ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], -1.5, 1.7),
            ([0.4, 0.0, 0.0], [0.7, 0.0, 0.7, 0.0], [0.01, 0.0, 0.02], [0.0, 2.0, 1.0], -2.32, 0.0),
        ];
        for (p, q, a, ax, lo, hi) in joints {
            v.extend(p);
            v.extend(q);
            v.extend(a);
            v.extend(ax);
            v.extend([lo, hi]);
        }
        v.extend([0.32, 0.0, 0.0]);
        v
    }

    /// The same kinematics written with nalgebra's isometries, joint by joint.
    fn reference(v: &[f64], theta: &[f64]) -> Vector3<f64> {
        let n = (v.len() - 3) / JOINT_LEN;
        let (mut p, mut r) = (Vector3::zeros(), Rotation3::identity());
        for j in 0..n {
            let c = &v[j * JOINT_LEN..(j + 1) * JOINT_LEN];
            p += r * Vector3::new(c[0], c[1], c[2]);
            r *= UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(c[3], c[4], c[5], c[6])).to_rotation_matrix();
            let anchor = Vector3::new(c[7], c[8], c[9]);
            let a = p + r * anchor;
            let angle = (c[13] + c[14]) / 2.0 + (c[14] - c[13]) / 2.0 * theta[j];
            r *= Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(c[10], c[11], c[12])), angle);
            p = a - r * anchor;
        }
        p + r * Vector3::new(v[n * JOINT_LEN], v[n * JOINT_LEN + 1], v[n * JOINT_LEN + 2])
    }

    #[test]
    fn forward_matches_nalgebra() {
        let v = flat();
        let c = Chain::from_flat(&v).unwrap();
        let mut rng = rng_from_seed(3);
        for _ in 0..200 {
            let theta: Vec<f64> = (0..4).map(|_| uniform(&mut rng, -1.0, 1.0)).collect();
            let x = c.forward(&theta);
            let e = reference(&v, &theta);
            for k in 0..3 {
                assert!((x[k] - e[k]).abs() < 1e-12, "{x:?} vs {e:?}");
            }
        }
    }

    #[test]
    fn jacobian_is_the_derivative_of_forward() {
        let c = Chain::from_flat(&flat()).unwrap();
        let theta = [0.3, -0.7, 0.1, 0.5];
        let mut j = [0.0; 12];
        c.jacobian(&theta, &mut j);
        for i in 0..4 {
            let (mut hi, mut lo) = (theta, theta);
            hi[i] += 1e-6;
            lo[i] -= 1e-6;
            let (xh, xl) = (c.forward(&hi), c.forward(&lo));
            for r in 0..3 {
                let fd = (xh[r] - xl[r]) / 2e-6;
                assert!((j[r * 4 + i] - fd).abs() < 1e-7, "row {r} joint {i}: {} vs {fd}", j[r * 4 + i]);
            }
        }
    }

    #[test]
    fn link_lengths_do_not_depend_on_the_configuration() {
        let c = Chain::from_flat(&flat()).unwrap();
        let l = c.link_lengths();
        assert_eq!(l.len(), 4);
        // Joints 1 and 2 share their body origin but joint 1's anchor is 0.05 off it.
        assert!((l[1] - 0.05).abs() < 1e-12, "{l:?}");
        let mut rng = rng_from_seed(5);
        let first = c.points(&[0.0; 4])[0];
        for _ in 0..50 {
            let theta: Vec<f64> = (0..4).map(|_| uniform(&mut rng, -1.0, 1.0)).collect();
            let pts = c.points(&theta);
            for (k, w) in pts.windows(2).enumerate() {
                let d = crate::task_space::distance(&w[0], &w[1]);
                assert!((d - l[k]).abs() < 1e-12);
            }
            // The first anchor does not move, and the tip stays within the summed lengths of it.
            assert_eq!(pts[0], first);
            assert!(crate::task_space::distance(&pts[4], &first) <= l.iter().sum::<f64>() + 1e-12);
        }
    }

    #[test]
    fn bad_chains_are_named() {
        let e = Chain::from_flat(&[0.0; 10]).unwrap_err().to_string();
        assert!(e.contains("'chain' parameter of Arm") && e.contains("Got 10 numbers"), "{e}");
        let mut v = flat();
        v[13] = 1.0;
        v[14] = 1.0;
        let e = Chain::from_flat(&v).unwrap_err().to_string();
        assert!(e.contains("low < high") && e.contains("joint 0: [1, 1]"), "{e}");
        let mut v = flat();
        v[JOINT_LEN + 10..JOINT_LEN + 13].copy_from_slice(&[0.0; 3]);
        assert!(Chain::from_flat(&v).unwrap_err().to_string().contains("joint 1"));
        let mut v = flat();
        v[2] = f64::NAN;
        assert!(Chain::from_flat(&v).is_err());
    }

    #[test]
    fn chain_goals_lie_in_the_box_and_come_with_a_configuration_reaching_them() {
        let c = Chain::from_flat(&flat()).unwrap();
        let (low, high) = ([-0.5, -1.2, -0.6], [0.9, 0.3, 0.6]);
        let mut rng = rng_from_seed(8);
        let goals = crate::evaluation::reachable_cloud::chain_goals(&c, 1.0, &low, &high, 200, &mut rng).unwrap();
        assert_eq!(goals.len(), 200);
        for (g, theta) in &goals {
            assert!((0..3).all(|i| g[i] >= low[i] && g[i] <= high[i]));
            assert!(theta.iter().all(|t| t.abs() <= 1.0));
            assert_eq!(c.forward(theta), *g);
        }
        // A box the chain never reaches is refused, naming the bounds.
        let e = crate::evaluation::reachable_cloud::chain_goals(&c, 1.0, &[5.0; 3], &[6.0; 3], 10, &mut rng).unwrap_err().to_string();
        assert!(e.contains("goal_low/goal_high") && e.contains("reachable set"), "{e}");
    }
}
