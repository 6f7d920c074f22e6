//! The command line: [`Cli`] and one module per subcommand. The binary in main.rs parses a
//! [`Cli`] and runs it; nothing else in the library uses this module.

pub mod bench;
pub mod color;
mod color_report;
pub mod measure;
pub mod merge;
pub mod render;
pub mod sss_report;
pub mod sss_scenes;

/// `prism`'s arguments.
#[derive(clap::Parser, Debug)]
#[command(name = "prism", version, about = "A spectral, physically based offline renderer")]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(clap::Subcommand, Debug)]
pub enum Command {
    /// Render a pbrt-v4 scene (or the built-in Cornell box).
    Render(render::RenderArgs),
    /// Colour tools: XYZ of an SPD file, RGB→spectrum, basis projection.
    #[command(subcommand)]
    Color(color::ColorCommand),
    /// Combine the .film parts of a split render (`render --part i/N`) into one image.
    Merge(merge::MergeArgs),
    /// Measure radiometric quantities with the full integrator (mean ± standard error).
    #[command(subcommand)]
    Measure(measure::MeasureCommand),
    /// Render a ladder of sample counts per backend and sampler; error vs time, plots.
    Bench(bench::BenchArgs),
    /// Error metrics between two images (RMSE, relMSE, MAE) and a false-colour difference.
    Compare(bench::CompareArgs),
    /// Subsurface report: diffusion vs random walk, time and RMSE (docs/subsurface.md).
    SssReport(sss_report::SssReportArgs),
}

impl Cli {
    /// Runs the subcommand.
    pub fn run(self) -> anyhow::Result<()> {
        match self.command {
            Command::Render(a) => render::run(&a),
            Command::Color(c) => color::run(c),
            Command::Merge(a) => merge::run(&a),
            Command::Measure(c) => measure::run(&c),
            Command::Bench(a) => bench::run(&a),
            Command::Compare(a) => bench::compare(&a),
            Command::SssReport(a) => sss_report::run(&a),
        }
    }
}

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
