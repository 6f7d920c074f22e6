//! Command-line subcommands (the binary in main.rs only parses and dispatches to these).

pub mod bench;
pub mod color;
mod color_report;
pub mod measure;
pub mod merge;
pub mod render;
pub mod sss_report;
pub mod sss_scenes;
