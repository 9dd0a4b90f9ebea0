//! Many independent runs at once: on rayon's thread pool with the `parallel` feature (the
//! default), one after another without it. Results come back in input order.

use kanestop_runtime::model::Model;
use kanestop_runtime::simulate::{self, RunResult};

use crate::kernels::KernelFactory;

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

/// [`map`] on a pool of `jobs` threads (rayon's default pool when none); without the
/// `parallel` feature, one after another whatever `jobs` says.
#[cfg(feature = "parallel")]
pub fn map_jobs<T: Sync, R: Send>(
    jobs: Option<usize>,
    items: &[T],
    f: impl Fn(&T) -> R + Sync + Send,
) -> Result<Vec<R>, String> {
    match jobs {
        None => Ok(map(items, f)),
        Some(0) => Err("must be at least 1".into()),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(|e| e.to_string())?;
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
) -> Result<Vec<R>, String> {
    if jobs == Some(0) {
        return Err("must be at least 1".into());
    }
    Ok(map(items, f))
}

/// Runs every model with a kernel from `kernel`, in parallel where the feature allows;
/// `done` is called (from any thread) as each run finishes. Results in input order.
pub fn run_models(models: &[Model], kernel: KernelFactory, done: &(dyn Fn(&RunResult) + Sync)) -> Vec<RunResult> {
    map(models, |m| {
        let result = simulate::run(m, kernel(m));
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
