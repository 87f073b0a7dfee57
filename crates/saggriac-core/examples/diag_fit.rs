use nalgebra::DMatrix;
use saggriac_core::body::arm::{Arm, ArmConfig};
use saggriac_core::model::local_model::{LocalModel, LocalModelConfig};
use saggriac_core::model::memory::{IndexKind, SensorimotorMemory};
use saggriac_core::rng::{rng_from_seed, uniform};

fn main() {
    let mut arm = Arm::new(ArmConfig::uniform(15, 50.0, 1.57, 0.05)).unwrap();
    let mut r = rng_from_seed(1);
    let th0: Vec<f64> = (0..15).map(|_| uniform(&mut r, -0.3, 0.3)).collect();
    arm.set_theta(&th0);
    let mut mem = SensorimotorMemory::new(15, 2, IndexKind::BruteForce);
    for _ in 0..40 {
        let t = arm.theta().to_vec();
        let x = arm.position();
        let mut d: Vec<f64> = (0..15).map(|_| uniform(&mut r, -0.01, 0.01)).collect();
        let dx = arm.step(&mut d);
        mem.add(&t, &d, &dx, &x);
    }
    // true J at current theta
    let th = arm.theta().to_vec();
    let mut jt = DMatrix::zeros(2, 15);
    for a in 0..15 {
        let mut p = th.clone();
        p[a] += 1e-6;
        let (x1, x0) = (arm.forward(&p), arm.forward(&th));
        jt[(0, a)] = (x1[0] - x0[0]) / 1e-6;
        jt[(1, a)] = (x1[1] - x0[1]) / 1e-6;
    }
    for &(k, ridge) in &[(20usize, 1e-3), (30, 1e-3), (40, 1e-3), (30, 1e-1)] {
        let mut lm = LocalModel::new(15, 2, LocalModelConfig { k_neighbours: k, ridge, pinv_rcond: 1e-2, bandwidth: 0.0 });
        let mut nb = Vec::new();
        mem.knn(&th, k, &mut nb);
        lm.fit(&mem, &nb).unwrap();
        let j = lm.jacobian();
        let mut dth = vec![0.0; 15];
        lm.inverse(&[0.5, 0.0], &mut dth).unwrap();
        let v = nalgebra::DVector::from_vec(dth.clone());
        let real = &jt * &v;
        println!(
            "k {k} ridge {ridge}: |J-Jt|/|Jt| = {:.3}  real dx for (0.5,0): {:.3},{:.3} |dth|max {:.4}",
            (j - &jt).norm() / jt.norm(),
            real[0],
            real[1],
            dth.iter().fold(0.0f64, |m, x| m.max(x.abs()))
        );
    }
    let sv = jt.clone().svd(false, false).singular_values;
    println!("true singular values {sv:?}");
}
