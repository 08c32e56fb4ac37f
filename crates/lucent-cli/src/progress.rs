use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// A progress bar over image rows, drawn on stderr only when stderr is a
/// terminal (logs and pipes stay clean).
pub struct RowProgress {
    bar: Option<ProgressBar>,
}

impl RowProgress {
    pub fn new(rows: u64, quiet: bool) -> Self {
        if quiet || !std::io::stderr().is_terminal() {
            return Self { bar: None };
        }
        let bar = ProgressBar::with_draw_target(Some(rows), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} rows, ETA {eta}")
                .expect("valid template"),
        );
        Self { bar: Some(bar) }
    }

    pub fn set(&self, rows_done: u64) {
        if let Some(b) = &self.bar {
            // Rows finish out of order across threads; keep the bar monotone.
            if rows_done > b.position() {
                b.set_position(rows_done);
            }
        }
    }

    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
