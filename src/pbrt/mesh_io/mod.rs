//! Mesh file readers: PLY (pbrt-v4 "plymesh") and OBJ (prism's "objmesh" extension).

mod error;
pub mod obj;
pub mod ply;

pub use error::MeshError;
