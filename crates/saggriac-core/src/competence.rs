//! Competence of a reaching attempt (paper II.D.1 and eq. 7).

pub use crate::config::high_level::CompetenceConfig;

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

/// Competence gamma (section II.D.1): the cost clipped to min_C below, and 0 above eps_C.
pub fn competence(goal: &[f64], reached: &[f64], start: &[f64], cfg: &CompetenceConfig) -> f64 {
    clip(cost(goal, reached, start, cfg.min_c), cfg)
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
        let cfg = CompetenceConfig { min_c: -1.0, eps_c: -0.05 };
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
    }

    #[test]
    fn validation_prints_both_values() {
        let e = CompetenceConfig { min_c: -1.0, eps_c: -2.0 }.validate().unwrap_err();
        assert_eq!(e.to_string(), "The 'eps_c' parameter of Competence must be a float with min_c < eps_c < 0 (min_c = -1). Got -2 instead.");
    }
}
