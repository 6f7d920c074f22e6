//! Command-line front ends; `main.rs` only parses and dispatches.

pub mod color;
mod color_report;
