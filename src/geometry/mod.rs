//! Geometry: rays, hits, triangle meshes, curves, bilinear patches, quadrics, object instances, test shapes.

pub mod animated;
pub mod bilinear;
pub mod curve;
pub mod curve_hit;
pub mod instance;
pub mod loop_subdivision;
mod mesh;
pub mod motion;
pub mod placed_quadric;
pub mod quadric;
pub mod quadric_hit;
mod ray;
mod shape;
pub mod shapes;
pub mod weingarten;

pub use animated::AnimatedTransform;
pub use curve::{CurveKind, CurveSegment, Curves};
pub use instance::{Instance, InstanceSet, Prototype};
pub(crate) use mesh::MIN_ELEMENTS_PER_THREAD;
pub use mesh::{slab_inverse, Bounds3, Mesh};
pub use motion::Motion;
pub use placed_quadric::{PlacedQuadric, QuadricSurface};
pub use quadric::Quadric;
pub use ray::{Hit, Ray};
pub use shape::Shape;
