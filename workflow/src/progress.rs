//! Progress of long work: a bar with the time left on a terminal; off a terminal (piped, in
//! CI, a scheduler's log), a plain line on standard error every 10 % of the work or every
//! 5 s, whichever comes first, with the time left too, and a last line when the work is done.
//! The one progress report of every command (batch, plot, the accuracy study, sweeps,
//! sensitivities).

use std::borrow::Cow;
use std::io::IsTerminal as _;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Progress over a number of units (runs, scenes).
pub struct Progress {
    bar: ProgressBar,
    /// Off a terminal: the last plain line's position and time, shared with the watcher.
    plain: Option<Arc<Mutex<(u64, Instant)>>>,
    unit: String,
    start: Instant,
}

/// Progress over `len` units named `unit` (e.g. "scenes").
pub fn bar(len: usize, unit: &str) -> Progress {
    let bar = ProgressBar::new(len as u64);
    let template = format!("{{bar:40}} {{pos}}/{{len}} {unit}  {{elapsed_precise}}  ETA {{eta}}  {{msg}}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style);
    }
    let start = Instant::now();
    let plain = (!std::io::stderr().is_terminal()).then(|| {
        bar.set_draw_target(ProgressDrawTarget::hidden());
        let last = Arc::new(Mutex::new((0u64, start)));
        watch(&bar, last.clone(), unit.to_string(), start);
        last
    });
    Progress { bar, plain, unit: unit.to_string(), start }
}

impl Progress {
    /// `n` more units done.
    pub fn inc(&self, n: u64) {
        self.bar.inc(n);
    }

    /// What the bar shows beside the count (on a terminal).
    pub fn set_message(&self, message: impl Into<Cow<'static, str>>) {
        self.bar.set_message(message);
    }

    /// Clears the bar; off a terminal, the last line (every unit done) if not yet printed.
    pub fn finish_and_clear(&self) {
        // Read before finishing: indicatif's finish sets the position to the length, and
        // work that stopped early (a sensitivity study's failed base run) did not do it all.
        let (pos, len) = (self.bar.position(), self.bar.length().unwrap_or(0));
        self.bar.finish_and_clear();
        if let Some(last) = &self.plain {
            let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
            if last.0 < pos {
                // The work is over: no time left to estimate, even if it stopped early.
                eprintln!("{}", line(pos, len.max(1), &self.unit, self.start.elapsed().as_secs_f64(), false));
                *last = (pos, Instant::now());
            }
        }
    }
}

/// `progress  done/len unit (p %), t s, ETA s`, the ETA only while `running` and partly done.
fn line(pos: u64, len: u64, unit: &str, elapsed: f64, running: bool) -> String {
    let left = if running && pos > 0 && pos < len {
        format!(", ETA {:.0} s", elapsed / pos as f64 * (len - pos) as f64)
    } else {
        String::new()
    };
    format!("progress  {pos}/{len} {unit} ({:.0} %), {elapsed:.0} s{left}", 100.0 * pos as f64 / len as f64)
}

/// Prints [`line`] on standard error from a watcher thread while `bar` is unfinished: at each
/// further 10 % or after 5 s without a line (so a long run still shows it is alive).
fn watch(bar: &ProgressBar, last: Arc<Mutex<(u64, Instant)>>, unit: String, start: Instant) {
    let bar = bar.clone();
    std::thread::spawn(move || {
        while !bar.is_finished() {
            std::thread::sleep(Duration::from_millis(200));
            let (pos, len) = (bar.position(), bar.length().unwrap_or(0).max(1));
            let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
            if bar.is_finished() {
                break; // the last line is finish_and_clear's
            }
            let step = (len / 10).max(1);
            if pos >= last.0 + step || (last.1.elapsed() >= Duration::from_secs(5) && pos < len) {
                eprintln!("{}", line(pos, len, &unit, start.elapsed().as_secs_f64(), true));
                *last = (pos, Instant::now());
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_says_what_is_done_and_what_is_left() {
        assert_eq!(line(2, 10, "runs", 4.0, true), "progress  2/10 runs (20 %), 4 s, ETA 16 s");
        assert_eq!(line(10, 10, "runs", 20.0, true), "progress  10/10 runs (100 %), 20 s");
        assert_eq!(line(0, 10, "runs", 0.2, true), "progress  0/10 runs (0 %), 0 s");
        assert_eq!(line(1, 73, "runs", 0.2, false), "progress  1/73 runs (1 %), 0 s");
    }
}
