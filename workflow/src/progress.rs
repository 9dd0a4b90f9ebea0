//! Progress of long work: a bar on a terminal (hidden when standard error is not one).

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar over `len` units named `unit` (e.g. "scenes").
pub fn bar(len: usize, unit: &str) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    let template = format!("{{bar:40}} {{pos}}/{{len}} {unit}  {{elapsed_precise}}  {{msg}}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style);
    }
    bar
}
