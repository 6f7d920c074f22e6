//! The command line: [`Cli`] and one module per subcommand. The binary in main.rs parses a
//! [`Cli`] and runs it; nothing else in the library uses this module.

pub mod bench;
pub mod color;
mod color_report;
pub mod compat;
mod denoised;
mod interrupt;
pub use interrupt::Interrupted;
mod compat_case;
mod compat_report;
pub mod measure;
pub mod merge;
pub mod render;
mod render_adaptive;
mod render_function;
mod render_job;
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

/// The subcommands. Parsed once per process, so the size gap between them costs nothing.
#[derive(clap::Subcommand, Debug)]
#[allow(clippy::large_enum_variant)]
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
    /// Render every scene that has a pbrt-v4 reference and compare (docs/compatibility.md).
    Compat(compat::CompatArgs),
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
            Command::Compat(a) => compat::run(&a),
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

/// Writes a command's result to standard output. A reader that closed the pipe early (`prism
/// compare … | head -1`) has what it wanted: that is not an error, and never a panic.
pub(crate) fn print_stdout(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(anyhow::Error::new(e).context("writing to stdout")),
        _ => Ok(()),
    }
}
