//! Command-line subcommands (the binary in main.rs only parses and dispatches to these).

pub mod bench;
pub mod color;
mod color_report;
pub mod measure;
pub mod merge;
pub mod render;
pub mod sss_report;
pub mod sss_scenes;

/// The render workers for `--threads` (all cores without it; 0 is an error), each set up for
/// rendering by [`crate::accel::init_render_thread`].
fn worker_pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    if threads == Some(0) {
        anyhow::bail!("--threads must be at least 1");
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .start_handler(|_| crate::accel::init_render_thread())
        .build()
        .map_err(|e| anyhow::anyhow!("starting worker threads: {e}"))
}

/// `n`, or the one-line error "`flag` must be positive" (sample counts, image sizes).
fn positive<T: Default + PartialEq>(n: T, flag: &str) -> anyhow::Result<T> {
    if n == T::default() {
        anyhow::bail!("{flag} must be positive, got 0");
    }
    Ok(n)
}

/// `--max-depth`: a depth ≥ 0, or -1 for no limit ([`crate::integrator::UNBOUNDED_DEPTH`]).
fn max_depth(d: i64) -> anyhow::Result<u32> {
    match d {
        -1 => Ok(crate::integrator::UNBOUNDED_DEPTH),
        d => {
            u32::try_from(d).map_err(|_| anyhow::anyhow!("--max-depth must be at least 0, or -1 for no limit, got {d}"))
        }
    }
}

/// A progress bar over a render's samples per pixel (drawn on stderr when it is a terminal).
pub(crate) fn spp_progress_bar(spp: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(spp);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} spp  {elapsed_precise} eta {eta}")
            .expect("static template"),
    );
    bar
}
