//! Interest of a region (paper eq. 2): the absolute competence progress over the zeta most
//! recent goals attempted in it.

pub use crate::config::high_level::InterestDivisor;

/// Interest of a time-ordered list of competences.
///
/// Eq. 2 compares the sum of the older half of the last zeta competences with the sum of the
/// newer half, divided by zeta. A region holding fewer than zeta values uses the window it has
/// (w = its size; an odd w drops the middle value so both halves have w/2 values), divided by
/// zeta as printed (`InterestDivisor::Zeta`) or by w (`InterestDivisor::Window`, saggriac <= 0.2).
/// `InterestDivisor::Printed` reads a full region's window as the printed index ranges do: the
/// last zeta + 1 values, the middle one dropped. Fewer than 2 values give 0.
pub fn interest(competences: &[f64], zeta: usize, divisor: InterestDivisor) -> f64 {
    let w = competences.len().min(divisor.window_len(zeta));
    let half = w / 2;
    if half == 0 {
        return 0.0;
    }
    let window = &competences[competences.len() - w..];
    let older: f64 = window[..half].iter().sum();
    let newer: f64 = window[w - half..].iter().sum();
    (older - newer).abs() / divisor.of(w, zeta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use InterestDivisor::{Printed, Window, Zeta};

    #[test]
    fn hand_computed_cases() {
        for d in [Zeta, Window] {
            // zeta = 4, last four: [-1, -0.8, -0.4, -0.2]: |(-1.8) - (-0.6)| / 4 = 0.3
            let c = [-1.0, -1.0, -0.8, -0.4, -0.2];
            assert!((interest(&c, 4, d) - 0.3).abs() < 1e-15);
            // decreasing competence gives the same interest (absolute value)
            let d4 = [-0.2, -0.4, -0.8, -1.0];
            assert!((interest(&d4, 4, d) - 0.3).abs() < 1e-15);
            // constant competence: no progress
            assert_eq!(interest(&[-0.5; 30], 20, d), 0.0);
            assert_eq!(interest(&[-1.0; 6], 20, d), 0.0);
            assert_eq!(interest(&[-1.0], 20, d), 0.0);
            assert_eq!(interest(&[], 20, d), 0.0);
        }
        // young region, 6 values, zeta = 20: |(-3) - 0| / 20 as printed, / 6 by its own window
        let young = [-1.0, -1.0, -1.0, 0.0, 0.0, 0.0];
        assert!((interest(&young, 20, Zeta) - 0.15).abs() < 1e-15);
        assert!((interest(&young, 20, Window) - 0.5).abs() < 1e-15);
        // 3 values, middle dropped: |-1 - 0| / 20 or / 3
        assert!((interest(&[-1.0, -0.5, 0.0], 20, Zeta) - 0.05).abs() < 1e-15);
        assert!((interest(&[-1.0, -0.5, 0.0], 20, Window) - 1.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn printed_index_ranges() {
        // zeta = 4, |R| = 6: the printed sums run over j = 2..4 and j = 4..6 (1-based), so C_4
        // cancels: |(C_2 + C_3) - (C_5 + C_6)| / 4. The last-zeta reading compares C_3 + C_4 with
        // C_5 + C_6.
        let c = [-0.9, -1.0, -0.8, -0.1, -0.4, -0.2];
        assert!((interest(&c, 4, Printed) - (-1.8f64 + 0.6).abs() / 4.0).abs() < 1e-15);
        assert!((interest(&c, 4, Zeta) - (-0.9f64 + 0.6).abs() / 4.0).abs() < 1e-15);
        // Up to zeta values the two read the same window.
        for n in 0..=20 {
            let v: Vec<f64> = (0..n).map(|i| -((i * 7 % 5) as f64) / 5.0).collect();
            assert_eq!(interest(&v, 20, Printed).to_bits(), interest(&v, 20, Zeta).to_bits(), "{n} values");
        }
        // With zeta + 1 values or more, the printed window reaches one value further back.
        let mut v = vec![-1.0];
        v.extend([0.0; 20]);
        assert_eq!(interest(&v, 20, Zeta), 0.0);
        assert!((interest(&v, 20, Printed) - 1.0 / 20.0).abs() < 1e-15);
    }
}
