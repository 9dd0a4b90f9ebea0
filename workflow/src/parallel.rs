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
