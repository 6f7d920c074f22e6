//! The first surface a camera ray sees, as the geometry buffers (AOVs) of pbrt-v4's
//! `GBufferFilm` record it: position, normals, (u, v), the pixel footprint ∂p/∂x, ∂p/∂y, and the
//! BSDF's albedo. The integrator fills it in at the path's first vertex with a BSDF.

use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};

/// What a camera ray's first surface vertex tells the geometry buffers [world space].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisibleSurface {
    /// The point [world units].
    pub p: Vec3,
    /// Geometric normal (unit, on the side of the shading normal).
    pub n: Vec3,
    /// Shading normal after bump or normal mapping (unit).
    pub ns: Vec3,
    /// Surface coordinates (u, v).
    pub uv: Vec2,
    /// ∂p/∂x: the change of `p` per pixel step along the film's x [world units per pixel],
    /// scaled by max(1/8, 1/√spp) as texture footprints are (pbrt-v4 does the same).
    pub dpdx: Vec3,
    /// ∂p/∂y.
    pub dpdy: Vec3,
    /// The ray's time.
    pub time: f32,
    /// Directional albedo ρ(ω_o) = ∫ f(ω_o, ω_i) |cos θ_i| dω_i at the ray's wavelengths.
    pub albedo: SampledSpectrum,
}
