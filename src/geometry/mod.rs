//! Geometry: rays, hits, triangle meshes, test shapes.

mod mesh;
mod ray;
pub mod shapes;

pub use mesh::{Bounds3, Mesh};
pub use ray::{Hit, Ray};
