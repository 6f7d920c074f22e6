//! Geometry: rays, hits, triangle meshes.

mod mesh;
mod ray;

pub use mesh::{Bounds3, Mesh};
pub use ray::{Hit, Ray};
