//! The end-to-end test suite, one binary: every module shares one link of the renderer, which
//! keeps CI's compile time down (one test binary per file would link it a dozen times).

mod accel_agreement;
mod alpha;
mod analytic_quadrics;
mod area_image;
mod bump;
mod cli;
mod common;
mod compat;
mod curves;
mod envmap;
mod equal_area_envmap;
mod film;
mod instancing;
mod light_sampler;
mod measured;
mod media;
mod merge;
mod motion;
mod naive_fails;
mod pbrt_defaults;
mod pbrt_materials;
mod portal;
mod quadrics;
mod radiometry;
mod readme;
mod regularize;
mod render;
mod resource_errors;
mod robustness;
mod scene_files;
mod scene_fuzz;
mod scene_parser;
mod spectral_edges;
mod strategies;
mod strict;
