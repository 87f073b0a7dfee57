//! Points of the task space. The run loop takes task spaces of 1 to `MAX_TASK_DIM` dimensions
//! (the planar arm's 2, the spatial arm's 3, a user's environment's own). A point is a fixed
//! array whose unused coordinates stay exactly 0: the hot loop never allocates for a position,
//! and sums over the unused coordinates only add exact zeros, so a 2-D task computes the same
//! numbers, bit for bit, as with 2-element arrays.

/// Largest task-space dimension of the run loop (goal selectors alone take any dimension).
pub const MAX_TASK_DIM: usize = 3;

/// A position or a displacement in the task space.
pub type Point = [f64; MAX_TASK_DIM];

/// The point with these coordinates (at most `MAX_TASK_DIM` of them), the others 0.
pub fn point(coords: &[f64]) -> Point {
    assert!(coords.len() <= MAX_TASK_DIM, "a task-space point has at most {MAX_TASK_DIM} coordinates, got {}", coords.len());
    let mut p = [0.0; MAX_TASK_DIM];
    p[..coords.len()].copy_from_slice(coords);
    p
}

/// Euclidean length.
pub fn norm(p: &Point) -> f64 {
    let mut s = 0.0;
    for v in p {
        s += v.powi(2);
    }
    s.sqrt()
}

/// Euclidean distance.
pub fn distance(a: &Point, b: &Point) -> f64 {
    norm(&sub(a, b))
}

/// a - b.
pub fn sub(a: &Point, b: &Point) -> Point {
    std::array::from_fn(|i| a[i] - b[i])
}

/// a + f (b - a): the point a fraction f of the way from a to b.
pub fn lerp(a: &Point, b: &Point, f: f64) -> Point {
    std::array::from_fn(|i| a[i] + f * (b[i] - a[i]))
}

/// Desired displacement of a reaching step: length min(v, |target - x|) towards the target
/// (the paper's x_c - x_g is a sign typo, see docs/parameters.md). The learner's reacher and the
/// evaluation's test reaches both ask for it.
pub fn desired_step(x: &Point, target: &Point, v: f64) -> Point {
    let e = sub(target, x);
    let d = norm(&e);
    if d == 0.0 {
        return [0.0; MAX_TASK_DIM];
    }
    let s = v.min(d) / d;
    e.map(|v| v * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn desired_step_points_at_the_target_and_stops_there() {
        let s = desired_step(&[0.0, 0.0, 0.0], &[3.0, 4.0, 0.0], 0.5);
        assert!((s[0] - 0.3).abs() < 1e-15 && (s[1] - 0.4).abs() < 1e-15 && s[2] == 0.0);
        let s = desired_step(&[0.0, 0.0, 0.0], &[0.03, 0.04, 0.0], 0.5);
        assert!((s[0] - 0.03).abs() < 1e-15 && (s[1] - 0.04).abs() < 1e-15);
        assert_eq!(desired_step(&[1.0, 1.0, 0.0], &[1.0, 1.0, 0.0], 0.5), [0.0, 0.0, 0.0]);
        let s = desired_step(&[1.0, 0.0, 0.0], &[2.0, 2.0, 2.0], 0.3);
        assert!((s[0] - 0.1).abs() < 1e-15 && (s[1] - 0.2).abs() < 1e-15 && (s[2] - 0.2).abs() < 1e-15);
    }

    #[test]
    fn padding_is_exact() {
        let (a, b) = (point(&[0.1, -0.7]), point(&[2.3, 0.4]));
        assert_eq!(a[2], 0.0);
        // The 2-D formula the loop used before points had a third coordinate.
        let d2 = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        assert_eq!(distance(&a, &b).to_bits(), d2.to_bits());
        assert_eq!(lerp(&a, &b, 0.4)[2], 0.0);
        assert_eq!(sub(&a, &b), [a[0] - b[0], a[1] - b[1], 0.0]);
    }

    #[test]
    #[should_panic(expected = "at most 3 coordinates")]
    fn too_many_coordinates() {
        point(&[1.0, 2.0, 3.0, 4.0]);
    }
}
