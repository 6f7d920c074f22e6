//! The `prism` command line: parse arguments, run the subcommand, turn errors into one line and
//! a non-zero exit code.

use clap::Parser;
use prism::cli::Cli;

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
    if let Err(e) = Cli::parse().run() {
        // One line: the chain of causes joined by ": ".
        let msg = e.chain().map(|c| c.to_string()).collect::<Vec<_>>().join(": ");
        eprintln!("prism: error: {msg}");
        std::process::exit(1);
    }
}
