//! Ray intersection. One trait, two backends: Intel Embree (feature `embree`) and the pure-Rust
//! obvhs BVH. Nothing backend-specific leaves this module.

pub mod obvhs;
pub mod watertight;

pub use self::obvhs::{BuildQuality, BuildStats, ObvhsAccel};

use crate::geometry::{Bounds3, Hit, Ray};

/// A ray-intersection accelerator over a set of triangle meshes.
pub trait Accel: Send + Sync {
    /// Closest hit with t in (0, ray.t_max], if any.
    fn intersect(&self, ray: &Ray) -> Option<Hit>;
    /// True when anything is hit with t in (0, ray.t_max) (shadow rays).
    fn occluded(&self, ray: &Ray) -> bool;
    /// Bounds of the whole scene.
    fn bounds(&self) -> Bounds3;
    /// Backend name, as on the command line.
    fn name(&self) -> &'static str;
}
