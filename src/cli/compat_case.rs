//! One case of `prism compat`: a scene with pbrt-v4's images of it.

use std::path::PathBuf;

/// One scene with pbrt-v4's images of it.
#[derive(Clone, Debug)]
pub struct CompatCase {
    /// Reference stem, e.g. `envmap` or `killeroo-simple-350`.
    pub name: String,
    /// The scene file.
    pub scene: PathBuf,
    /// pbrt-v4's high-spp image.
    pub reference: PathBuf,
    /// pbrt-v4's second-seed image and its spp.
    pub second: Option<(PathBuf, u64)>,
    /// pbrt-v4's wall time for the second-seed image [s], from REFERENCES*.json.
    pub pbrt_wall_s: Option<f64>,
}
