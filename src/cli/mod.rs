//! Command-line subcommands (the binary in main.rs only dispatches to these).

pub mod bench;
pub mod measure;
pub mod merge;
pub mod render;
