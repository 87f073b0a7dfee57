//! Where test goals come from when a body's reachable set is no ball about the origin (a chain,
//! a user's body): a cloud of positions the body reached, each with the configuration that
//! reached it.

use crate::body::chain::Chain;
use crate::error::{invalid, Result};
use crate::rng::{index, uniform, CoreRng};
use crate::task_space::Point;

/// Cells per axis of the grid that `Cloud::goals` spreads goals over.
const GOAL_GRID: usize = 16;
/// Configurations sampled for `chain_goals`.
pub const CLOUD_SIZE: usize = 20_000;

/// Goals spread evenly over the reachable part of the goal box (`Cloud::goals`), from a fresh
/// cloud of `CLOUD_SIZE` configurations of `chain` uniform in [-limit, limit]; each comes with
/// the configuration that reaches it.
pub fn chain_goals(chain: &Chain, limit: f64, goal_low: &[f64], goal_high: &[f64], n_goals: usize, rng: &mut CoreRng) -> Result<Vec<(Point, Vec<f64>)>> {
    let configs: Vec<Vec<f64>> = (0..CLOUD_SIZE).map(|_| (0..chain.n_joints()).map(|_| uniform(rng, -limit, limit)).collect()).collect();
    let positions: Vec<Point> = configs.iter().map(|t| chain.forward(t)).collect();
    Cloud { configs, positions }.goals(goal_low, goal_high, n_goals, rng, "the chain's")
}

/// Positions a body reaches and the configurations that reach them, row for row.
#[derive(Debug, Clone, Default)]
pub struct Cloud {
    pub configs: Vec<Vec<f64>>,
    pub positions: Vec<Point>,
}

impl Cloud {
    /// Goals spread evenly over the reachable part of the goal box: the cloud is binned on a
    /// grid over the box; each goal picks an occupied cell uniformly, then a cloud point in it.
    /// Every goal is reachable; the density is uniform over the occupied cells (cells on the
    /// boundary of the reachable set count as whole ones). Each goal comes with the
    /// configuration that reaches it. `whose` names the body in the error ("the chain's").
    pub fn goals(&self, goal_low: &[f64], goal_high: &[f64], n_goals: usize, rng: &mut CoreRng, whose: &str) -> Result<Vec<(Point, Vec<f64>)>> {
        let m = goal_low.len();
        let cell = |p: &Point| -> Option<usize> {
            let mut id = 0;
            for i in 0..m {
                if !(p[i] >= goal_low[i] && p[i] <= goal_high[i]) {
                    return None;
                }
                let k = (((p[i] - goal_low[i]) / (goal_high[i] - goal_low[i])) * GOAL_GRID as f64) as usize;
                id = id * GOAL_GRID + k.min(GOAL_GRID - 1);
            }
            Some(id)
        };
        let mut cells: std::collections::BTreeMap<usize, Vec<usize>> = std::collections::BTreeMap::new();
        for (i, p) in self.positions.iter().enumerate() {
            if let Some(c) = cell(p) {
                cells.entry(c).or_default().push(i);
            }
        }
        if cells.is_empty() {
            return Err(invalid("Evaluation", "goal_low/goal_high", format!("a box that meets {whose} reachable set"), format!("{goal_low:?}..{goal_high:?}")));
        }
        let occupied: Vec<&Vec<usize>> = cells.values().collect();
        Ok((0..n_goals)
            .map(|_| {
                let members = occupied[index(rng, occupied.len())];
                let i = members[index(rng, members.len())];
                (self.positions[i], self.configs[i].clone())
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{rng_from_seed, uniform};
    use crate::task_space::point;

    /// A ring of positions far from the origin: goals are cloud points inside the box, each with
    /// its own configuration; a box the cloud misses is refused with the rule.
    #[test]
    fn goals_are_cloud_points_in_the_box() {
        let mut rng = rng_from_seed(7);
        let configs: Vec<Vec<f64>> = (0..2000).map(|_| vec![uniform(&mut rng, -3.0, 3.0)]).collect();
        let positions: Vec<Point> = configs.iter().map(|t| point(&[100.0 + 2.0 * t[0].cos(), -40.0 + 2.0 * t[0].sin()])).collect();
        let cloud = Cloud { configs, positions };
        let goals = cloud.goals(&[99.0, -43.0], &[103.0, -40.0], 300, &mut rng, "the body's").unwrap();
        for (g, t) in &goals {
            assert!(g[0] >= 99.0 && g[0] <= 103.0 && g[1] >= -43.0 && g[1] <= -40.0, "{g:?}");
            assert_eq!(*g, point(&[100.0 + 2.0 * t[0].cos(), -40.0 + 2.0 * t[0].sin()]));
        }
        let e = cloud.goals(&[0.0, 0.0], &[1.0, 1.0], 3, &mut rng, "the body's").unwrap_err().to_string();
        assert!(e.contains("meets the body's reachable set"), "{e}");
    }
}
