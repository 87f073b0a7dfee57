//! Interest of a region (paper eq. 2): the absolute competence progress over the zeta most
//! recent goals attempted in it.

/// Interest of a time-ordered list of competences.
///
/// Eq. 2 compares the sum of the older half of the last zeta competences with the sum of the
/// newer half, divided by zeta. While a region holds fewer than zeta goals we use the window it
/// has (w = its size; an odd w drops the middle value so both halves have w/2 values) and divide
/// by w, so a young region is not penalised for its size. Fewer than 2 values give 0.
pub fn interest(competences: &[f64], zeta: usize) -> f64 {
    let w = competences.len().min(zeta);
    let half = w / 2;
    if half == 0 {
        return 0.0;
    }
    let window = &competences[competences.len() - w..];
    let older: f64 = window[..half].iter().sum();
    let newer: f64 = window[w - half..].iter().sum();
    (older - newer).abs() / w as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_cases() {
        // zeta = 4, last four: [-1, -0.8, -0.4, -0.2]: |(-1.8) - (-0.6)| / 4 = 0.3
        let c = [-1.0, -1.0, -0.8, -0.4, -0.2];
        assert!((interest(&c, 4) - 0.3).abs() < 1e-15);
        // decreasing competence gives the same interest (absolute value)
        let d = [-0.2, -0.4, -0.8, -1.0];
        assert!((interest(&d, 4) - 0.3).abs() < 1e-15);
        // constant competence: no progress
        assert_eq!(interest(&[-0.5; 30], 20), 0.0);
        // young region: 3 values, middle dropped: |-1 - 0| / 3
        assert!((interest(&[-1.0, -0.5, 0.0], 20) - 1.0 / 3.0).abs() < 1e-15);
        assert_eq!(interest(&[-1.0], 20), 0.0);
        assert_eq!(interest(&[], 20), 0.0);
    }
}
