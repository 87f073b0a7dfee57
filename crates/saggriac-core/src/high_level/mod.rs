//! The high level (paper II): the competence of an attempt (`competence`, eq. 7), the interest of
//! a region (`interest`, eq. 2), the region tree that splits the goal space (`region_tree`), goal
//! selection with its three modes (`goal_selection`: the `GoalSelector` trait, SAGG-RIAC and
//! random goals), the other teachers (`teachers`: RIAC, ALP-GMM, Covar-GMM, discrete learning
//! progress), and the ask/tell form of any of them (`ask_tell`).

pub mod ask_tell;
pub mod competence;
pub mod goal_selection;
pub mod interest;
pub mod region_tree;
pub mod teachers;
