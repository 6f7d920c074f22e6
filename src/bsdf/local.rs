//! Spherical trigonometry in the local shading frame (z = normal, θ from z) and the mirror and
//! refraction laws (pbrt-v4 `vecmath.h`, `scattering.h`).

use crate::math::Vec3;

/// cos θ.
#[inline]
pub fn cos_theta(w: Vec3) -> f32 {
    w.z
}
/// |cos θ|.
#[inline]
pub fn abs_cos_theta(w: Vec3) -> f32 {
    w.z.abs()
}
/// cos² θ.
#[inline]
pub fn cos2_theta(w: Vec3) -> f32 {
    w.z * w.z
}
/// sin² θ of a unit vector, as x² + y²: exact near the pole, where 1 − cos²θ cancels
/// catastrophically in f32 (a GGX lobe with α = 10⁻³ lives at sin²θ ~ 10⁻⁶).
#[inline]
pub fn sin2_theta(w: Vec3) -> f32 {
    (w.x * w.x + w.y * w.y).min(1.0)
}
/// tan² θ (∞ at the horizon).
#[inline]
pub fn tan2_theta(w: Vec3) -> f32 {
    sin2_theta(w) / cos2_theta(w)
}
/// True when both directions are on the same side of the surface.
#[inline]
pub fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}
/// Mirror of `wo` about the normal `n`: 2(wo·n)n − wo.
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}
/// `v` flipped to the hemisphere of `toward`.
#[inline]
pub fn face_forward(v: Vec3, toward: Vec3) -> Vec3 {
    if v.dot(toward) < 0.0 {
        -v
    } else {
        v
    }
}

/// Refraction of `wi` through an interface with normal `n` and relative IOR `eta` = η_t/η_i
/// for `wi` on the side `n` points to (Snell: η_i sin θ_i = η_t sin θ_t). Returns the
/// transmitted direction and the relative IOR it saw, or `None` on total internal reflection.
pub fn refract(wi: Vec3, mut n: Vec3, mut eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    Some((-wi / eta + (cos_i / eta - cos_t) * n, eta))
}
