//! Command-line subcommands (the binary in main.rs only parses and dispatches to these).

pub mod bench;
pub mod color;
mod color_report;
pub mod measure;
pub mod merge;
pub mod render;
pub mod sss_report;
pub mod sss_scenes;

/// `n`, or the one-line error "`flag` must be positive" (sample counts, image sizes).
fn positive<T: Default + PartialEq>(n: T, flag: &str) -> anyhow::Result<T> {
    if n == T::default() {
        anyhow::bail!("{flag} must be positive, got 0");
    }
    Ok(n)
}
