//! Goal selection on its own (ask/tell): any learner asks for a goal, tries it, and tells the
//! competence it obtained. This is how later work uses SAGG-RIAC as a curriculum "teacher". The
//! wrapper checks every input, and keeps the history of what was asked and told.

use crate::error::{Error, Result};
use crate::goal_selection::{GoalChoice, GoalSelector, ModeProbabilities, RandomGoals, SaggRiac};
use crate::region_tree::RegionTreeConfig;

pub struct AskTell {
    selector: Box<dyn GoalSelector>,
    /// Sampled goals, row by row, with their mode and region (-1: none).
    pub asked: Vec<f64>,
    pub asked_mode: Vec<u8>,
    pub asked_region: Vec<i64>,
    /// Told goals, row by row, with their competence and the region that recorded it.
    pub told: Vec<f64>,
    pub told_competence: Vec<f64>,
    pub told_region: Vec<i64>,
}

impl AskTell {
    pub fn new(selector: Box<dyn GoalSelector>) -> Self {
        AskTell { selector, asked: Vec::new(), asked_mode: Vec::new(), asked_region: Vec::new(), told: Vec::new(), told_competence: Vec::new(), told_region: Vec::new() }
    }

    /// SAGG-RIAC over the box [low, high] of any dimension.
    pub fn sagg_riac(low: &[f64], high: &[f64], tree: RegionTreeConfig, modes: ModeProbabilities, seed: u64) -> Result<Self> {
        Ok(Self::new(Box::new(SaggRiac::new(low, high, tree, modes, seed)?)))
    }

    /// Goals uniform in [low, high] (SAGG-Random's high level).
    pub fn random(low: &[f64], high: &[f64], seed: u64) -> Result<Self> {
        Ok(Self::new(Box::new(RandomGoals::new(low, high, seed)?)))
    }

    pub fn selector(&self) -> &dyn GoalSelector {
        self.selector.as_ref()
    }
    pub fn dim(&self) -> usize {
        self.selector.dim()
    }

    pub fn sample(&mut self) -> GoalChoice {
        let c = self.selector.sample();
        self.asked.extend_from_slice(&c.goal);
        self.asked_mode.push(c.mode as u8);
        self.asked_region.push(c.region.map(|r| r as i64).unwrap_or(-1));
        c
    }

    /// `n` goals in a row, flattened row by row (no update in between, so the same tree).
    pub fn sample_batch(&mut self, n: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(n * self.dim());
        for _ in 0..n {
            out.extend(self.sample().goal);
        }
        out
    }

    /// Check a told goal: the right length, finite, inside the box; a finite competence.
    fn check(&self, goal: &[f64], competence: f64, row: Option<usize>) -> Result<()> {
        let at = row.map(|r| format!(" (row {r})")).unwrap_or_default();
        let d = self.dim();
        if goal.len() != d {
            return Err(Error::InvalidInput(format!("goal{at} must have {d} coordinates, the dimension of the goal space; got {}.", goal.len())));
        }
        if !competence.is_finite() {
            return Err(Error::InvalidInput(format!("competence{at} must be a finite float; got {competence}.")));
        }
        let (lo, hi) = (self.selector.low(), self.selector.high());
        for i in 0..d {
            if !(goal[i] >= lo[i] && goal[i] <= hi[i]) {
                return Err(Error::InvalidInput(format!("goal{at} must lie in the goal space [low, high]; coordinate {i} is {} but the bounds are [{}, {}].", goal[i], lo[i], hi[i])));
            }
        }
        Ok(())
    }

    /// Tell the competence obtained at `goal`; returns the region that recorded it (-1: none).
    pub fn update(&mut self, goal: &[f64], competence: f64) -> Result<i64> {
        self.check(goal, competence, None)?;
        Ok(self.record(goal, competence))
    }

    /// Tell a batch (goals row by row). Every row is checked before any is recorded, so a bad
    /// batch changes nothing.
    pub fn update_batch(&mut self, goals: &[f64], competences: &[f64]) -> Result<Vec<i64>> {
        let d = self.dim();
        if goals.len() != competences.len() * d {
            return Err(Error::InvalidInput(format!("goals must have one row of {d} coordinates per competence; got {} values for {} competences.", goals.len(), competences.len())));
        }
        for (i, (g, c)) in goals.chunks_exact(d).zip(competences).enumerate() {
            self.check(g, *c, Some(i))?;
        }
        Ok(goals.chunks_exact(d).zip(competences).map(|(g, c)| self.record(g, *c)).collect())
    }

    fn record(&mut self, goal: &[f64], competence: f64) -> i64 {
        let r = self.selector.update(goal, competence).map(|r| r as i64).unwrap_or(-1);
        self.told.extend_from_slice(goal);
        self.told_competence.push(competence);
        self.told_region.push(r);
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_input_and_keeps_state() {
        let mut a = AskTell::sagg_riac(&[0.0, 0.0], &[1.0, 1.0], RegionTreeConfig::default(), ModeProbabilities::default(), 1).unwrap();
        let e = a.update(&[0.5], -0.1).unwrap_err().to_string();
        assert!(e.contains("2 coordinates"), "{e}");
        let e = a.update(&[0.5, 1.5], -0.1).unwrap_err().to_string();
        assert!(e.contains("coordinate 1 is 1.5"), "{e}");
        let e = a.update(&[0.5, 0.5], f64::NAN).unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
        let e = a.update_batch(&[0.1, 0.1, 0.2, f64::INFINITY], &[-0.1, -0.2]).unwrap_err().to_string();
        assert!(e.contains("row 1"), "{e}");
        assert!(a.told_competence.is_empty());
        assert_eq!(a.selector().tree().unwrap().n_measurements(), 0);
        assert_eq!(a.update_batch(&[0.1, 0.1, 0.2, 0.2], &[-0.1, -0.2]).unwrap(), vec![0, 0]);
    }
}
