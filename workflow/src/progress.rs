//! Progress of long work: a bar with the time left on a terminal; off a terminal (piped, in
//! CI, a scheduler's log), a plain line on standard error every 10 % of the work or every
//! 5 s, whichever comes first, with the time left too. The one progress report of every
//! command (batch, plot, the accuracy study, sweeps, sensitivities).

use std::io::IsTerminal as _;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Progress over `len` units named `unit` (e.g. "scenes").
pub fn bar(len: usize, unit: &str) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    let template = format!("{{bar:40}} {{pos}}/{{len}} {unit}  {{elapsed_precise}}  ETA {{eta}}  {{msg}}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style);
    }
    if !std::io::stderr().is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::hidden());
        plain_lines(&bar, unit.to_string());
    }
    bar
}

/// Prints `done/len unit (p %), elapsed` on standard error from a watcher thread while `bar`
/// is unfinished: at each further 10 % or after 5 s without a line.
fn plain_lines(bar: &ProgressBar, unit: String) {
    let bar = bar.clone();
    let last = Arc::new(Mutex::new((0u64, Instant::now())));
    std::thread::spawn(move || {
        let start = Instant::now();
        while !bar.is_finished() {
            std::thread::sleep(Duration::from_millis(200));
            let (pos, len) = (bar.position(), bar.length().unwrap_or(0).max(1));
            let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
            let step = (len / 10).max(1);
            if pos >= last.0 + step || (last.1.elapsed() >= Duration::from_secs(5) && pos < len) {
                let elapsed = start.elapsed().as_secs_f64();
                let left = if pos > 0 {
                    format!(", ETA {:.0} s", elapsed / pos as f64 * (len - pos) as f64)
                } else {
                    String::new()
                };
                eprintln!(
                    "progress  {pos}/{len} {unit} ({:.0} %), {elapsed:.0} s{left}",
                    100.0 * pos as f64 / len as f64
                );
                *last = (pos, Instant::now());
            }
        }
    });
}
