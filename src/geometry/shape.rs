//! A primitive's shape: what a hit's `geom_id` names and what the accelerators trace. pbrt-v4
//! has one `Shape` interface over many kinds (Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., §6.1); prism keeps three, a closed set dispatched by `match`. Triangle
//! meshes, PLY meshes, bilinear patches and Loop subdivision surfaces are all triangles by the
//! time they are placed; curves and quadrics are intersected as they are.

use std::sync::Arc;

use super::{Curves, Mesh, PlacedQuadric};

/// The geometry of one primitive (world space, or object space in a prototype).
#[derive(Clone, Debug)]
pub enum Shape {
    /// Triangles (a hit's `prim_id` is a triangle, its (u, v) barycentrics). In a built
    /// scene they have moved to the scene's mesh table (`Scene::mesh`, shared with the
    /// accelerator) and this is left empty.
    Mesh(Mesh),
    /// Curves (a hit's `prim_id` is a segment, its `u` the curve parameter along it).
    Curves(Arc<Curves>),
    /// A sphere, disk or cylinder with its placement (a hit's t is all the backends report: the
    /// surface is recomputed from the ray).
    Quadric(Arc<PlacedQuadric>),
}

impl Default for Shape {
    /// An empty mesh: a shape that nothing hits.
    fn default() -> Self {
        Shape::Mesh(Mesh::default())
    }
}

impl Shape {
    /// The triangles, when the shape is a mesh.
    pub fn mesh(&self) -> Option<&Mesh> {
        match self {
            Shape::Mesh(mesh) => Some(mesh),
            Shape::Curves(_) | Shape::Quadric(_) => None,
        }
    }

    /// Number of triangles: the mesh's, 0 for curves and quadrics.
    pub fn triangle_count(&self) -> usize {
        match self {
            Shape::Mesh(mesh) => mesh.len(),
            Shape::Curves(_) | Shape::Quadric(_) => 0,
        }
    }
}
