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
            let level = if r.level() == log::Level::Warn { "warning" } else { "error" };
            eprintln!("prism: {level}: {}", r.args());
        }
    }
    fn flush(&self) {}
}

fn main() {
    static LOGGER: StderrLog = StderrLog;
    let _ = log::set_logger(&LOGGER).map(|_| log::set_max_level(log::LevelFilter::Warn));
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => e.exit(), // --help, --version
        Err(e) => {
            // clap's message, without its usage and tips.
            let text = e.to_string();
            let first = text.lines().next().unwrap_or_default();
            eprintln!("prism: error: {}", first.trim_start_matches("error: "));
            std::process::exit(2);
        }
    };
    if let Err(e) = cli.run() {
        // A render stopped by SIGINT or SIGTERM: what it wrote, and the shell's status.
        if let Some(i) = e.downcast_ref::<prism::cli::Interrupted>() {
            eprintln!("prism: {i}");
            std::process::exit(i.status);
        }
        // One line: the chain of causes joined by ": ", each cause's own lines joined by spaces
        // (some decoders end their messages in a newline).
        let causes = e.chain().map(|c| c.to_string().split_whitespace().collect::<Vec<_>>().join(" "));
        eprintln!("prism: error: {}", causes.collect::<Vec<_>>().join(": "));
        std::process::exit(1);
    }
}
