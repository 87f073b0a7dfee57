//! What every property test file shares: the proptest configuration. Each test file uses a
//! part of it.
#![allow(dead_code)]

use proptest::prelude::ProptestConfig;
use proptest::test_runner::{FileFailurePersistence, TestCaseError};

pub type TestResult = Result<(), TestCaseError>;

/// `cases` cases per property in a debug build, four times as many in an optimised one
/// (PROPTEST_CASES overrides both, e.g. for a long soak); failures print their minimal input,
/// nothing is written to disk.
pub fn cases(cases: u32) -> ProptestConfig {
    let cases = if cfg!(debug_assertions) { cases } else { 4 * cases };
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(cases);
    ProptestConfig { cases, failure_persistence: Some(Box::new(FileFailurePersistence::Off)), ..ProptestConfig::default() }
}
