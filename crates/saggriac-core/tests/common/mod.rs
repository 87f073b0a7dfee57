//! What every property test file shares: the proptest configuration (a fixed seed, one
//! regression file). Each test file uses a part of it.
#![allow(dead_code)]

use proptest::prelude::ProptestConfig;
use proptest::test_runner::{FailurePersistence, FileFailurePersistence, RngSeed, TestCaseError};

pub type TestResult = Result<(), TestCaseError>;

/// Seed of every property's case generator unless PROPTEST_RNG_SEED names another: the default
/// test command runs the same cases on every machine and every run, so it cannot fail by luck.
/// `benchmarks/proptest_reruns.py` reruns the suite with many seeds to look further.
pub const DEFAULT_SEED: u64 = 20100601;

/// Failing cases found with any seed are appended here and replayed first on every later run
/// (commit the file); PROPTEST_DISABLE_FAILURE_PERSISTENCE turns it off. The path is explicit
/// because proptest's default (a `proptest-regressions` folder next to the crate's `src`) is not
/// found from an integration test.
pub const REGRESSIONS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/proptest-regressions/properties.txt");

/// `cases` cases per property in a debug build, four times as many in an optimised one
/// (PROPTEST_CASES overrides both, e.g. for a long soak), from `DEFAULT_SEED` unless
/// PROPTEST_RNG_SEED is set.
pub fn cases(cases: u32) -> ProptestConfig {
    let cases = if cfg!(debug_assertions) { cases } else { 4 * cases };
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(cases);
    // ProptestConfig::default() has already read PROPTEST_RNG_SEED and
    // PROPTEST_DISABLE_FAILURE_PERSISTENCE from the environment.
    let base = ProptestConfig::default();
    let rng_seed = if std::env::var_os("PROPTEST_RNG_SEED").is_some() { base.rng_seed } else { RngSeed::Fixed(DEFAULT_SEED) };
    let failure_persistence: Option<Box<dyn FailurePersistence>> = base.failure_persistence.as_ref().map(|_| Box::new(FileFailurePersistence::Direct(REGRESSIONS)) as _);
    ProptestConfig { cases, rng_seed, failure_persistence, ..base }
}
