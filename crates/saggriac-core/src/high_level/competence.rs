//! Competence of a reaching attempt (paper II.D.1 and eq. 7).

pub use crate::config::high_level::{CompetenceConfig, CompetenceKind};

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Cost of eq. 7: C = -D(x_g, x_f) / D(x_start, x_g); by the paper's convention C = min_C when
/// the start is the goal but the final position is not, and 0 when both coincide.
pub fn cost(goal: &[f64], reached: &[f64], start: &[f64], min_c: f64) -> f64 {
    let d_final = dist(goal, reached);
    let d_start = dist(start, goal);
    if d_start == 0.0 {
        return if d_final == 0.0 { 0.0 } else { min_c };
    }
    -d_final / d_start
}

/// The cost of `cfg.kind`: eq. 7, or the final distance over `reach`.
pub fn cost_of(cfg: &CompetenceConfig, reach: f64, goal: &[f64], reached: &[f64], start: &[f64]) -> f64 {
    match cfg.kind {
        CompetenceKind::Relative => cost(goal, reached, start, cfg.min_c),
        CompetenceKind::Absolute => -dist(goal, reached) / reach,
    }
}

/// Competence gamma (section II.D.1) of eq. 7: the cost clipped to min_C below, and 0 above
/// eps_C. (`cfg.kind` is not read: see `competence_of`.)
pub fn competence(goal: &[f64], reached: &[f64], start: &[f64], cfg: &CompetenceConfig) -> f64 {
    clip(cost(goal, reached, start, cfg.min_c), cfg)
}

/// Competence gamma with the cost `cfg.kind` names (`reach`: the arm's length, the scale of
/// the absolute cost).
pub fn competence_of(cfg: &CompetenceConfig, reach: f64, goal: &[f64], reached: &[f64], start: &[f64]) -> f64 {
    clip(cost_of(cfg, reach, goal, reached, start), cfg)
}

/// Apply the piecewise definition of gamma to a cost value.
pub fn clip(c: f64, cfg: &CompetenceConfig) -> f64 {
    if c.is_nan() || c <= cfg.min_c {
        cfg.min_c
    } else if c <= cfg.eps_c {
        c
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_cases() {
        let cfg = CompetenceConfig { min_c: -1.0, eps_c: -0.05, kind: CompetenceKind::Relative };
        // start 10 units away, end 2 units away: -0.2
        assert!((competence(&[10.0, 0.0], &[8.0, 0.0], &[0.0, 0.0], &cfg) + 0.2).abs() < 1e-15);
        // within tolerance: 0.3 / 10 = 0.03 < 0.05 -> reached
        assert_eq!(competence(&[10.0, 0.0], &[10.0, 0.3], &[0.0, 0.0], &cfg), 0.0);
        // moved away: -15/10 -> clipped to min_C
        assert_eq!(competence(&[10.0, 0.0], &[-5.0, 0.0], &[0.0, 0.0], &cfg), -1.0);
        // start at the goal, ended elsewhere: min_C; ended there: 0
        assert_eq!(competence(&[1.0, 1.0], &[1.0, 2.0], &[1.0, 1.0], &cfg), -1.0);
        assert_eq!(competence(&[1.0, 1.0], &[1.0, 1.0], &[1.0, 1.0], &cfg), 0.0);
        // exactly at eps_C is still "not reached" (C <= eps_C keeps C)
        assert_eq!(clip(-0.05, &cfg), -0.05);
        assert_eq!(clip(f64::NAN, &cfg), -1.0);
        // The relative kind is eq. 7.
        assert_eq!(competence_of(&cfg, 50.0, &[10.0, 0.0], &[8.0, 0.0], &[0.0, 0.0]), competence(&[10.0, 0.0], &[8.0, 0.0], &[0.0, 0.0], &cfg));
        // Absolute: the distance over the reach, wherever the attempt started.
        let abs = CompetenceConfig { kind: CompetenceKind::Absolute, ..cfg };
        // 2 units of 50 is within eps_C: reached.
        assert_eq!(competence_of(&abs, 50.0, &[10.0, 0.0], &[8.0, 0.0], &[0.0, 0.0]), 0.0);
        // 5 units from a start 1 unit away: eq. 7 would give min_C, here -5/50.
        assert!((competence_of(&abs, 50.0, &[10.0, 0.0], &[5.0, 0.0], &[9.0, 0.0]) + 0.1).abs() < 1e-15);
        assert_eq!(competence_of(&abs, 50.0, &[1.0, 1.0], &[1.0, 2.0], &[1.0, 1.0]), 0.0);
    }

    #[test]
    fn validation_prints_both_values() {
        let e = CompetenceConfig { min_c: -1.0, eps_c: -2.0, ..Default::default() }.validate().unwrap_err();
        assert_eq!(e.to_string(), "The 'eps_c' parameter of Competence must be a float with min_c < eps_c < 0 (min_c = -1). Got -2 instead.");
    }
}
