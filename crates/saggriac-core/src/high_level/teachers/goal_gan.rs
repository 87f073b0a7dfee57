//! Goal GAN (Florensa, Held, Geng & Abbeel, "Automatic goal generation for reinforcement
//! learning agents", ICML 2018).
//!
//! Goals of intermediate difficulty (GOID) are those whose success rate lies in [r_min, r_max].
//! Each goal the teacher proposes is asked `n_rollouts` times in a row; a told competence of at
//! least `success_threshold` is a success, and once the goal's `n_rollouts` competences are told
//! its success rate labels it (good: a GOID). Every `update_size` labelled goals that hold at
//! least one good one, a least-squares GAN with goal labels is trained for `gan_iterations`
//! steps (the paper's a = -1, b = 1, c = 0): the discriminator scores good goals 1, bad goals
//! and generated goals -1, and the generator is trained toward a score of 0. Goals come from the
//! generator (noise of dimension `noise_dim`, two hidden layers of `hidden` ReLU units), and with
//! probability `p_old` from the goals labelled so far (replay). Until the first training, goals
//! are uniform in the first goals' box (`initial`, `initial_width`, per dimension if given: the
//! whole box by default; the paper starts from goals its initial policy reaches). Inside the
//! teacher the box is scaled to [-1, 1].

use std::collections::VecDeque;

use nalgebra::DMatrix;

use crate::config::high_level::check_bounds;
use crate::error::Result;
use crate::config::teachers::TeacherParams;
use crate::high_level::goal_selection::{load_state, save_state, GoalChoice, GoalSelector, Mode};
use crate::high_level::teachers::mlp::Mlp;
use crate::rng::{child_seed, index, normal, rng_from_seed, unit, CoreRng};

pub use crate::config::teachers::GoalGanConfig;
use crate::config::teachers::PerDimension;

/// Goals asked but not yet labelled: each with the successes told so far.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct Pending {
    goal: Vec<f64>,
    successes: Vec<bool>,
}

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct GoalGanState {
    rng: CoreRng,
    gen: Mlp,
    disc: Mlp,
    queue: VecDeque<(Vec<f64>, u8)>,
    pending: VecDeque<Pending>,
    /// This round's labelled goals (scaled, flattened) and labels.
    round_goals: Vec<f64>,
    round_labels: Vec<bool>,
    /// Every goal labelled so far (scaled, flattened): the replay buffer.
    old_goals: Vec<f64>,
    trainings: u64,
}

pub struct GoalGan {
    cfg: GoalGanConfig,
    low: Vec<f64>,
    high: Vec<f64>,
    /// The first goals' box in each dimension, as shares of its width from low: [from, to].
    first: Vec<(f64, f64)>,
    st: GoalGanState,
}

/// Pending goals kept at most (a goal never told again is dropped, oldest first).
const MAX_PENDING: usize = 10_000;

impl GoalGan {
    pub fn new(low: &[f64], high: &[f64], cfg: GoalGanConfig, seed: u64) -> Result<Self> {
        Self::with_dims(low, high, cfg, &PerDimension::default(), seed)
    }

    /// Goal GAN with the first goals' box (`initial`, `initial_width`) given per dimension where
    /// `dims` has them (checked by `PerDimension::check`).
    pub fn with_dims(low: &[f64], high: &[f64], cfg: GoalGanConfig, dims: &PerDimension, seed: u64) -> Result<Self> {
        check_bounds("GoalGanSelector", low, high)?;
        cfg.validate()?;
        let d = low.len();
        let mut init = rng_from_seed(child_seed(seed, 1));
        let gen = Mlp::new(&Self::gen_sizes(&cfg, d), cfg.learning_rate, &mut init);
        let disc = Mlp::new(&Self::disc_sizes(&cfg, d), cfg.learning_rate, &mut init);
        let st = GoalGanState {
            rng: rng_from_seed(seed),
            gen,
            disc,
            queue: VecDeque::new(),
            pending: VecDeque::new(),
            round_goals: Vec::new(),
            round_labels: Vec::new(),
            old_goals: Vec::new(),
            trainings: 0,
        };
        let (centre, width) = (dims.vector("initial", cfg.initial, d), dims.vector("initial_width", cfg.initial_width, d));
        let first = centre.iter().zip(&width).map(|(c, w)| ((c - 0.5 * w).max(0.0), (c + 0.5 * w).min(1.0))).collect();
        Ok(GoalGan { cfg, low: low.to_vec(), high: high.to_vec(), first, st })
    }

    fn gen_sizes(cfg: &GoalGanConfig, d: usize) -> Vec<usize> {
        vec![cfg.noise_dim, cfg.hidden, cfg.hidden, d]
    }
    fn disc_sizes(cfg: &GoalGanConfig, d: usize) -> Vec<usize> {
        vec![d, cfg.hidden, cfg.hidden, 1]
    }

    /// Trainings of the GAN so far.
    pub fn n_trainings(&self) -> u64 {
        self.st.trainings
    }

    fn to_scaled(&self, p: &[f64]) -> Vec<f64> {
        p.iter().zip(self.low.iter().zip(&self.high)).map(|(v, (l, h))| (2.0 * (v - l) / (h - l) - 1.0).clamp(-1.0, 1.0)).collect()
    }
    fn to_box(&self, s: &[f64]) -> Vec<f64> {
        s.iter().zip(self.low.iter().zip(&self.high)).map(|(v, (l, h))| (l + (v.clamp(-1.0, 1.0) + 1.0) / 2.0 * (h - l)).clamp(*l, *h)).collect()
    }

    /// `n` generated goals, scaled to [-1, 1] (tanh of the generator's output), with the noise
    /// and the generator's tape for training.
    fn generate(&mut self, n: usize) -> (DMatrix<f64>, DMatrix<f64>, crate::high_level::teachers::mlp::Tape) {
        let rng = &mut self.st.rng;
        let z = DMatrix::from_fn(n, self.cfg.noise_dim, |_, _| normal(rng));
        let (out, tape) = self.st.gen.forward(&z);
        (out.map(f64::tanh), z, tape)
    }

    /// Generated goals scaled to [-1, 1], for tests and studies.
    pub fn generated(&mut self, n: usize) -> Vec<Vec<f64>> {
        let (g, _, _) = self.generate(n);
        g.row_iter().map(|r| self.to_box(&r.iter().copied().collect::<Vec<f64>>())).collect()
    }

    fn train(&mut self) {
        let d = self.low.len();
        let n = self.st.round_labels.len();
        let real = DMatrix::from_row_slice(n, d, &self.st.round_goals);
        let target: Vec<f64> = self.st.round_labels.iter().map(|g| if *g { 1.0 } else { -1.0 }).collect();
        for _ in 0..self.cfg.gan_iterations {
            // Discriminator: real goals to their label's score (b = 1 good, a = -1 bad),
            // generated ones to a = -1.
            let (fake, _, _) = self.generate(n);
            let (dr, tr) = self.st.disc.forward(&real);
            let gr = DMatrix::from_fn(n, 1, |i, _| 2.0 * (dr[(i, 0)] - target[i]) / n as f64);
            let (mut grad, _) = self.st.disc.backward(&tr, &gr);
            let (df, tf) = self.st.disc.forward(&fake);
            let gf = df.map(|v| 2.0 * (v + 1.0) / n as f64);
            let (grad_f, _) = self.st.disc.backward(&tf, &gf);
            grad.iter_mut().zip(&grad_f).for_each(|(a, b)| *a += b);
            self.st.disc.adam_step(&grad);
            // Generator: its goals' score toward c = 0.
            let (fake, _, gtape) = self.generate(n);
            let (df, tf) = self.st.disc.forward(&fake);
            let (_, gx) = self.st.disc.backward(&tf, &df.map(|v| 2.0 * v / n as f64));
            let gout = gx.zip_map(&fake, |g, t| g * (1.0 - t * t));
            let (ggrad, _) = self.st.gen.backward(&gtape, &gout);
            self.st.gen.adam_step(&ggrad);
        }
        self.st.trainings += 1;
    }

    fn matches(&self, a: &[f64], b: &[f64]) -> bool {
        // Tolerant of a round trip through float32 (Syllabus's boxes).
        a.iter().zip(b).zip(self.low.iter().zip(&self.high)).all(|((x, y), (l, h))| (x - y).abs() <= 1e-6 * (h - l).max(x.abs()).max(y.abs()))
    }
}

impl GoalSelector for GoalGan {
    fn goal_box(&self) -> (&[f64], &[f64]) {
        (&self.low, &self.high)
    }
    fn sample(&mut self) -> GoalChoice {
        if let Some((goal, mode)) = self.st.queue.pop_front() {
            return GoalChoice { goal, mode: if mode == 1 { Mode::Interest } else if mode == 2 { Mode::Global } else { Mode::Initial }, region: None };
        }
        let d = self.low.len();
        let n_old = self.st.old_goals.len() / d;
        let (scaled, mode) = if self.st.trainings == 0 {
            // Uniform in the first goals' box ([0, 1] by default: 2 u - 1 over the whole box).
            let first = &self.first;
            ((0..d).map(|i| 2.0 * (first[i].0 + (first[i].1 - first[i].0) * unit(&mut self.st.rng)) - 1.0).collect::<Vec<f64>>(), 0u8)
        } else if n_old > 0 && unit(&mut self.st.rng) < self.cfg.p_old {
            let i = index(&mut self.st.rng, n_old);
            (self.st.old_goals[i * d..(i + 1) * d].to_vec(), 2)
        } else {
            let (g, _, _) = self.generate(1);
            (g.row(0).iter().copied().collect(), 1)
        };
        let goal = self.to_box(&scaled);
        for _ in 1..self.cfg.n_rollouts {
            self.st.queue.push_back((goal.clone(), mode));
        }
        self.st.pending.push_back(Pending { goal: goal.clone(), successes: Vec::new() });
        if self.st.pending.len() > MAX_PENDING {
            self.st.pending.pop_front();
        }
        GoalChoice { goal, mode: if mode == 1 { Mode::Interest } else if mode == 2 { Mode::Global } else { Mode::Initial }, region: None }
    }
    fn update(&mut self, point: &[f64], competence: f64) -> Option<usize> {
        let k = self.st.pending.iter().position(|p| self.matches(&p.goal, point))?;
        let p = &mut self.st.pending[k];
        p.successes.push(competence >= self.cfg.success_threshold);
        if p.successes.len() >= self.cfg.n_rollouts {
            let p = self.st.pending.remove(k).expect("found above");
            let rate = p.successes.iter().filter(|s| **s).count() as f64 / p.successes.len() as f64;
            let scaled = self.to_scaled(&p.goal);
            self.st.round_goals.extend_from_slice(&scaled);
            self.st.old_goals.extend_from_slice(&scaled);
            self.st.round_labels.push(self.cfg.r_min <= rate && rate <= self.cfg.r_max);
            if self.st.round_labels.len() >= self.cfg.update_size {
                if self.st.round_labels.iter().any(|g| *g) {
                    self.train();
                }
                self.st.round_goals.clear();
                self.st.round_labels.clear();
            }
        }
        None
    }
    fn save(&self) -> Option<Vec<u8>> {
        save_state(&self.st)
    }
    fn load(&mut self, state: &[u8]) -> bool {
        let Some(st) = load_state::<GoalGanState>(state) else { return false };
        let d = self.low.len();
        let fits = st.gen.shapes_fit(&Self::gen_sizes(&self.cfg, d))
            && st.disc.shapes_fit(&Self::disc_sizes(&self.cfg, d))
            && st.round_goals.len() == st.round_labels.len() * d
            && st.old_goals.len() % d == 0
            && st.queue.iter().all(|(g, _)| g.len() == d)
            && st.pending.iter().all(|p| p.goal.len() == d);
        if fits {
            self.st = st;
        }
        fits
    }
}

build_by_new!(GoalGanConfig => GoalGan, box, per_dimension);

#[cfg(test)]
mod tests {
    use super::*;

    /// A disc of solvable goals around the box's centre whose radius grows with practice: a
    /// goal at distance r succeeds with probability 1 well inside, 0 well outside, and in
    /// between over a band of width 0.1; the radius grows by 2e-5 with every success.
    struct Disc {
        radius: f64,
    }
    impl Disc {
        fn p(&self, g: &[f64]) -> f64 {
            let r = (g[0].powi(2) + g[1].powi(2)).sqrt();
            ((self.radius + 0.05 - r) / 0.1).clamp(0.0, 1.0)
        }
    }

    #[test]
    fn trained_generator_proposes_mostly_goals_of_intermediate_difficulty() {
        let cfg = GoalGanConfig::default();
        let mut t = GoalGan::new(&[-1.0, -1.0], &[1.0, 1.0], cfg, 4).unwrap();
        let mut disc = Disc { radius: 0.2 };
        let mut rng = rng_from_seed(11);
        for _ in 0..6000 {
            let g = t.sample().goal;
            let s = unit(&mut rng) < disc.p(&g);
            if s {
                disc.radius = (disc.radius + 2e-5).min(0.9);
            }
            t.update(&g, if s { 1.0 } else { 0.0 });
        }
        assert!(t.n_trainings() >= 5, "{}", t.n_trainings());
        let goid = |gs: &[Vec<f64>], disc: &Disc| gs.iter().filter(|g| (0.1..=0.9).contains(&disc.p(g))).count() as f64 / gs.len() as f64;
        let generated = t.generated(2000);
        let uniform: Vec<Vec<f64>> = (0..2000).map(|_| vec![2.0 * unit(&mut rng) - 1.0, 2.0 * unit(&mut rng) - 1.0]).collect();
        let (share, base) = (goid(&generated, &disc), goid(&uniform, &disc));
        let mean: Vec<f64> = (0..2).map(|i| generated.iter().map(|g| g[i]).sum::<f64>() / 2000.0).collect();
        let radii: Vec<f64> = generated.iter().take(10).map(|g| (g[0].powi(2) + g[1].powi(2)).sqrt()).collect();
        assert!(share > 0.5 && share > 3.0 * base, "generated {share}, uniform {base}, radius {}, mean {mean:?} radii {radii:?}", disc.radius);
    }

    #[test]
    fn the_first_goals_are_uniform_in_their_box_per_dimension() {
        let cfg = GoalGanConfig { update_size: 10, gan_iterations: 5, hidden: 8, ..GoalGanConfig::default() };
        let dims = PerDimension(vec![("initial".into(), vec![0.1, 0.5]), ("initial_width".into(), vec![0.2, 1.0])]);
        let mut t = GoalGan::with_dims(&[0.0, -1.0], &[2.0, 1.0], cfg, &dims, 3).unwrap();
        let goals: Vec<Vec<f64>> = (0..400).map(|_| t.sample().goal).collect();
        assert_eq!(t.n_trainings(), 0);
        // x in [0, 0.2] of [0, 2] = [0, 0.4]; y over all of [-1, 1].
        assert!(goals.iter().all(|g| (0.0..=0.4).contains(&g[0])));
        let (lo, hi) = goals.iter().fold((1.0f64, -1.0f64), |(a, b), g| (a.min(g[1]), b.max(g[1])));
        assert!(lo < -0.9 && hi > 0.9, "{lo} {hi}");
        // The default box is the whole box (benchmarks/bench_teacher_bits.py checks its goals
        // against those before the parameters existed); given per dimension, the same.
        let (mut a, mut b) = (GoalGan::new(&[0.0, -1.0], &[2.0, 1.0], cfg, 3).unwrap(), GoalGan::with_dims(&[0.0, -1.0], &[2.0, 1.0], cfg, &PerDimension(vec![("initial_width".into(), vec![1.0, 1.0])]), 3).unwrap());
        for _ in 0..50 {
            assert_eq!(a.sample().goal, b.sample().goal);
        }
    }

    #[test]
    fn save_and_load_continue_exactly() {
        let cfg = GoalGanConfig { update_size: 10, gan_iterations: 5, hidden: 8, ..GoalGanConfig::default() };
        let mut a = GoalGan::new(&[0.0, 2.0, -3.0], &[1.0, 5.0, 0.0], cfg, 7).unwrap();
        // Success on every other try below 0.5: rates of 1/2 there, goals of intermediate difficulty.
        let mut k = 0;
        let mut c = |g: &[f64]| {
            k += 1;
            if g[0] < 0.5 && k % 2 == 0 { 1.0 } else { 0.0 }
        };
        for _ in 0..137 {
            let g = a.sample().goal;
            a.update(&g, c(&g));
        }
        assert!(a.n_trainings() > 0);
        let mut b = GoalGan::new(&[0.0, 2.0, -3.0], &[1.0, 5.0, 0.0], cfg, 0).unwrap();
        assert!(b.load(&a.save().unwrap()));
        for _ in 0..150 {
            let (ga, gb) = (a.sample().goal, b.sample().goal);
            assert_eq!(ga, gb);
            let v = c(&ga);
            a.update(&ga, v);
            b.update(&gb, v);
        }
        let other = GoalGanConfig { hidden: 9, ..cfg };
        assert!(!GoalGan::new(&[0.0, 2.0, -3.0], &[1.0, 5.0, 0.0], other, 0).unwrap().load(&a.save().unwrap()));
    }
}
