//! The CPU time of the calling thread, for the cost of a run beside its wall time: on a
//! shared machine wall time counts the waits for a core, CPU time only the work.

use std::time::Duration;

/// CPU time the calling thread has used so far (user and system), where the platform
/// says: on Linux the first field of `/proc/thread-self/schedstat` (ns on the CPU); none
/// elsewhere or when the file cannot be read.
pub fn thread_cpu_time() -> Option<Duration> {
    if !cfg!(target_os = "linux") {
        return None;
    }
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(Duration::from_nanos(ns))
}

/// The CPU time since `start` (a [`thread_cpu_time`] reading), none when either reading is.
pub fn since(start: Option<Duration>) -> Option<Duration> {
    Some(thread_cpu_time()?.saturating_sub(start?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(target_os = "linux")]
    fn busy_work_takes_cpu_time_and_sleep_does_not() {
        // Spin until 10 ms of this thread's CPU time show, however long the shared cores make
        // that take (CI's test threads once left it 0.9 ms of 30 ms wall time); a clock that
        // does not move fails after 20 s.
        let start = thread_cpu_time();
        let mut x = 0u64;
        let t = std::time::Instant::now();
        loop {
            for _ in 0..10_000 {
                x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
            }
            let busy = since(start).expect("Linux has thread CPU time");
            if busy >= Duration::from_millis(10) {
                break;
            }
            assert!(t.elapsed() < Duration::from_secs(20), "{busy:?} of CPU time after 20 s of spinning");
        }
        let start = thread_cpu_time();
        std::thread::sleep(Duration::from_millis(50));
        let slept = since(start).unwrap();
        assert!(slept < Duration::from_millis(20), "{slept:?} while asleep");
    }
}
