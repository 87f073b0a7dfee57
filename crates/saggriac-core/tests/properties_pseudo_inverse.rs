//! Property tests of the pseudo-inverse: Moore-Penrose identities, rank deficiency, cutoffs.
//!
//! proptest chooses the shape of each case (sizes, dimensions, scales, adversarial modes, k);
//! bulk coordinates come from the crate's seeded generator with a proptest-chosen seed, which
//! keeps cases cheap to generate while the shape parameters still shrink.

mod common;

use nalgebra::DMatrix;
use proptest::prelude::*;

use common::cases;
use saggriac_core::local_model::{pinv_apply, pinv_apply_svd, pinv_apply_wide, FitFailure};

#[derive(Debug, Clone, Copy)]
enum Shape {
    Full,
    /// Rows parallel up to a relative perturbation of 1e-3 (condition number ~1e3).
    NearlyParallel,
    /// Rows exactly parallel: rank one (see `pseudo_inverse_of_rank_one_matrices`).
    Parallel,
    /// One row zero.
    ZeroRow,
    /// Some columns zero (joints that do not move the tip).
    ZeroColumns,
}

fn shaped(n: usize, v: &[f64], shape: Shape, exp: i32, c: f64) -> DMatrix<f64> {
    let scale = 10f64.powi(exp);
    let mut j = DMatrix::from_row_slice(2, n, &v[..2 * n]) * scale;
    match shape {
        Shape::Full => {}
        Shape::NearlyParallel | Shape::Parallel => {
            let mut row = j.row(0).clone_owned() * c;
            if let Shape::NearlyParallel = shape {
                for a in 0..n {
                    row[a] += 1e-3 * scale * v[2 * n + a];
                }
            }
            j.set_row(1, &row);
        }
        Shape::ZeroRow => j.row_mut(1).fill(0.0),
        Shape::ZeroColumns => {
            for a in (0..n).step_by(2) {
                j.column_mut(a).fill(0.0);
            }
        }
    }
    j
}

fn jacobian_with(shapes: impl Strategy<Value = Shape> + Clone + 'static) -> impl Strategy<Value = DMatrix<f64>> {
    (1usize..=20).prop_flat_map(move |n| (Just(n), prop::collection::vec(-1.0..1.0f64, 3 * n), shapes.clone(), -6i32..=6, -2.0..2.0f64)).prop_map(|(n, v, shape, exp, c)| shaped(n, &v, shape, exp, c))
}

fn jacobian() -> impl Strategy<Value = DMatrix<f64>> {
    jacobian_with(prop_oneof![Just(Shape::Full), Just(Shape::NearlyParallel), Just(Shape::ZeroRow), Just(Shape::ZeroColumns)])
}

type PinvApply = fn(&DMatrix<f64>, &[f64], f64, &mut [f64]) -> Result<(), FitFailure>;

/// J+ as a matrix, column by column (J+ dx is linear in dx).
fn pinv_matrix_with(apply: PinvApply, j: &DMatrix<f64>, rcond: f64) -> Result<DMatrix<f64>, FitFailure> {
    let (m, n) = j.shape();
    let mut p = DMatrix::zeros(n, m);
    for c in 0..m {
        let mut e = vec![0.0; m];
        e[c] = 1.0;
        let mut col = vec![0.0; n];
        apply(j, &e, rcond, &mut col)?;
        p.column_mut(c).copy_from_slice(&col);
    }
    Ok(p)
}

fn pinv_matrix(j: &DMatrix<f64>, rcond: f64) -> Result<DMatrix<f64>, FitFailure> {
    pinv_matrix_with(pinv_apply, j, rcond)
}

/// Singular values s1 >= s2 of a 2 x n matrix, from the eigenvalues of its 2 x 2 Gram matrix
/// (s2 is only accurate to about sqrt(eps) * s1, enough for the error bounds below).
fn singular_values_2xn(j: &DMatrix<f64>) -> (f64, f64) {
    let g = j * j.transpose();
    let (a, b, c) = (g[(0, 0)], g[(0, 1)], g[(1, 1)]);
    let l1 = 0.5 * (a + c) + (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let l2 = if l1 > 0.0 { ((a * c - b * b) / l1).max(0.0) } else { 0.0 };
    (l1.sqrt(), l2.sqrt())
}

proptest! {
    #![proptest_config(cases(512))]

    #[test]
    fn pseudo_inverse_identities(j in jacobian(), rcond in prop_oneof![Just(1e-2), 1e-12..1.0f64]) {
        if j.iter().all(|v| *v == 0.0) {
            prop_assert_eq!(pinv_matrix(&j, 1e-12).unwrap_err(), FitFailure::Degenerate);
            return Ok(());
        }
        // With a negligible cut-off J+ is the Moore-Penrose inverse: J J+ J = J. The SVD route
        // takes any cutoff (the J J^T route floors it at MIN_RCOND, tested separately).
        let p = pinv_matrix_with(pinv_apply_svd, &j, 1e-12).expect("non-zero finite J");
        let jn = j.norm();
        let err = (&j * &p * &j - &j).norm();
        prop_assert!(err <= 1e-9 * jn, "|J J+ J - J| = {} for |J| = {}", err, jn);
        // The symmetry of J J+ is as accurate as J+ itself: its error grows with the condition
        // number |J| |J+| (nalgebra's SVD has a backward error of ~1e-12 on nearly parallel rows).
        let jp = &j * &p;
        let cond = jn * p.norm();
        prop_assert!((&jp - jp.transpose()).norm() <= 1e-10 * cond, "J J+ not symmetric (condition {})", cond);

        // With any cut-off it is the Moore-Penrose inverse of a truncated J: J+ J J+ = J+, and
        // both products stay symmetric.
        let p = pinv_matrix(&j, rcond).expect("non-zero finite J");
        prop_assert!(p.iter().all(|v| v.is_finite()));
        let pn = p.norm();
        let err = (&p * &j * &p - &p).norm();
        prop_assert!(err <= 1e-9 * pn * pn * jn, "|J+ J J+ - J+| = {} for |J+| = {}", err, pn);
        let pj = &p * &j;
        prop_assert!((&pj - pj.transpose()).norm() <= 1e-10 * pn * jn, "J+ J not symmetric");
    }

    /// `pinv_apply_wide` (J+ through the eigen-decomposition of J J^T, what the local model
    /// uses) over every shape, rank one included, with cut-offs from 1e-6: it is the
    /// pseudo-inverse of J with singular values below rcond * s1 dropped, to the accuracy the
    /// squared condition number of J J^T allows, and it agrees with the SVD route away from the
    /// cut-off.
    #[test]
    fn wide_pseudo_inverse_identities(
        j in jacobian_with(prop_oneof![
            Just(Shape::Full),
            Just(Shape::NearlyParallel),
            Just(Shape::Parallel),
            Just(Shape::ZeroRow),
            Just(Shape::ZeroColumns),
        ]),
        rcond in prop_oneof![Just(1e-2), 1e-6..1.0f64],
    ) {
        if j.iter().all(|v| *v == 0.0) {
            prop_assert_eq!(pinv_matrix_with(pinv_apply_wide, &j, rcond).unwrap_err(), FitFailure::Degenerate);
            return Ok(());
        }
        let p = pinv_matrix_with(pinv_apply_wide, &j, rcond).expect("non-zero finite J");
        prop_assert!(p.iter().all(|v| v.is_finite()));
        let (s1, s2) = singular_values_2xn(&j);
        // s2 is surely dropped below 0.9 rcond s1, surely kept above 1.1 rcond s1.
        let maybe_dropped = s2 <= 1.1 * rcond * s1;
        let surely_dropped = s2 < 0.9 * rcond * s1;
        // Relative accuracy of J+ through J J^T: eps times the squared condition number of the
        // part of J that is kept.
        let s_kept = if surely_dropped { s1 } else { s2 };
        let rel = 1e-12 + 16.0 * f64::EPSILON * (s1 / s_kept).powi(2);
        let (jn, pn) = (j.norm(), p.norm());
        // J J+ J = J minus the dropped part, whose norm is s2 (known here to within
        // ~sqrt(eps) s1, the accuracy of s2 computed through J J^T).
        let err = (&j * &p * &j - &j).norm();
        let allowed = rel * jn + if maybe_dropped { s2 + 4.0 * f64::EPSILON.sqrt() * s1 } else { 0.0 };
        prop_assert!(err <= allowed, "|J J+ J - J| = {} > {} (s = {}, {}; rcond {})", err, allowed, s1, s2, rcond);
        let err = (&p * &j * &p - &p).norm();
        prop_assert!(err <= rel * pn * pn * jn, "|J+ J J+ - J+| = {} (s = {}, {}; rcond {})", err, s1, s2, rcond);
        let pj = &p * &j;
        prop_assert!((&pj - pj.transpose()).norm() <= rel * pn * jn, "J+ J not symmetric");
        // Same answer as the SVD route where the cut-off does not hesitate and the SVD is sound
        // (not on parallel rows, see below; s2 as computed here cannot tell rank one from
        // s2 < ~1e-8 s1).
        let near_cut = (0.5 * rcond * s1..=2.0 * rcond * s1).contains(&s2);
        let rank_one_ish = s2 <= 1e-6 * s1;
        if !near_cut && !rank_one_ish {
            let q = pinv_matrix(&j, rcond).expect("non-zero finite J");
            let diff = (&p - &q).norm();
            prop_assert!(diff <= 1e-9 * q.norm() + 4.0 * rel * q.norm(), "wide and SVD pseudo-inverses differ by {} (|J+| = {})", diff, q.norm());
        }
    }

    /// Exactly rank-one J with two non-zero rows. nalgebra 0.35's SVD gets these wrong for
    /// n >= ~7 columns (nalgebra issue 1172), which is why `pinv_apply` goes through J J^T for
    /// wide matrices.
    #[test]
    fn pseudo_inverse_of_rank_one_matrices(j in jacobian_with(Just(Shape::Parallel))) {
        if j.iter().all(|v| *v == 0.0) {
            return Ok(());
        }
        let p = pinv_matrix(&j, 1e-12).expect("non-zero finite J");
        let err = (&j * &p * &j - &j).norm();
        prop_assert!(err <= 1e-9 * j.norm(), "|J J+ J - J| = {} for |J| = {}", err, j.norm());
    }
}

/// Jacobian of the tip of a planar arm: column a is sum_{i >= a} l_i (-sin phi_i, cos phi_i).
fn arm_jacobian(lengths: &[f64], theta: &[f64]) -> DMatrix<f64> {
    let n = theta.len();
    let phi: Vec<f64> = theta
        .iter()
        .scan(0.0, |s, t| {
            *s += t;
            Some(*s)
        })
        .collect();
    DMatrix::from_fn(2, n, |r, a| (a..n).map(|i| if r == 0 { -lengths[i] * phi[i].sin() } else { lengths[i] * phi[i].cos() }).sum())
}

/// `pinv_apply_wide` works on J J^T, whose eigenvalues below ~eps s1^2 are rounding noise; a
/// cut-off below ~1e-8 would invert that noise (|J J+ J - J| / |J| = 0.48 for the rank-one
/// Jacobian of a straight arm at rcond = 1e-10), so the cutoff never goes below MIN_RCOND.
#[test]
fn wide_pseudo_inverse_with_a_tiny_cutoff() {
    let mut theta = vec![0.0; 15];
    theta[0] = 0.7;
    let j = arm_jacobian(&[50.0 / 15.0; 15], &theta);
    for rcond in [1e-2, 1e-6, 1e-10, 1e-12] {
        let p = pinv_matrix_with(pinv_apply_wide, &j, rcond).unwrap();
        let err = (&j * &p * &j - &j).norm() / j.norm();
        assert!(err < 1e-9, "rcond {rcond:e}: |J J+ J - J| / |J| = {err:.2e}");
    }
}
