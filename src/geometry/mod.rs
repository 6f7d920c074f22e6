//! Geometry: rays, hits, triangle meshes, object instances, test shapes.

pub mod instance;
pub mod loop_subdivision;
mod mesh;
mod ray;
pub mod shapes;

pub use instance::{Instance, InstanceSet, Prototype};
pub use mesh::{Bounds3, Mesh};
pub use ray::{Hit, Ray};
