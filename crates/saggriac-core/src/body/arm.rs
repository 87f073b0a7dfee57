//! The simulated arm: n revolute joints in series, base at the origin, joint angles relative to
//! the previous link, rest pose straight along +x. The paper's arm (Fig. 2) is planar; the
//! spatial variant moves in 3-D, its joints turning alternately about the local z axis (yaw) and
//! the local y axis (pitch). A chain (`crate::body::chain`) is any serial arm of hinges in 3-D, such as
//! a MuJoCo model's.

use crate::body::chain::Chain;
use crate::body::Body;
pub use crate::config::body::{ArmConfig, ArmKind};
use crate::error::Result;
use crate::rng::{normal, rng_from_seed, CoreRng};
use crate::task_space::{sub, Point, MAX_TASK_DIM};

/// What a checkpoint keeps of an arm: joints, last reading, noise generator, link lengths (a
/// link may have changed during the run). The arm's own encoding: `Body::save` gives its bytes.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct ArmState {
    pub theta: Vec<f64>,
    pub x: Point,
    pub rng: CoreRng,
    pub link_lengths: Vec<f64>,
}

/// The arm: geometry plus its current joint state.
#[derive(Debug, Clone)]
pub struct Arm {
    cfg: ArmConfig,
    theta: Vec<f64>,
    /// The last position reading (the true position when there is no sensor noise).
    x: Point,
    rng: CoreRng,
    /// A chain's kinematics, built once from `cfg.chain`.
    chain: Option<Chain>,
}

impl Arm {
    pub fn new(cfg: ArmConfig) -> Result<Self> {
        cfg.validate()?;
        let n = cfg.link_lengths.len();
        let rng = rng_from_seed(cfg.noise_seed);
        let chain = cfg.chain.as_ref().map(Chain::new);
        let mut arm = Arm { cfg, theta: vec![0.0; n], x: [0.0; MAX_TASK_DIM], rng, chain };
        arm.reset();
        Ok(arm)
    }

    pub fn config(&self) -> &ArmConfig {
        &self.cfg
    }
    pub fn n_joints(&self) -> usize {
        self.theta.len()
    }
    pub fn total_length(&self) -> f64 {
        self.cfg.link_lengths.iter().sum()
    }
    pub fn theta(&self) -> &[f64] {
        &self.theta
    }
    pub fn position(&self) -> Point {
        self.x
    }
    pub fn task_dim(&self) -> usize {
        self.cfg.kind.task_dim()
    }

    /// Back to the rest pose (all joints at 0: straight along +x). Not a micro-action.
    pub fn reset(&mut self) {
        self.theta.iter_mut().for_each(|t| *t = 0.0);
        self.x = self.read(self.forward(&self.theta));
    }

    /// A position reading: the true position plus sensor noise, if any.
    fn read(&mut self, mut x: Point) -> Point {
        let s = self.cfg.sensor_noise;
        if s > 0.0 {
            for v in x.iter_mut().take(self.task_dim()) {
                *v += s * normal(&mut self.rng);
            }
        }
        x
    }

    fn state(&self) -> ArmState {
        ArmState { theta: self.theta.clone(), x: self.x, rng: self.rng.clone(), link_lengths: self.cfg.link_lengths.clone() }
    }
    /// Restore a saved state; false if it is not an arm's or belongs to an arm with another
    /// number of joints.
    fn load_state(&mut self, bytes: &[u8]) -> bool {
        let Ok(s) = postcard::from_bytes::<ArmState>(bytes) else { return false };
        if s.theta.len() != self.theta.len() || s.link_lengths.len() != self.theta.len() {
            return false;
        }
        self.theta.copy_from_slice(&s.theta);
        self.x = s.x;
        self.rng = s.rng.clone();
        self.cfg.link_lengths = s.link_lengths;
        true
    }

    /// Change one link's length (a body that changes during a run).
    pub fn set_link_length(&mut self, link: usize, length: f64) {
        self.cfg.link_lengths[link] = length;
        self.x = self.read(self.forward(&self.theta));
    }

    /// Put the arm in a given configuration (clipped to the joint limits).
    pub fn set_theta(&mut self, theta: &[f64]) {
        let lim = self.cfg.joint_limit;
        for (t, &v) in self.theta.iter_mut().zip(theta) {
            *t = v.clamp(-lim, lim);
        }
        self.x = self.read(self.forward(&self.theta));
    }

    /// The Jacobian of `forward` (task_dim x n, row-major) where it is written out: the planar
    /// arm and chains. False for the spatial arm (callers differentiate numerically).
    pub fn jacobian(&self, theta: &[f64], out: &mut [f64]) -> bool {
        match (self.cfg.kind, &self.chain) {
            (ArmKind::Planar, _) => {
                planar_jacobian(&self.cfg.link_lengths, theta, out);
                true
            }
            (ArmKind::Chain, Some(chain)) => {
                chain.jacobian(theta, out);
                true
            }
            _ => false,
        }
    }

    /// `forward` at theta with joint i set to `values[i]`, for every joint i, into `out[i]` (the
    /// same bits as `forward` gives each, in about half its time; a finite-difference Jacobian's
    /// positions). False for a chain.
    pub fn forward_moved(&self, theta: &[f64], values: &[f64], out: &mut [Point]) -> bool {
        let Some(start) = Link::start(self.cfg.kind) else { return false };
        forward_moved_from(start, &self.cfg.link_lengths, theta, values, out);
        true
    }

    /// End-effector position for a configuration.
    pub fn forward(&self, theta: &[f64]) -> Point {
        match self.cfg.kind {
            ArmKind::Planar => planar_forward(&self.cfg.link_lengths, theta),
            ArmKind::Spatial => spatial_forward(&self.cfg.link_lengths, theta),
            ArmKind::Chain => self.chain.as_ref().expect("a validated chain arm has its chain").forward(theta),
        }
    }

    /// Execute one micro-action. The command is first scaled down (keeping its direction) so no
    /// joint moves more than `max_joint_step`, then the new angles are clipped to the joint
    /// limits. Writes the realised joint change into `dtheta` and returns the realised dx.
    pub fn step(&mut self, dtheta: &mut [f64]) -> Point {
        let max_abs = dtheta.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        let scale = if max_abs > self.cfg.max_joint_step { self.cfg.max_joint_step / max_abs } else { 1.0 };
        let lim = self.cfg.joint_limit;
        let noise = self.cfg.motor_noise;
        for (t, d) in self.theta.iter_mut().zip(dtheta.iter_mut()) {
            let cmd = if noise > 0.0 { *d * scale + noise * normal(&mut self.rng) } else { *d * scale };
            let target = (*t + cmd).clamp(-lim, lim);
            *d = target - *t;
            *t = target;
        }
        let x_new = self.read(self.forward(&self.theta));
        let dx = sub(&x_new, &self.x);
        self.x = x_new;
        dx
    }
}

/// Planar arm: x = sum_i l_i (cos phi_i, sin phi_i), phi_i = theta_1 + ... + theta_i.
/// Planar arm: d x / d theta_i = -sum_{j >= i} l_j sin(phi_j), d y / d theta_i = sum_{j >= i}
/// l_j cos(phi_j), phi_j the absolute angle of link j. Row-major 2 x n into `out`.
pub(crate) fn planar_jacobian(links: &[f64], theta: &[f64], out: &mut [f64]) {
    let n = theta.len();
    let mut phi = 0.0;
    for (i, (l, t)) in links.iter().zip(theta).enumerate() {
        phi += t;
        let (s, c) = phi.sin_cos();
        out[i] = -l * s;
        out[n + i] = l * c;
    }
    for i in (0..n.saturating_sub(1)).rev() {
        out[i] += out[i + 1];
        out[n + i] += out[n + i + 1];
    }
}

/// What the links so far leave for the next: the planar arm's absolute angle and position, the
/// spatial arm's frame (link direction, y and z axes) and position.
#[derive(Clone, Copy)]
enum Link {
    Planar(f64, Point),
    Spatial([[f64; 3]; 3], Point),
}

impl Link {
    fn start(kind: ArmKind) -> Option<Link> {
        match kind {
            ArmKind::Planar => Some(Link::Planar(0.0, [0.0; MAX_TASK_DIM])),
            ArmKind::Spatial => Some(Link::Spatial([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [0.0; MAX_TASK_DIM])),
            ArmKind::Chain => None,
        }
    }

    /// Joint i at angle t, then link i of length l.
    #[inline]
    fn add(&mut self, i: usize, l: f64, t: f64) {
        match self {
            Link::Planar(phi, x) => {
                *phi += t;
                let (s, c) = phi.sin_cos();
                x[0] += l * c;
                x[1] += l * s;
            }
            Link::Spatial([e0, e1, e2], x) => {
                let (s, c) = t.sin_cos();
                if i % 2 == 0 {
                    // R Rz(t): e0' = c e0 + s e1, e1' = c e1 - s e0.
                    let (a, b) = (*e0, *e1);
                    *e0 = std::array::from_fn(|k| c * a[k] + s * b[k]);
                    *e1 = std::array::from_fn(|k| c * b[k] - s * a[k]);
                } else {
                    // R Ry(t): e0' = c e0 - s e2, e2' = s e0 + c e2.
                    let (a, b) = (*e0, *e2);
                    *e0 = std::array::from_fn(|k| c * a[k] - s * b[k]);
                    *e2 = std::array::from_fn(|k| s * a[k] + c * b[k]);
                }
                for k in 0..3 {
                    x[k] += l * e0[k];
                }
            }
        }
    }

    fn tip(&self) -> Point {
        match self {
            Link::Planar(_, x) | Link::Spatial(_, x) => *x,
        }
    }
}

/// The arm's position at `theta`, link by link from `start`.
fn forward_from(start: Link, links: &[f64], theta: &[f64]) -> Point {
    let mut link = start;
    for (i, (l, t)) in links.iter().zip(theta).enumerate() {
        link.add(i, *l, *t);
    }
    link.tip()
}

/// `forward_from` at theta with joint i set to `values[i]`, for every i, into `out[i]`. The
/// links before joint i are those of theta, so their state is kept rather than recomputed:
/// about half the sines and cosines, the same operations in the same order (the same bits).
fn forward_moved_from(start: Link, links: &[f64], theta: &[f64], values: &[f64], out: &mut [Point]) {
    let n = links.len().min(theta.len());
    let mut before = Vec::with_capacity(n);
    let mut link = start;
    for i in 0..n {
        before.push(link);
        link.add(i, links[i], theta[i]);
    }
    for i in 0..n {
        if values[i].to_bits() == theta[i].to_bits() {
            out[i] = link.tip();
            continue;
        }
        let mut moved = before[i];
        moved.add(i, links[i], values[i]);
        for j in i + 1..n {
            moved.add(j, links[j], theta[j]);
        }
        out[i] = moved.tip();
    }
}

fn planar_forward(links: &[f64], theta: &[f64]) -> Point {
    forward_from(Link::Planar(0.0, [0.0; MAX_TASK_DIM]), links, theta)
}

/// Spatial arm: the link frame R starts as the identity; joint i turns it by theta_i about its
/// own z axis (even i) or y axis (odd i), then link i adds l_i times R's first column (the link
/// direction) to the position.
fn spatial_forward(links: &[f64], theta: &[f64]) -> Point {
    forward_from(Link::start(ArmKind::Spatial).expect("the spatial arm has links"), links, theta)
}

impl Body for Arm {
    fn n_joints(&self) -> usize {
        Arm::n_joints(self)
    }
    fn theta(&self) -> &[f64] {
        Arm::theta(self)
    }
    fn task_dim(&self) -> usize {
        Arm::task_dim(self)
    }
    fn position(&self) -> Point {
        Arm::position(self)
    }
    fn reset(&mut self) {
        Arm::reset(self)
    }
    fn set_theta(&mut self, theta: &[f64]) {
        Arm::set_theta(self, theta)
    }
    fn forward(&self, theta: &[f64]) -> Option<Point> {
        // Within the limits, as a placement would be.
        let lim = self.config().joint_limit;
        if theta.iter().all(|t| t.abs() <= lim) {
            return Some(Arm::forward(self, theta));
        }
        let clipped: Vec<f64> = theta.iter().map(|t| t.clamp(-lim, lim)).collect();
        Some(Arm::forward(self, &clipped))
    }
    fn forward_moved(&self, theta: &[f64], values: &[f64], out: &mut [Point]) -> bool {
        // Only inside the limits, where `forward` does not clip.
        let lim = self.config().joint_limit;
        let inside = |v: &[f64]| v.len() == self.n_joints() && v.iter().all(|t| t.abs() <= lim);
        inside(theta) && inside(values) && out.len() >= self.n_joints() && Arm::forward_moved(self, theta, values, out)
    }
    fn jacobian(&self, theta: &[f64], out: &mut [f64]) -> bool {
        // Only inside the limits, where placements do not clip.
        let lim = self.config().joint_limit;
        theta.iter().all(|t| t.abs() < lim) && Arm::jacobian(self, theta, out)
    }
    fn step(&mut self, dtheta: &mut [f64]) -> Point {
        Arm::step(self, dtheta)
    }
    fn scratch(&self) -> Option<Box<dyn Body>> {
        Some(Box::new(self.clone()))
    }
    fn forgets_on_reset(&self) -> bool {
        // Noise draws advance the arm's generator: the next evaluation depends on this one's.
        self.config().motor_noise == 0.0 && self.config().sensor_noise == 0.0
    }
    fn set_link_length(&mut self, link: usize, length: f64) -> bool {
        if self.config().kind == ArmKind::Chain {
            return false;
        }
        Arm::set_link_length(self, link, length);
        true
    }
    fn save(&self) -> Option<Vec<u8>> {
        postcard::to_stdvec(&self.state()).ok()
    }
    fn load(&mut self, state: &[u8]) -> bool {
        self.load_state(state)
    }
}

/// An arm's bytes as checkpoints of format 5 and older held them: its state inline in the
/// checkpoint. Read, it gives the bytes `Body::save` writes today.
pub struct InlineState(pub Vec<u8>);

impl<'de> serde::Deserialize<'de> for InlineState {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let s = ArmState::deserialize(d)?;
        postcard::to_stdvec(&s).map(InlineState).map_err(serde::de::Error::custom)
    }
}

impl From<InlineState> for Vec<u8> {
    fn from(s: InlineState) -> Self {
        s.0
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn planar_jacobian_is_the_derivative_of_forward() {
        let a = Arm::new(ArmConfig::uniform(7, 21.0, 1.5, 0.05)).unwrap();
        let theta = [0.3, -0.2, 0.9, 0.1, -1.1, 0.5, 0.05];
        let mut j = [0.0; 14];
        assert!(a.jacobian(&theta, &mut j));
        for i in 0..7 {
            let (mut hi, mut lo) = (theta, theta);
            hi[i] += 1e-6;
            lo[i] -= 1e-6;
            let (xh, xl) = (a.forward(&hi), a.forward(&lo));
            for r in 0..2 {
                let fd = (xh[r] - xl[r]) / 2e-6;
                assert!((j[r * 7 + i] - fd).abs() < 1e-6, "row {r} joint {i}: {} vs {fd}", j[r * 7 + i]);
            }
        }
    }

    use super::*;
    use std::f64::consts::PI;

    fn arm(n: usize) -> Arm {
        Arm::new(ArmConfig::uniform(n, 50.0, PI, 0.1)).unwrap()
    }

    #[test]
    fn rest_pose_is_straight_along_x() {
        let a = arm(15);
        let x = a.position();
        assert!((x[0] - 50.0).abs() < 1e-12 && x[1].abs() < 1e-12);
    }

    #[test]
    fn two_link_closed_form() {
        // Classic 2-link formula: x = l1 cos t1 + l2 cos(t1 + t2).
        let a = Arm::new(ArmConfig { link_lengths: vec![3.0, 2.0], ..ArmConfig::uniform(1, 1.0, PI, 1.0) }).unwrap();
        for &(t1, t2) in &[(0.3, -1.1), (1.5, 2.0), (-2.5, 0.7)] {
            let x = a.forward(&[t1, t2]);
            let ex = [3.0 * f64::cos(t1) + 2.0 * f64::cos(t1 + t2), 3.0 * f64::sin(t1) + 2.0 * f64::sin(t1 + t2)];
            assert!((x[0] - ex[0]).abs() < 1e-12 && (x[1] - ex[1]).abs() < 1e-12);
        }
    }

    #[test]
    fn uniform_bend_lies_on_a_circle_arc() {
        // Equal bends of a chain of equal links: the tip is a chord sum with a closed form.
        let n = 15;
        let a = arm(n);
        let alpha = 0.1;
        let theta = vec![alpha; n];
        let x = a.forward(&theta);
        let l = 50.0 / n as f64;
        let (mut ex, mut ey) = (0.0, 0.0);
        // sum_{k=1..n} l e^{i k alpha} = l e^{i alpha} (1 - e^{i n alpha}) / (1 - e^{i alpha})
        let num = (n as f64 * alpha / 2.0).sin() / (alpha / 2.0).sin();
        let ang = (n as f64 + 1.0) * alpha / 2.0;
        ex += l * num * ang.cos();
        ey += l * num * ang.sin();
        assert!((x[0] - ex).abs() < 1e-9 && (x[1] - ey).abs() < 1e-9, "{x:?} vs {ex},{ey}");
    }

    #[test]
    fn step_bounds_and_limits() {
        let mut a = Arm::new(ArmConfig::uniform(3, 3.0, 0.5, 0.1)).unwrap();
        let mut d = vec![1.0, 0.05, -0.5];
        a.step(&mut d);
        // scaled by 0.1: (0.1, 0.005, -0.05)
        assert!((d[0] - 0.1).abs() < 1e-15 && (d[1] - 0.005).abs() < 1e-15 && (d[2] + 0.05).abs() < 1e-15);
        for _ in 0..20 {
            let mut d = vec![0.1, 0.1, 0.1];
            a.step(&mut d);
        }
        assert!(a.theta().iter().all(|t| (*t - 0.5).abs() < 1e-12));
        let mut d = vec![0.1, 0.0, 0.0];
        let dx = a.step(&mut d);
        assert_eq!(d[0], 0.0);
        assert_eq!(dx, [0.0, 0.0, 0.0]);
    }

    fn spatial(links: Vec<f64>) -> Arm {
        Arm::new(ArmConfig { kind: ArmKind::Spatial, link_lengths: links, ..ArmConfig::uniform(1, 1.0, PI, 1.0) }).unwrap()
    }

    #[test]
    fn spatial_rest_pose_and_single_joints() {
        let a = spatial(vec![2.0, 3.0]);
        assert_eq!(a.position(), [5.0, 0.0, 0.0]);
        assert_eq!(a.task_dim(), 3);
        // Yaw of the first joint turns the whole arm in the (x, y) plane.
        let x = a.forward(&[0.4, 0.0]);
        assert!((x[0] - 5.0 * 0.4f64.cos()).abs() < 1e-12 && (x[1] - 5.0 * 0.4f64.sin()).abs() < 1e-12 && x[2] == 0.0);
        // Pitch of the second joint lifts the second link out of the plane (towards -z).
        let x = a.forward(&[0.0, 0.7]);
        assert!((x[0] - (2.0 + 3.0 * 0.7f64.cos())).abs() < 1e-12 && x[1].abs() < 1e-12 && (x[2] + 3.0 * 0.7f64.sin()).abs() < 1e-12);
    }

    /// The frame update against a product of rotation matrices built by nalgebra.
    #[test]
    fn spatial_forward_matches_rotation_matrices() {
        use nalgebra::{Rotation3, Vector3};
        let links: Vec<f64> = (0..9).map(|i| 1.0 + 0.3 * i as f64).collect();
        let a = spatial(links.clone());
        let mut rng = rng_from_seed(11);
        for _ in 0..50 {
            let theta: Vec<f64> = (0..links.len()).map(|_| crate::rng::uniform(&mut rng, -PI, PI)).collect();
            let mut r = Rotation3::identity();
            let mut p = Vector3::zeros();
            for (i, (l, t)) in links.iter().zip(&theta).enumerate() {
                let axis = if i % 2 == 0 { Vector3::z_axis() } else { Vector3::y_axis() };
                r *= Rotation3::from_axis_angle(&axis, *t);
                p += r * Vector3::new(*l, 0.0, 0.0);
            }
            let x = a.forward(&theta);
            for k in 0..3 {
                assert!((x[k] - p[k]).abs() < 1e-10, "{x:?} vs {p:?}");
            }
            // Rotations keep the distance to the base within the arm's length.
            assert!(p.norm() <= links.iter().sum::<f64>() + 1e-9);
        }
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = Arm::new(ArmConfig::uniform(3, 3.0, 0.0, 0.1)).unwrap_err();
        assert_eq!(e.to_string(), "The 'joint_limit' parameter of Arm must be a float in (0, 3.141592653589793]. Got 0 instead.");
    }
}
