//! The `prism` command line: parse arguments, dispatch to a subcommand, turn errors into one line
//! and a non-zero exit code.

use clap::{Parser, Subcommand};
use prism::cli;

#[derive(Parser)]
#[command(name = "prism", version, about = "A spectral, physically based offline renderer")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a pbrt-v4 scene (or the built-in Cornell box).
    Render(cli::render::RenderArgs),
    /// Colour tools: XYZ of an SPD file, RGB→spectrum, basis projection.
    #[command(subcommand)]
    Color(cli::color::ColorCommand),
    /// Combine the .film parts of a split render (`render --part i/N`) into one image.
    Merge(cli::merge::MergeArgs),
    /// Measure radiometric quantities with the full integrator (mean ± standard error).
    #[command(subcommand)]
    Measure(cli::measure::MeasureCommand),
    /// Render a ladder of sample counts per backend and sampler; error vs time, plots.
    Bench(cli::bench::BenchArgs),
    /// Error metrics between two images (RMSE, relMSE, MAE) and a false-colour difference.
    Compare(cli::bench::CompareArgs),
    /// Subsurface report: diffusion vs random walk, time and RMSE (docs/subsurface.md).
    SssReport(cli::sss_report::SssReportArgs),
}

/// Logs warnings and errors to stderr as "prism: warning: …".
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, m: &log::Metadata) -> bool {
        m.level() <= log::Level::Warn
    }
    fn log(&self, r: &log::Record) {
        if self.enabled(r.metadata()) {
            eprintln!("prism: {}: {}", r.level().as_str().to_lowercase(), r.args());
        }
    }
    fn flush(&self) {}
}

fn main() {
    static LOGGER: StderrLog = StderrLog;
    let _ = log::set_logger(&LOGGER).map(|_| log::set_max_level(log::LevelFilter::Warn));
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(a) => cli::render::run(&a),
        Command::Color(c) => cli::color::run(c),
        Command::Merge(a) => cli::merge::run(&a),
        Command::Measure(c) => cli::measure::run(&c),
        Command::Bench(a) => cli::bench::run(&a),
        Command::Compare(a) => cli::bench::compare(&a),
        Command::SssReport(a) => cli::sss_report::run(&a),
    };
    if let Err(e) = result {
        // One line: the chain of causes joined by ": ".
        let msg = e.chain().map(|c| c.to_string()).collect::<Vec<_>>().join(": ");
        eprintln!("prism: error: {msg}");
        std::process::exit(1);
    }
}
