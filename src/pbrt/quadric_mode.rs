//! How the reader builds pbrt-v4's sphere, disk and cylinder shapes.

/// How pbrt-v4's sphere, disk and cylinder shapes are built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum QuadricMode {
    /// Intersected exactly in object space by both backends.
    #[default]
    Analytic,
    /// Inscribed triangle meshes with analytic normals and (u, v) ([`crate::geometry::quadric`]).
    Tessellated,
}

crate::named::name_table!(QuadricMode, "quadric mode", {
    "analytic" => QuadricMode::Analytic,
    "tessellated" => QuadricMode::Tessellated,
});
