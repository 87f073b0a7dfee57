//! SPDL's parameters (Klink et al., NeurIPS 2020 / JMLR 2021).

use serde::{Deserialize, Serialize};

use crate::config::teachers::{Registered, Shape, TeacherParams};
use crate::config::rules::{check_fields, COUNT, POSITIVE, Rule};
use crate::error::{invalid, Num, Result, MAX_COUNT};

/// Which of the papers' updates SPDL runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpdlForm {
    /// Klink et al., JMLR 2021: min KL(p || mu) s.t. E_p[competence] >= delta and
    /// KL(p || p_old) <= epsilon.
    Delta,
    /// Klink et al., NeurIPS 2020, as TeachMyAgent runs it: one natural-gradient step on
    /// E_p[competence] - alpha KL(p || mu) within KL(p_old || p) <= epsilon, alpha = alpha_zeta
    /// times the mean competence over KL(p || mu), 0 for the first alpha_offset updates.
    Alpha,
}

/// The covariance of SPDL's context distribution p.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpdlCovariance {
    /// One standard deviation per dimension (2 d parameters).
    Diagonal,
    /// A full covariance through its Cholesky factor (d + d (d + 1) / 2 parameters), as the
    /// papers' Gaussians: correlations are learnt, and a target's are matched.
    Full,
}

/// SPDL's parameters (Klink et al., NeurIPS 2020 / JMLR 2021), in the box scaled to [0, 1]. The
/// means and standard deviations are one number for every dimension here; a list, one per
/// dimension, and full covariances (`init_cov`, `target_cov`) are given beside
/// (`config::teachers::PerDimension`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpdlConfig {
    /// Mean of the initial distribution in every scaled dimension (0.5: the box's centre).
    pub init_mean: f64,
    /// Its standard deviation, in box widths (0.1, TeachMyAgent's initial distribution).
    pub init_std: f64,
    /// Mean of the target distribution mu in every scaled dimension (0.5).
    pub target_mean: f64,
    /// Its standard deviation, in box widths (0.25: TeachMyAgent's Gaussian for a uniform box).
    pub target_std: f64,
    /// Bound on KL(p_new || p_old) at each update (0.05).
    pub epsilon: f64,
    /// Least expected competence of a new distribution (0.5, for competences in [0, 1]).
    pub delta: f64,
    /// Told goals between updates (100).
    pub update_every: usize,
    /// Told goals before the first update (200, TeachMyAgent's offset of two periods).
    pub warmup: usize,
    /// The update: the JMLR paper's delta form (default) or the NeurIPS paper's alpha form.
    pub form: SpdlForm,
    /// p's covariance: diagonal (default) or full.
    pub covariance: SpdlCovariance,
    /// Alpha form: the first updates with alpha = 0 (0, TeachMyAgent's default).
    pub alpha_offset: usize,
    /// Alpha form: zeta, alpha KL(p || mu) as a share of the mean competence (0.05,
    /// TeachMyAgent's default).
    pub alpha_zeta: f64,
}

impl Default for SpdlConfig {
    fn default() -> Self {
        SpdlConfig {
            init_mean: 0.5,
            init_std: 0.1,
            target_mean: 0.5,
            target_std: 0.25,
            epsilon: 0.05,
            delta: 0.5,
            update_every: 100,
            warmup: 200,
            form: SpdlForm::Delta,
            covariance: SpdlCovariance::Diagonal,
            alpha_offset: 0,
            alpha_zeta: 0.05,
        }
    }
}

const MEAN: Rule = Rule::Float { lo: 0.0, lo_in: true, hi: 1.0, hi_in: true, note: "a position in the box scaled to [0, 1]" };
const STD: Rule = Rule::Float { lo: 1e-4, lo_in: true, hi: 10.0, hi_in: true, note: "box widths" };

impl TeacherParams for SpdlConfig {
    const RULES: &'static [(&'static str, Rule)] = &[
        ("init_mean", MEAN),
        ("init_std", STD),
        ("target_mean", MEAN),
        ("target_std", STD),
        ("epsilon", POSITIVE),
        ("delta", Rule::Finite),
        ("update_every", COUNT),
        ("warmup", Rule::Int(0, MAX_COUNT)),
        ("form", Rule::Choice),
        ("covariance", Rule::Choice),
        ("alpha_offset", Rule::Int(0, MAX_COUNT)),
        ("alpha_zeta", Rule::Float { lo: 0.0, lo_in: true, hi: f64::INFINITY, hi_in: false, note: "" }),
    ];

    const PER_DIMENSION: &'static [(&'static str, Shape)] = &[
        ("init_mean", Shape::Vector),
        ("init_std", Shape::Vector),
        ("target_mean", Shape::Vector),
        ("target_std", Shape::Vector),
        ("init_cov", Shape::Matrix),
        ("target_cov", Shape::Matrix),
    ];

    fn validate(&self) -> Result<()> {
        let (o, r) = (Self::CLASS, Self::RULES);
        check_fields!(o, r, self, float init_mean, float init_std, float target_mean, float target_std, float epsilon, float delta, int update_every, int warmup, int alpha_offset, float alpha_zeta);
        Ok(())
    }

    fn scaled_to_competences(self, lo: f64, hi: f64) -> Self {
        SpdlConfig { delta: lo + self.delta * (hi - lo), ..self }
    }

    fn check_competences(&self, lo: f64, hi: f64, told: &str) -> Result<()> {
        if self.form == SpdlForm::Alpha {
            // alpha = zeta * max(mean competence, 0) / KL: never above 0, p is never drawn to mu.
            if hi <= 0.0 {
                return Err(invalid(Self::CLASS, "form", format!("'delta' ({told}; the alpha form weighs KL(p || mu) by zeta times the mean competence clipped at 0, so with competences <= 0 it never moves p toward the target)"), "'alpha'"));
            }
            return Ok(());
        }
        if !(lo..=hi).contains(&self.delta) {
            return Err(invalid(Self::CLASS, "delta", format!("a float in [{}, {}] ({told}; the distribution moves only while the expected competence is >= delta, so outside it would never move, or never be held back)", Num(lo), Num(hi)), Num(self.delta)));
        }
        Ok(())
    }
}
