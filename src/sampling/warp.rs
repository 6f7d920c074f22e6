//! Warps from the unit square to disks, hemispheres, spheres, cones and triangles, each with
//! its probability density (pbrt-v4 `sampling.h`; Shirley & Chiu 1997 for the concentric disk).

use crate::math::{Vec2, Vec3, INV_PI, PI};
use crate::simd::{Real, V3};

/// 1/(2π).
const INV_2PI: f32 = 0.5 * INV_PI;
/// 1/(4π).
const INV_4PI: f32 = 0.25 * INV_PI;

/// Uniform point on the unit disk by Shirley & Chiu's concentric map ("A Low Distortion Map
/// Between Disk and Square", 1997): squares map to rings, so strata stay compact.
pub fn sample_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let (x, y) = disk_concentric(u.x, u.y);
    Vec2::new(x, y)
}

/// [`sample_uniform_disk_concentric`] for every lane: (x, y) on the disk. The angle
/// θ = (π/4)(v/u), or π/2 − (π/4)(u/v) when |v| ≥ |u|, needs sin and cos only on [−π/4, π/4]
/// (the second case swaps them).
#[inline(always)]
pub fn disk_concentric<R: Real>(ux: R, uy: R) -> (R, R) {
    let (one, two) = (R::splat(1.0), R::splat(2.0));
    let (ox, oy) = (two * ux - one, two * uy - one);
    let x_major = oy.abs().lt(ox.abs());
    let r = R::select(x_major, ox, oy);
    let ratio = R::select(x_major, oy, ox) / r;
    let (s, c) = (R::splat(0.25 * PI) * ratio).sin_cos_quarter_pi();
    let (cos_t, sin_t) = (R::select(x_major, c, s), R::select(x_major, s, c));
    // Both coordinates 0 only at the centre, where the ratio is 0/0.
    let centre = ox.eq(R::splat(0.0)) & oy.eq(R::splat(0.0));
    let zero = R::splat(0.0);
    (R::select(centre, zero, r * cos_t), R::select(centre, zero, r * sin_t))
}

/// Uniform point on the unit disk by the polar map r = √u₀, φ = 2πu₁.
pub fn sample_uniform_disk_polar(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    r * Vec2::new(phi.cos(), phi.sin())
}

/// Density of a uniform point on the unit disk [1/area].
#[inline]
pub fn uniform_disk_pdf() -> f32 {
    INV_PI
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method: project a uniform disk
/// point up). Density cos θ / π [1/sr].
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    cosine_hemisphere(u.x, u.y).into()
}

/// [`sample_cosine_hemisphere`] for every lane.
#[inline(always)]
pub fn cosine_hemisphere<R: Real>(ux: R, uy: R) -> V3<R> {
    let (x, y) = disk_concentric(ux, uy);
    let z = (R::splat(1.0) - x * x - y * y).max(R::splat(0.0)).sqrt();
    V3::new(x, y, z)
}

/// Density of [`sample_cosine_hemisphere`] [1/sr]: cos θ / π (0 below the horizon).
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * INV_PI
}

/// Uniform direction on the +z hemisphere.
pub fn sample_uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`sample_uniform_hemisphere`] [1/sr]: 1/(2π).
#[inline]
pub fn uniform_hemisphere_pdf() -> f32 {
    INV_2PI
}

/// Uniform direction on the unit sphere (Archimedes: z is uniform in [-1, 1]).
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`sample_uniform_sphere`] [1/sr]: 1/(4π).
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    INV_4PI
}

/// Uniform direction in the cone of half-angle θmax around +z, given `cos_theta_max`.
/// Used for sampling spherical lights by the solid angle they subtend.
pub fn sample_uniform_cone(u: Vec2, cos_theta_max: f32) -> Vec3 {
    let cos_theta = (1.0 - u.x) + u.x * cos_theta_max;
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// Density of [`sample_uniform_cone`] [1/sr]: 1 / (2π (1 − cos θmax)).
#[inline]
pub fn uniform_cone_pdf(cos_theta_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_theta_max))
}

/// Uniform barycentric coordinates (b0, b1, b2) on a triangle; density 1/area on the triangle.
/// Square-root map: b0 = 1 − √u₀, b1 = u₁ √u₀ (Osada et al. 2002, "Shape distributions").
pub fn sample_uniform_triangle(u: Vec2) -> [f32; 3] {
    uniform_triangle(u.x, u.y)
}

/// [`sample_uniform_triangle`] for every lane.
#[inline(always)]
pub fn uniform_triangle<R: Real>(ux: R, uy: R) -> [R; 3] {
    let su0 = ux.sqrt();
    let b0 = R::splat(1.0) - su0;
    let b1 = uy * su0;
    [b0, b1, (R::splat(1.0) - b0 - b1).max(R::splat(0.0))]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::{Chi2Test, Domain};

    fn tester() -> Chi2Test {
        Chi2Test { sample_count: 400_000, ..Chi2Test::default() }
    }

    #[test]
    fn cosine_hemisphere_passes_chi2() {
        let r = tester().run(|_, u| Some(sample_cosine_hemisphere(u)), |w| cosine_hemisphere_pdf(w.z));
        assert!(r.passed, "{r}");
    }

    #[test]
    fn uniform_hemisphere_and_sphere_pass_chi2() {
        let r = tester().run(
            |_, u| Some(sample_uniform_hemisphere(u)),
            |w| {
                if w.z >= 0.0 {
                    uniform_hemisphere_pdf()
                } else {
                    0.0
                }
            },
        );
        assert!(r.passed, "{r}");
        let r = tester().run(|_, u| Some(sample_uniform_sphere(u)), |_| uniform_sphere_pdf());
        assert!(r.passed, "{r}");
    }

    #[test]
    fn uniform_cone_passes_chi2() {
        let cos_max = 0.8f32;
        let r = tester().run(
            |_, u| Some(sample_uniform_cone(u, cos_max)),
            |w| {
                if w.z >= cos_max {
                    uniform_cone_pdf(cos_max)
                } else {
                    0.0
                }
            },
        );
        assert!(r.passed, "{r}");
    }

    #[test]
    fn disks_pass_chi2_on_the_plane() {
        let t = Chi2Test {
            domain: Domain::Plane { min: Vec2::splat(-1.0), max: Vec2::splat(1.0) },
            theta_res: 40,
            phi_res: 40,
            ..tester()
        };
        let pdf = |p: Vec3| {
            if p.x * p.x + p.y * p.y <= 1.0 {
                uniform_disk_pdf()
            } else {
                0.0
            }
        };
        let r = t.run(|_, u| Some(sample_uniform_disk_concentric(u).extend(0.0)), pdf);
        assert!(r.passed, "{r}");
        let r = t.run(|_, u| Some(sample_uniform_disk_polar(u).extend(0.0)), pdf);
        assert!(r.passed, "{r}");
    }

    #[test]
    fn triangle_passes_chi2_on_the_plane() {
        // Barycentrics of the triangle (0,0), (1,0), (0,1) are its (x, y) = (b1, b2); area 1/2.
        let t = Chi2Test {
            domain: Domain::Plane { min: Vec2::ZERO, max: Vec2::ONE },
            theta_res: 40,
            phi_res: 40,
            ..tester()
        };
        let r = t.run(
            |_, u| {
                let b = sample_uniform_triangle(u);
                Some(Vec3::new(b[1], b[2], 0.0))
            },
            |p| {
                if p.x >= 0.0 && p.y >= 0.0 && p.x + p.y <= 1.0 {
                    2.0
                } else {
                    0.0
                }
            },
        );
        assert!(r.passed, "{r}");
    }

    #[test]
    fn chi2_rejects_a_wrong_pdf() {
        // Cosine-distributed samples tested against the uniform-hemisphere density.
        let r = tester().run(
            |_, u| Some(sample_cosine_hemisphere(u)),
            |w| {
                if w.z >= 0.0 {
                    uniform_hemisphere_pdf()
                } else {
                    0.0
                }
            },
        );
        assert!(!r.passed, "{r}");
        // A subtler error: cone samples against a cone density 2% too wide.
        let cos_max = 0.8f32;
        let wrong = 0.8 - 0.02 * 0.2;
        let r = tester().run(
            |_, u| Some(sample_uniform_cone(u, cos_max)),
            |w| {
                if w.z >= wrong {
                    uniform_cone_pdf(wrong)
                } else {
                    0.0
                }
            },
        );
        assert!(!r.passed, "{r}");
    }

    #[test]
    fn chi2_rejects_samples_where_the_pdf_is_zero() {
        let r = tester().run(
            |_, u| Some(sample_uniform_sphere(u)),
            |w| {
                if w.z >= 0.0 {
                    2.0 * uniform_sphere_pdf()
                } else {
                    0.0
                }
            },
        );
        assert!(!r.passed, "{r}");
    }
}
