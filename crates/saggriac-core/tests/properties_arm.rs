//! Property tests of the arm: forward kinematics against a closed form, micro-action bounds.
//!
//! proptest chooses the shape of each case (sizes, dimensions, scales, adversarial modes, k);
//! bulk coordinates come from the crate's seeded generator with a proptest-chosen seed, which
//! keeps cases cheap to generate while the shape parameters still shrink.

mod common;

use std::f64::consts::PI;

use proptest::prelude::*;

use common::cases;
use saggriac_core::body::arm::{Arm, ArmConfig};

/// Complex multiplication (re, im).
fn cmul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

fn arm_case() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    (1usize..=30).prop_flat_map(|n| (prop::collection::vec(1e-2..100.0f64, n), prop::collection::vec(-PI..PI, n)))
}

proptest! {
    #![proptest_config(cases(512))]

    /// x = sum_i l_i exp(i phi_i) with phi the cumulative sum of theta. The rotation e^{i phi_i}
    /// is built as the product of the joint rotations e^{i theta_1} ... e^{i theta_i}, not from
    /// the cumulative angle, so this is an independent computation.
    #[test]
    fn forward_kinematics_is_a_sum_of_rotations((lengths, theta) in arm_case()) {
        let arm = Arm::new(ArmConfig { link_lengths: lengths.clone(), ..ArmConfig::uniform(1, 1.0, PI, 0.1) }).unwrap();
        let x = arm.forward(&theta);
        let mut rot = (1.0, 0.0);
        let mut z = (0.0, 0.0);
        for (l, t) in lengths.iter().zip(&theta) {
            rot = cmul(rot, (t.cos(), t.sin()));
            z = (z.0 + l * rot.0, z.1 + l * rot.1);
        }
        let total: f64 = lengths.iter().sum();
        let tol = 1e-12 * total * lengths.len() as f64;
        prop_assert!((x[0] - z.0).abs() <= tol && (x[1] - z.1).abs() <= tol, "forward {:?} vs complex sum {:?}", x, z);
        prop_assert!(x[0].hypot(x[1]) <= total * (1.0 + 1e-12), "tip beyond the arm's reach");
    }

    /// A micro-action moves no joint more than max_joint_step, keeps every joint within its
    /// limit, reports the realised joint change, and its dx is the change of forward().
    #[test]
    fn micro_actions_respect_bounds(
        n in 1usize..=15,
        limit in 0.1..PI,
        max_step in 1e-3..0.5f64,
        commands in prop::collection::vec(prop::collection::vec(-2.0..2.0f64, 15), 1..40),
    ) {
        let mut arm = Arm::new(ArmConfig::uniform(n, 50.0, limit, max_step)).unwrap();
        for cmd in &commands {
            let before = arm.theta().to_vec();
            let x0 = arm.position();
            let mut d = cmd[..n].to_vec();
            let dx = arm.step(&mut d);
            let after = arm.theta().to_vec();
            for a in 0..n {
                prop_assert!(after[a].abs() <= limit, "joint {} at {} beyond {}", a, after[a], limit);
                prop_assert!(d[a].abs() <= max_step * (1.0 + 1e-12) + 1e-15, "joint {} moved {} > {}", a, d[a], max_step);
                prop_assert!((after[a] - before[a] - d[a]).abs() <= 1e-15, "reported change differs from realised");
            }
            let x1 = arm.forward(&after);
            prop_assert_eq!(arm.position(), x1);
            prop_assert!((dx[0] - (x1[0] - x0[0])).abs() <= 1e-12 && (dx[1] - (x1[1] - x0[1])).abs() <= 1e-12);
        }
    }
}
