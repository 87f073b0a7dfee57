//! Goal GAN's parameters (Florensa et al., ICML 2018).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, Shape, TeacherParams};
use crate::config::rules::{check_fields, open_closed, PROBABILITY, Rule};
use crate::error::{invalid, Num, Result};

/// Goal GAN's parameters (Florensa et al., ICML 2018).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GoalGanConfig {
    /// A told competence of at least this is a success (0.5, for competences in [0, 1]).
    pub success_threshold: f64,
    /// A goal of intermediate difficulty has a success rate in [r_min, r_max] (0.1, 0.9).
    pub r_min: f64,
    pub r_max: f64,
    /// Times each proposed goal is asked in a row, its success rate being theirs (2).
    pub n_rollouts: usize,
    /// Labelled goals between trainings of the GAN (100).
    pub update_size: usize,
    /// Steps of each training: one of the discriminator, one of the generator (250).
    pub gan_iterations: usize,
    /// Share of goals replayed from those labelled so far (1/3).
    pub p_old: f64,
    /// Dimension of the generator's noise (4).
    pub noise_dim: usize,
    /// Units of each of the two hidden layers of both networks (32; the paper's 128).
    pub hidden: usize,
    /// Adam's step size for both networks (0.001).
    pub learning_rate: f64,
    /// Where the box of the first goals (those before the first training) sits in each
    /// dimension, as a share of its width from low: 0.5, the box's centre.
    pub initial: f64,
    /// That box's width, as a share of each dimension's width: 1, the whole box (the first goals
    /// uniform in it, as before the parameter existed).
    pub initial_width: f64,
}

impl Default for GoalGanConfig {
    fn default() -> Self {
        GoalGanConfig { success_threshold: 0.5, r_min: 0.1, r_max: 0.9, n_rollouts: 2, update_size: 100, gan_iterations: 250, p_old: 1.0 / 3.0, noise_dim: 4, hidden: 32, learning_rate: 0.001, initial: 0.5, initial_width: 1.0 }
    }
}

impl TeacherParams for GoalGanConfig {
    const RULES: &'static [(&'static str, Rule)] = &[
        ("success_threshold", Rule::Finite),
        ("r_min", PROBABILITY),
        ("r_max", PROBABILITY),
        ("n_rollouts", Rule::Int(1, 255)),
        ("update_size", Rule::Int(1, 100_000)),
        ("gan_iterations", Rule::Int(0, 100_000)),
        ("p_old", PROBABILITY),
        ("noise_dim", Rule::Int(1, 1024)),
        ("hidden", Rule::Int(1, 1024)),
        ("learning_rate", open_closed(0.0, 1.0)),
        ("initial", PROBABILITY),
        ("initial_width", PROBABILITY),
    ];

    const PER_DIMENSION: &'static [(&'static str, Shape)] = &[("initial", Shape::Vector), ("initial_width", Shape::Vector)];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, float success_threshold, float r_min, float r_max);
        if self.r_min > self.r_max {
            return Err(invalid(o, "r_max", format!("a float >= r_min (r_min = {})", Num(self.r_min)), Num(self.r_max)));
        }
        check_fields!(o, r, self, int n_rollouts);
        // A goal's success rate is k / n_rollouts: none in [r_min, r_max] and no goal is ever
        // good, so the GAN would never train.
        let n = self.n_rollouts as f64;
        if !(0..=self.n_rollouts).any(|k| (self.r_min..=self.r_max).contains(&(k as f64 / n))) {
            return Err(invalid(o, "r_max", format!("a float such that [r_min, r_max] holds a success rate k / n_rollouts (r_min = {}, n_rollouts = {})", Num(self.r_min), self.n_rollouts), Num(self.r_max)));
        }
        check_fields!(o, r, self, int update_size, int gan_iterations, float p_old, int noise_dim, int hidden, float learning_rate, float initial, float initial_width);
        Ok(())
    }

    fn scaled_to_competences(self, lo: f64, hi: f64) -> Self {
        GoalGanConfig { success_threshold: lo + self.success_threshold * (hi - lo), ..self }
    }

    fn check_competences(&self, lo: f64, hi: f64, told: &str) -> Result<()> {
        if !(self.success_threshold > lo && self.success_threshold <= hi) {
            return Err(invalid(Self::CLASS, "success_threshold", format!("a float in ({}, {}] ({told}; a competence >= success_threshold is a success, so outside every attempt would fail, or succeed)", Num(lo), Num(hi)), Num(self.success_threshold)));
        }
        Ok(())
    }
}
