//! Many independent runs at once: on rayon's thread pool with the `parallel` feature (the
//! default), one after another without it. Results come back in input order.

use kanestop_runtime::model::Model;
use kanestop_runtime::simulate::{self, RunResult};

use crate::kernels::KernelFactory;
use crate::{Error, Result};

/// `f` applied to every item, in parallel where the feature allows, results in input order.
#[cfg(feature = "parallel")]
pub fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    items.par_iter().map(f).collect()
}

/// `f` applied to every item, one after another (the `parallel` feature is off).
#[cfg(not(feature = "parallel"))]
pub fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    items.iter().map(f).collect()
}

/// The most runs at once `--jobs` takes: each is a thread, and far more threads than cores
/// only add work stealing (10 000 of them hung a 3-row sweep for minutes).
pub const MAX_JOBS: usize = 1024;

/// `jobs` as the CLI's `--jobs` takes it: none (one run per core) or 1 to [`MAX_JOBS`].
pub fn check_jobs(jobs: Option<usize>) -> Result<()> {
    match jobs {
        Some(n) if !(1..=MAX_JOBS).contains(&n) => Err(Error::Argument {
            name: "--jobs",
            value: n.to_string(),
            expected: format!("in [1, {MAX_JOBS}] (runs at once; the default is one per core)"),
        }),
        _ => Ok(()),
    }
}

/// [`map`] on a pool of `jobs` threads (rayon's default pool when none), after
/// [`check_jobs`]; without the `parallel` feature, one after another whatever `jobs` says.
#[cfg(feature = "parallel")]
pub fn map_jobs<T: Sync, R: Send>(
    jobs: Option<usize>,
    items: &[T],
    f: impl Fn(&T) -> R + Sync + Send,
) -> Result<Vec<R>> {
    check_jobs(jobs)?;
    match jobs {
        None => Ok(map(items, f)),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(|e| Error::Argument {
                name: "--jobs",
                value: n.to_string(),
                expected: format!("as many threads as the system starts ({e})"),
            })?;
            Ok(pool.install(|| map(items, f)))
        }
    }
}

/// [`map`], one after another (the `parallel` feature is off; `jobs` is checked only).
#[cfg(not(feature = "parallel"))]
pub fn map_jobs<T: Sync, R: Send>(
    jobs: Option<usize>,
    items: &[T],
    f: impl Fn(&T) -> R + Sync + Send,
) -> Result<Vec<R>> {
    check_jobs(jobs)?;
    Ok(map(items, f))
}

/// Runs every model with a kernel from `kernel`, its starting state checked as `run` checks
/// it, in parallel where the feature allows; `done` is called (from any thread) as each run
/// finishes. Results in input order.
pub fn run_models(models: &[Model], kernel: KernelFactory, done: &(dyn Fn(&RunResult) + Sync)) -> Vec<RunResult> {
    map(models, |m| {
        let result = simulate::run_checked(m, kernel(m), kernel(m));
        done(&result);
        result
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn results_keep_the_input_order() {
        let items: Vec<u64> = (0..1000).collect();
        assert_eq!(super::map(&items, |&i| 3 * i + 1), items.iter().map(|i| 3 * i + 1).collect::<Vec<_>>());
    }
}
