//! prism: a spectral, physically based offline renderer.
//!
//! Rendering the built-in Cornell box in a few lines:
//! ```no_run
//! use prism::{accel::AccelKind, render::*, scene::SceneBuilder};
//! let scene = SceneBuilder::cornell_box().build(AccelKind::Obvhs).unwrap();
//! let settings = RenderSettings {
//!     resolution: (64, 64),
//!     spp: 4,
//!     sampler: SamplerKind::Sobol,
//!     filter: prism::filter::Filter::by_name("box").unwrap(),
//!     ..Default::default()
//! };
//! let (film, stats) = render(&scene, &settings, |_| {}).unwrap();
//! assert_eq!(stats.samples, 64 * 64 * 4);
//! let xyz = film.xyz(32, 32);
//! ```

pub mod accel;
pub mod adaptive;
pub mod bench;
pub mod bsdf;
pub mod bssrdf;
pub mod camera;
pub mod checkpoint;
pub mod cli;
pub mod denoise;
pub mod film;
pub mod filter;
pub mod fingerprint;
pub mod geometry;
pub mod image;
pub mod integrator;
pub mod io;
pub mod light;
pub mod material;
pub mod math;
pub mod measure;
pub mod media;
pub mod named;
pub mod pbrt;
pub mod progress;
pub mod render;
pub mod render_settings;
pub mod sampling;
pub mod scene;
pub mod sensor;
pub mod sensor_fit;
pub mod settings;
pub mod simd;
pub mod spectrum;
pub mod sppm_render;
pub mod texture;
