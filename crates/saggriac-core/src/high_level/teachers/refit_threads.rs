//! How many threads a mixture refit's EM fits use (issue 49). The fits of each k are
//! independent once their k-means starts are drawn, so running them on several threads changes
//! no bit of the result; it only changes the wall time. Small refits stay on the calling thread:
//! starting a thread costs more than the fits it would take over.

use std::sync::OnceLock;

use crate::error::{invalid, Result};

/// The environment variable that caps the threads of a refit (a whole number >= 1). It changes
/// no result, so it is read when a teacher is built and never saved with the teacher.
pub const FIT_THREADS_VAR: &str = "SAGGRIAC_FIT_THREADS";

/// A refit on fewer samples runs on one thread. Below 150 samples (in 3 to 12 dimensions) a
/// refit took 0.1-5 ms and two threads lost in every case, down to 0.13x; from 200 samples it
/// took 16 ms or more and two threads were 0.78-1.10x on a loaded machine
/// (`examples/refit_threads_probe.rs`, docs/performance.md, issue 49 item 4). The count of
/// samples says more than n d^2: EM's iterations to converge vary more than d does.
pub const MIN_PARALLEL_SAMPLES: usize = 200;

/// The cap set by `SAGGRIAC_FIT_THREADS`, or None when it is unset. `owner` names the teacher in
/// the error a bad value gets.
pub fn cap_from_env(owner: &'static str) -> Result<Option<usize>> {
    match std::env::var(FIT_THREADS_VAR) {
        Err(std::env::VarError::NotPresent) => Ok(None),
        Err(std::env::VarError::NotUnicode(v)) => Err(bad(owner, format!("{v:?}"))),
        Ok(v) => match v.trim().parse::<usize>() {
            Ok(n) if n >= 1 => Ok(Some(n)),
            _ => Err(bad(owner, format!("{v:?}"))),
        },
    }
}

fn bad(owner: &'static str, value: String) -> crate::error::Error {
    invalid(owner, FIT_THREADS_VAR, "a whole number >= 1 when set (the environment variable capping the threads of a mixture refit)", value)
}

/// The cores this process may use (read once: on Linux it reads the cgroup's quota).
fn cores() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |c| c.get()))
}

/// The threads a refit of `n_fits` fits on `n` samples uses: the cores (or `cap`), at most one
/// per fit, and one below `MIN_PARALLEL_SAMPLES` samples.
pub fn for_refit(n: usize, n_fits: usize, cap: Option<usize>) -> usize {
    if n < MIN_PARALLEL_SAMPLES {
        return 1;
    }
    cores().min(cap.unwrap_or(usize::MAX)).min(n_fits).max(1)
}
