use super::*;

/// Choosing among candidates: uniform before the first split; then mode 1 favours the
/// candidates in the leaf of high interest, and mode 3 takes the one in the leaf of lowest
/// mean competence.
#[test]
fn chooses_among_candidates_by_their_leaves() {
    let cfg = RegionTreeConfig { g_max: 20, zeta: 10, min_child: 3, ..Default::default() };
    let mut s = SaggRiac::new(&[0.0, 0.0], &[1.0, 1.0], cfg, ModeProbabilities::default(), 3).unwrap();
    let cands = vec![vec![0.1, 0.5], vec![0.9, 0.5]];
    let first = s.choose(&cands).unwrap();
    assert_eq!(first.mode, Mode::Initial);
    // Left half: competence rising (interest); right half: flat at -0.9 (no interest, lowest).
    let mut r = rng_from_seed(5);
    for i in 0..60 {
        s.update(&[uniform(&mut r, 0.0, 0.5), uniform(&mut r, 0.0, 1.0)], -1.0 + i as f64 / 60.0);
        s.update(&[uniform(&mut r, 0.5, 1.0), uniform(&mut r, 0.0, 1.0)], -0.9);
    }
    assert!(s.tree.leaves().len() >= 2);
    let (mut left, mut by_mode) = (0, std::collections::HashMap::new());
    for _ in 0..2000 {
        let c = s.choose(&cands).unwrap();
        assert!(c.goal == cands[0] || c.goal == cands[1]);
        assert_eq!(c.region, Some(s.tree.leaf_of(&c.goal)));
        *by_mode.entry(c.mode as u8).or_insert(0) += 1;
        if c.mode == Mode::Interest && c.goal == cands[0] {
            left += 1;
        }
        if c.mode == Mode::LowestCompetence {
            assert_eq!(c.goal, cands[1], "the right half has the lowest mean competence");
        }
    }
    let interest = by_mode[&(Mode::Interest as u8)];
    assert!((1250..1550).contains(&interest), "{interest} of 2000 in mode 1 (p = 0.7)");
    assert!(left as f64 > 0.9 * interest as f64, "mode 1 chose the learnable half {left} of {interest} times");
    // A selector without regions cannot choose.
    let mut random = RandomGoals::new(&[0.0, 0.0], &[1.0, 1.0], 1).unwrap();
    assert!(random.choose(&cands).is_none());
}

/// Competence on a toy task: the left quarter of [0,1]^2 improves with practice, the rest is
/// hopeless (always min_C). SAGG-RIAC must concentrate its goals where progress is.
#[test]
fn concentrates_on_the_learnable_region() {
    let mut s = SaggRiac::new(&[0.0, 0.0], &[1.0, 1.0], RegionTreeConfig::default(), ModeProbabilities::default(), 7).unwrap();
    let mut practice = 0.0;
    let mut inside = 0;
    let n = 4000;
    for i in 0..n {
        let g = s.sample();
        let c = if g.goal[0] < 0.25 {
            practice += 1.0;
            // noisy progress: competence rises with practice
            -1.0 / (1.0 + 0.02 * practice) * (0.8 + 0.4 * ((i * 7919) % 100) as f64 / 100.0)
        } else {
            -1.0
        };
        s.update(&g.goal, c.max(-1.0));
        if i >= n / 2 && g.goal[0] < 0.25 {
            inside += 1;
        }
    }
    let share = inside as f64 / (n / 2) as f64;
    assert!(share > 0.5, "share of goals in the learnable quarter: {share}");
}

#[test]
fn same_seed_same_goals() {
    let mk = || SaggRiac::new(&[0.0], &[1.0], RegionTreeConfig { g_max: 10, zeta: 4, min_child: 2, ..Default::default() }, ModeProbabilities::default(), 3).unwrap();
    let (mut a, mut b) = (mk(), mk());
    for i in 0..500 {
        let (ga, gb) = (a.sample(), b.sample());
        assert_eq!(ga, gb);
        let c = -((i % 7) as f64) / 7.0 * ga.goal[0];
        a.update(&ga.goal, c);
        b.update(&gb.goal, c);
    }
}

/// A tree of two leaves: the left half learnable (rising competence, high interest), the
/// right half flat at -0.9 (no interest, the lowest mean). The paper's mode 3 draws in the
/// right half; `InterestWorst` in the left, about its worst goal (planted at (0.2, 0.3)).
fn two_halves(mode3: Mode3Config) -> SaggRiac {
    let cfg = RegionTreeConfig { g_max: 20, zeta: 10, min_child: 3, ..Default::default() };
    let mut s = SaggRiac::new(&[0.0, 0.0], &[1.0, 1.0], cfg, ModeProbabilities { p_interest: 0.0, p_global: 0.0, p_lowest: 1.0 }, 3).unwrap().with_mode3(mode3).unwrap();
    let mut r = rng_from_seed(5);
    s.update(&[0.2, 0.3], -1.0);
    for i in 0..60 {
        s.update(&[uniform(&mut r, 0.0, 0.5), uniform(&mut r, 0.0, 1.0)], -0.99 + i as f64 / 60.0);
        s.update(&[uniform(&mut r, 0.5, 1.0), uniform(&mut r, 0.0, 1.0)], -0.9);
    }
    s
}

#[test]
fn mode3_interest_worst_aims_near_the_worst_goal_of_an_interesting_leaf() {
    let paper = two_halves(Mode3Config::default());
    let leaves = paper.tree.leaves().to_vec();
    assert!(leaves.len() >= 2);
    let lowest = paper.lowest_leaf();
    assert!(paper.tree.region(lowest).low[0] >= 0.5, "the right half has the lowest mean");
    let mut paper = paper;
    for _ in 0..500 {
        let c = paper.sample();
        assert_eq!((c.mode, c.region), (Mode::LowestCompetence, Some(lowest)));
        assert!(c.goal[0] >= 0.5);
    }
    let sigma = 0.05;
    let mut s = two_halves(Mode3Config { reading: Mode3Reading::InterestWorst, sigma });
    let worst_leaf = s.tree.leaf_of(&[0.2, 0.3]);
    let (mut near, mut in_worst, mut left, n) = (0, 0, 0, 2000);
    for _ in 0..n {
        let c = s.sample();
        assert_eq!(c.mode, Mode::LowestCompetence);
        let leaf = c.region.unwrap();
        let r = s.tree.region(leaf);
        assert!(c.goal.iter().zip(r.low.iter().zip(&r.high)).all(|(g, (l, h))| l <= g && g <= h), "clipped to its leaf");
        assert!(r.interest > s.tree.min_leaf_interest(), "drawn by interest: never a leaf of least interest ({:?})", c.goal);
        left += usize::from(c.goal[0] < 0.5);
        if leaf == worst_leaf {
            in_worst += 1;
            if (c.goal[0] - 0.2).hypot(c.goal[1] - 0.3) < 3.0 * sigma {
                near += 1;
            }
        }
    }
    assert!(in_worst > 0 && left > n * 9 / 10, "{in_worst} in the worst goal's leaf, {left} of {n} in the learnable half");
    // Within 3 sd in each of 2 dimensions: about 99 % of an unclipped Gaussian's draws.
    assert!(near as f64 > 0.95 * in_worst as f64, "{near} of {in_worst} near the worst goal");
    // Choosing among candidates: the one nearest the worst goal of the drawn leaf.
    let cands = vec![vec![0.4, 0.9], vec![0.21, 0.31], vec![0.9, 0.5]];
    for _ in 0..200 {
        let c = s.choose(&cands).unwrap();
        assert_eq!(c.mode, Mode::LowestCompetence);
        if c.region == Some(worst_leaf) && s.tree.leaf_of(&cands[0]) == worst_leaf {
            assert_eq!(c.goal, cands[1]);
        }
        assert!(s.tree.region(c.region.unwrap()).interest > s.tree.min_leaf_interest());
    }
}

#[test]
fn mode3_parameters_are_checked() {
    let bad = |sigma: f64| Mode3Config { reading: Mode3Reading::InterestWorst, sigma }.validate().unwrap_err().to_string();
    for v in [0.0, -0.1, 1.5, f64::NAN, f64::INFINITY] {
        let e = bad(v);
        assert!(e.starts_with("The 'mode3_sigma' parameter of SaggRiac must be a float in (0, 1] (a share of the box's width). Got "), "{e}");
    }
    assert!(Mode3Config { reading: Mode3Reading::InterestWorst, sigma: 1.0 }.validate().is_ok());
    let e = Mode3Config { reading: Mode3Reading::LowestCompetence, sigma: 0.5 }.validate().unwrap_err().to_string();
    assert!(e.starts_with("The 'mode3_sigma' parameter of SaggRiac must be left at its default") && e.contains("'lowest_competence'") && e.ends_with("Got 0.5 instead."), "{e}");
    let e = Mode3Reading::parse("SaggRiac", "worst").unwrap_err().to_string();
    assert!(e.contains("'mode3'") && e.contains("'lowest_competence'") && e.contains("Got 'worst'"), "{e}");
    assert_eq!(Mode3Reading::parse("X", "interest_worst").unwrap().name(), "interest_worst");
}

#[test]
fn probabilities_must_sum_to_one() {
    let e = ModeProbabilities { p_interest: 0.7, p_global: 0.2, p_lowest: 0.2 }.validate().unwrap_err();
    assert!(e.to_string().contains("p_interest + p_global + p_lowest = 1"), "{e}");
}
