//! Mesh file readers: PLY (pbrt-v4 "plymesh") and OBJ (prism's "objmesh" extension).

pub mod obj;
pub mod ply;
