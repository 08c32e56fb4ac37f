use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// A progress bar over a fraction of the work, drawn on stderr only when
/// stderr is a terminal (logs and pipes stay clean).
pub struct FractionProgress {
    bar: Option<ProgressBar>,
}

const STEPS: u64 = 1000;

impl FractionProgress {
    pub fn new(quiet: bool) -> Self {
        if quiet || !std::io::stderr().is_terminal() {
            return Self { bar: None };
        }
        let bar = ProgressBar::with_draw_target(Some(STEPS), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {percent}%, ETA {eta}")
                .expect("valid template"),
        );
        Self { bar: Some(bar) }
    }

    pub fn set(&self, fraction: f64) {
        if let Some(b) = &self.bar {
            let pos = (fraction.clamp(0.0, 1.0) * STEPS as f64) as u64;
            if pos > b.position() {
                b.set_position(pos);
            }
        }
    }

    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
