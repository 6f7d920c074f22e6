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

/// (sin 2πt, cos 2πt): the sine and cosine of the fraction `t` of a full turn, as every warp
/// that draws an azimuth φ = 2πu needs. t is reduced to the nearest quarter turn k/4 exactly
/// (k/4 is dyadic), the rest, within ±π/4, goes to the polynomial of
/// [`Real::sin_cos_quarter_pi`], and the pair is rotated by k quarter turns: within 2 ulp of the
/// library's and without its calls.
#[inline]
pub fn sin_cos_turn(t: f32) -> (f32, f32) {
    let k = crate::math::floor(4.0 * t + 0.5);
    let x = (t - 0.25 * k) * (2.0 * PI);
    let (s, c) = x.sin_cos_quarter_pi();
    match (k as i32).rem_euclid(4) {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// Uniform point on the unit disk by the polar map r = √u₀, φ = 2πu₁.
pub fn sample_uniform_disk_polar(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let (sin_phi, cos_phi) = sin_cos_turn(u.y);
    r * Vec2::new(cos_phi, sin_phi)
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
    let (sin_phi, cos_phi) = sin_cos_turn(u.y);
    Vec3::new(r * cos_phi, r * sin_phi, z)
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
    let (sin_phi, cos_phi) = sin_cos_turn(u.y);
    Vec3::new(r * cos_phi, r * sin_phi, z)
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
    let (sin_phi, cos_phi) = sin_cos_turn(u.y);
    Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
}

/// Density of [`sample_uniform_cone`] [1/sr]: 1 / (2π (1 − cos θmax)).
#[inline]
pub fn uniform_cone_pdf(cos_theta_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_theta_max))
}

/// x ∈ [0, 1] with density ∝ (1 − x) a + x b (a, b ≥ 0, not both 0): the root of the cdf
/// ((b − a) x² + 2a x) / (a + b) = u, in the form u (a + b) / (a + √((1 − u) a² + u b²)) that
/// does not cancel when a ≈ b.
pub fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return u;
    }
    let den = a + ((1.0 - u) * a * a + u * b * b).sqrt();
    if den == 0.0 {
        // a = 0 and u = 0: the density's zero end.
        return 0.0;
    }
    (u * (a + b) / den).min(1.0f32.next_down())
}

/// Density of [`sample_linear`] at `x`.
pub fn linear_pdf(x: f32, a: f32, b: f32) -> f32 {
    if !(0.0..=1.0).contains(&x) {
        return 0.0;
    }
    if a == b {
        return 1.0;
    }
    2.0 * ((1.0 - x) * a + x * b) / (a + b)
}

/// A point of [0, 1]² with density ∝ the bilinear interpolation of the corner values
/// `w` = [w(0,0), w(1,0), w(0,1), w(1,1)] (non-negative, not all 0): y from its marginal,
/// linear between w₀₀ + w₁₀ and w₀₁ + w₁₁, then x from the line at that y.
pub fn sample_bilinear(u: Vec2, w: [f32; 4]) -> Vec2 {
    let y = sample_linear(u.y, w[0] + w[1], w[2] + w[3]);
    let x = sample_linear(u.x, (1.0 - y) * w[0] + y * w[2], (1.0 - y) * w[1] + y * w[3]);
    Vec2::new(x, y)
}

/// Density of [`sample_bilinear`] at `p`: the bilinear value over its mean (w₀₀ + w₁₀ + w₀₁ + w₁₁)/4.
pub fn bilinear_pdf(p: Vec2, w: [f32; 4]) -> f32 {
    if !(0.0..=1.0).contains(&p.x) || !(0.0..=1.0).contains(&p.y) {
        return 0.0;
    }
    let sum = w[0] + w[1] + w[2] + w[3];
    if sum == 0.0 {
        return 1.0;
    }
    let value =
        (1.0 - p.x) * (1.0 - p.y) * w[0] + p.x * (1.0 - p.y) * w[1] + (1.0 - p.x) * p.y * w[2] + p.x * p.y * w[3];
    4.0 * value / sum
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

    #[test]
    fn sin_cos_turn_is_within_two_ulp_of_the_library() {
        let mut rng = crate::sampling::Rng::new(2, 8);
        let mut ts: Vec<f32> = (0..400_000).map(|_| rng.uniform()).collect();
        ts.extend((0..=64).map(|k| k as f32 / 64.0));
        ts.extend([-0.3, 1.7, 0.125f32.next_up(), 0.375f32.next_down(), 1.0f32.next_down()]);
        for t in ts {
            let (s, c) = sin_cos_turn(t);
            let phi = 2.0 * std::f64::consts::PI * t as f64;
            // Two ulp of a unit-sized value, and the f32 rounding of 2πt itself.
            let tol = 2.5e-7;
            assert!((s as f64 - phi.sin()).abs() < tol && (c as f64 - phi.cos()).abs() < tol, "{t}: {s} {c}");
        }
    }

    #[test]
    fn bilinear_samples_follow_the_bilinear_density() {
        let plane = |n: usize| Chi2Test {
            domain: Domain::Plane { min: Vec2::ZERO, max: Vec2::ONE },
            theta_res: n,
            phi_res: n,
            test_count: 4,
            ..tester()
        };
        for w in [[1.0, 1.0, 1.0, 1.0], [0.01, 1.0, 0.3, 2.0], [5.0, 0.0, 0.0, 0.2], [0.0, 0.0, 1.0, 1.0]] {
            let r = plane(40).run(|_, u| Some(sample_bilinear(u, w).extend(0.0)), |p| bilinear_pdf(p.truncate(), w));
            assert!(r.passed, "{w:?}: {r}");
        }
        // The marginal alone (x left uniform) is not the bilinear density.
        let w = [0.01, 1.0, 0.3, 2.0];
        let wrong = plane(40).run(
            |_, u| Some(Vec2::new(u.x, sample_linear(u.y, w[0] + w[1], w[2] + w[3])).extend(0.0)),
            |p| bilinear_pdf(p.truncate(), w),
        );
        assert!(!wrong.passed, "{wrong}");
        // The 1D density integrates to 1 (midpoint rule) and inverts its cdf.
        for (a, b) in [(0.2f32, 3.0f32), (1.0, 1.0), (0.0, 1.0), (4.0, 0.0)] {
            let n = 10_000;
            let integral: f32 = (0..n).map(|i| linear_pdf((i as f32 + 0.5) / n as f32, a, b)).sum::<f32>() / n as f32;
            assert!((integral - 1.0).abs() < 1e-4, "{a} {b}: {integral}");
            for u in [0.0f32, 0.1, 0.5, 0.93] {
                let x = sample_linear(u, a, b) as f64;
                let cdf = if a == b { x } else { ((b - a) as f64 * x * x + 2.0 * a as f64 * x) / (a + b) as f64 };
                assert!((cdf - u as f64).abs() < 1e-5, "{a} {b} {u}: cdf {cdf}");
            }
        }
    }

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
