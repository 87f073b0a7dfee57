//! Property tests of competence and interest: both stay in their ranges.
//!
//! proptest chooses the shape of each case (sizes, dimensions, scales, adversarial modes, k);
//! bulk coordinates come from the crate's seeded generator with a proptest-chosen seed, which
//! keeps cases cheap to generate while the shape parameters still shrink.

mod common;

use proptest::prelude::*;

use common::cases;
use saggriac_core::high_level::competence::{competence, CompetenceConfig};
use saggriac_core::high_level::interest::{interest, InterestDivisor};

fn competence_config() -> impl Strategy<Value = CompetenceConfig> {
    (1e-6..10.0f64, 1e-6..0.999_999f64).prop_map(|(m, f)| CompetenceConfig { min_c: -m, eps_c: -m * f, ..Default::default() })
}

fn point2() -> impl Strategy<Value = [f64; 2]> {
    prop_oneof![
        (-100.0..100.0f64, -100.0..100.0f64).prop_map(|(a, b)| [a, b]),
        (-1e-9..1e-9f64, -1e-9..1e-9f64).prop_map(|(a, b)| [a, b]),
        (-1e12..1e12f64, -1e12..1e12f64).prop_map(|(a, b)| [a, b]),
        Just([0.0, 0.0]),
    ]
}

/// (goal, reached, start), with reached or start sometimes equal to the goal.
fn attempt() -> impl Strategy<Value = ([f64; 2], [f64; 2], [f64; 2])> {
    (point2(), point2(), point2(), 0u8..4).prop_map(|(g, r, s, tie)| match tie {
        0 => (g, g, s),
        1 => (g, r, g),
        2 => (g, g, g),
        _ => (g, r, s),
    })
}

proptest! {
    #![proptest_config(cases(512))]

    #[test]
    fn competence_in_range(cfg in competence_config(), (g, r, s) in attempt()) {
        let c = competence(&g, &r, &s, &cfg);
        prop_assert!(cfg.min_c <= c && c <= 0.0, "competence {} outside [{}, 0]", c, cfg.min_c);
        if r == g {
            prop_assert_eq!(c, 0.0, "reaching the goal exactly is full competence");
        } else if s == g {
            prop_assert_eq!(c, cfg.min_c, "starting at the goal and leaving it is the worst competence");
        }
    }

    #[test]
    fn competence_in_range_for_any_floats(
        cfg in competence_config(),
        v in prop::array::uniform6(prop::num::f64::ANY),
    ) {
        let (g, r, s) = ([v[0], v[1]], [v[2], v[3]], [v[4], v[5]]);
        let c = competence(&g, &r, &s, &cfg);
        prop_assert!(cfg.min_c <= c && c <= 0.0, "competence {} outside [{}, 0] for {:?}", c, cfg.min_c, v);
    }

    #[test]
    fn interest_is_bounded(
        vals in prop_oneof![
            prop::collection::vec(-1.0..=0.0f64, 0..80),
            prop::collection::vec(-1e6..1e6f64, 0..80),
            (1usize..80, -1.0..=0.0f64).prop_map(|(n, v)| vec![v; n]),
        ],
        zeta in 2usize..50,
        divisor in prop_oneof![Just(InterestDivisor::Zeta), Just(InterestDivisor::Window)],
    ) {
        let i = interest(&vals, zeta, divisor);
        prop_assert!(i.is_finite() && i >= 0.0, "interest {}", i);
        let window = &vals[vals.len() - vals.len().min(zeta)..];
        // The readings differ only in the denominator: zeta as printed, or the window's length.
        let other = interest(&vals, zeta, if divisor == InterestDivisor::Zeta { InterestDivisor::Window } else { InterestDivisor::Zeta });
        let (by_zeta, by_w) = if divisor == InterestDivisor::Zeta { (i, other) } else { (other, i) };
        prop_assert!((by_zeta * zeta as f64 - by_w * window.len() as f64).abs() <= 1e-9 * (by_w * window.len() as f64).max(1e-300), "zeta {} vs window {}", by_zeta, by_w);
        let max = window.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let min = window.iter().cloned().fold(f64::INFINITY, f64::min);
        if window.len() < 2 || max == min {
            prop_assert_eq!(i, 0.0);
        } else {
            // |sum of h older - sum of h newer| / w with 2h <= w: at most half the spread.
            let bound = (max - min) / 2.0;
            prop_assert!(i <= bound * (1.0 + 1e-12) + 1e-12 * max.abs().max(min.abs()), "interest {} > (max - min) / 2 = {}", i, bound);
        }
    }
}
