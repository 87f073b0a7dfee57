//! ADR's parameters (Akkaya et al., 2019, Algorithm 1).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, Shape, TeacherParams};
use crate::config::rules::{check_fields, open_closed, COUNT, PROBABILITY, Rule};
use crate::error::{invalid, Num, Result};

/// Parameters of Automatic Domain Randomization (Akkaya et al., 2019, Algorithm 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AdrConfig {
    /// p_b: the share of goals with one dimension set to one of its bounds (the paper's 0.5).
    pub boundary_prob: f64,
    /// m: the boundary performances averaged before a bound moves (TeachMyAgent's 10; the paper
    /// sets it per experiment).
    pub buffer_size: usize,
    /// t_L: a mean competence at a bound <= t_low moves it inwards. Competence units.
    pub t_low: f64,
    /// t_H: a mean competence at a bound >= t_high moves it outwards. Competence units.
    pub t_high: f64,
    /// Delta: how far a bound moves, as a share of its dimension's width (the paper sets one
    /// per randomized parameter: a list, one per dimension, is taken too).
    pub step: f64,
    /// Where the initial region sits in each dimension, as a share of its width from low: 0.5
    /// is the box's centre, 0 its low corner.
    pub initial: f64,
    /// The initial region's width, as a share of each dimension's width: 0 (the default) is the
    /// paper's single initial value.
    pub initial_width: f64,
}

impl Default for AdrConfig {
    fn default() -> Self {
        AdrConfig { boundary_prob: 0.5, buffer_size: 10, t_low: 0.2, t_high: 0.8, step: 0.05, initial: 0.5, initial_width: 0.0 }
    }
}

impl TeacherParams for AdrConfig {
    const RULES: &'static [(&'static str, Rule)] = &[
        ("boundary_prob", PROBABILITY),
        ("buffer_size", COUNT),
        ("t_low", Rule::Finite),
        ("t_high", Rule::Finite),
        ("step", open_closed(0.0, 1.0)),
        ("initial", PROBABILITY),
        ("initial_width", PROBABILITY),
    ];

    const PER_DIMENSION: &'static [(&'static str, Shape)] = &[("initial", Shape::Vector), ("initial_width", Shape::Vector), ("step", Shape::Vector)];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, float boundary_prob, int buffer_size, float t_low, float t_high);
        if self.t_low >= self.t_high {
            return Err(invalid(o, "t_low", format!("a float < t_high (t_high = {})", Num(self.t_high)), Num(self.t_low)));
        }
        check_fields!(o, r, self, float step, float initial, float initial_width);
        Ok(())
    }

    fn scaled_to_competences(self, lo: f64, hi: f64) -> Self {
        let at = |share: f64| lo + share * (hi - lo);
        AdrConfig { t_low: at(self.t_low), t_high: at(self.t_high), ..self }
    }

    fn check_competences(&self, lo: f64, hi: f64, told: &str) -> Result<()> {
        if self.t_high > hi {
            return Err(invalid(Self::CLASS, "t_high", format!("a float <= {} ({told}, and a bound grows only when the mean competence at it is >= t_high)", Num(hi)), Num(self.t_high)));
        }
        if self.t_low < lo {
            return Err(invalid(Self::CLASS, "t_low", format!("a float >= {} ({told}, and a bound shrinks only when the mean competence at it is <= t_low)", Num(lo)), Num(self.t_low)));
        }
        Ok(())
    }
}
