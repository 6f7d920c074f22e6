//! Progress of a long render: a bar on a terminal, plain lines in a log.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// A progress bar over a render's samples per pixel (drawn on stderr when it is a terminal).
pub fn spp_progress_bar(spp: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(spp);
    bar.set_style(bar_style("spp"));
    bar
}

/// The bar's look, counting `unit`.
fn bar_style(unit: &str) -> indicatif::ProgressStyle {
    indicatif::ProgressStyle::with_template(&format!(
        "{{bar:40}} {{pos}}/{{len}} {unit}  {{elapsed_precise}} eta {{eta}}"
    ))
    .expect("a fixed template")
}

/// Seconds between two progress lines in a log.
const LINE_INTERVAL: Duration = Duration::from_secs(10);

/// A render's progress on stderr: the bar on a terminal; otherwise (a batch job's log) one line
/// `prism: 48/256 spp, 12.3 s, ETA 53 s` after the first pass and then at most every
/// [`LINE_INTERVAL`].
pub enum SppProgress {
    /// stderr is a terminal; the render's samples per pixel.
    Bar(indicatif::ProgressBar, u64),
    /// stderr is a file or pipe.
    Lines {
        /// Samples per pixel of the whole render.
        total: u64,
        /// Samples per pixel done when this run started (a resumed render's checkpoint).
        first: u64,
        /// When this run started.
        start: Instant,
        /// When the last line was printed (`None`: none yet).
        last: Option<Instant>,
    },
}

impl SppProgress {
    /// Progress over `total` samples per pixel, `done` of them already taken.
    pub fn new(total: u64, done: u64) -> Self {
        if std::io::stderr().is_terminal() {
            let bar = spp_progress_bar(total);
            bar.set_position(done);
            Self::Bar(bar, total)
        } else {
            Self::Lines { total, first: done, start: Instant::now(), last: None }
        }
    }

    /// Reports `done` samples per pixel taken.
    pub fn set(&mut self, done: u64) {
        match self {
            Self::Bar(bar, _) => bar.set_position(done),
            Self::Lines { total, first, start, last } => {
                if last.is_some_and(|t| t.elapsed() < LINE_INTERVAL) {
                    return;
                }
                *last = Some(Instant::now());
                let elapsed = start.elapsed().as_secs_f64();
                // The rate of this run so far, extrapolated to the samples left.
                let eta = match done.saturating_sub(*first) {
                    0 => String::new(),
                    n => format!(", ETA {:.0} s", elapsed / n as f64 * total.saturating_sub(done) as f64),
                };
                eprintln!("prism: {done}/{total} spp, {elapsed:.1} s{eta}");
            }
        }
    }

    /// Reports `done` of Metropolis light transport's `total` bootstrap paths made, before the
    /// first sample: the bar counts them until they are all made, then samples per pixel again;
    /// a log gets lines as for samples.
    pub fn bootstrap(&mut self, done: u64, total: u64) {
        match self {
            Self::Bar(bar, spp) => {
                if done == 0 {
                    bar.set_length(total);
                    bar.set_style(bar_style("bootstrap paths"));
                }
                bar.set_position(done);
                if done == total {
                    bar.set_length(*spp);
                    bar.set_position(0);
                    bar.reset_eta();
                    bar.set_style(bar_style("spp"));
                }
            }
            Self::Lines { start, last, .. } => {
                if done != total && last.is_some_and(|t| t.elapsed() < LINE_INTERVAL) {
                    return;
                }
                *last = Some(Instant::now());
                eprintln!("prism: mlt bootstrap {done}/{total} paths, {:.1} s", start.elapsed().as_secs_f64());
            }
        }
    }

    /// Removes the bar (lines stay in the log).
    pub fn finish(&self) {
        if let Self::Bar(bar, _) = self {
            bar.finish_and_clear();
        }
    }
}
