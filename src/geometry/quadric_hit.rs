//! Exact ray–quadric intersection in object space (PBR 4th ed. §6.2.2, §6.3.2, §6.4.2): the
//! nearest hit inside the shape's z, φ and radius ranges, with pbrt-v4's (u, v), ∂p/∂u, ∂p/∂v and
//! a bound on the hit point's rounding error for spawning rays.
//!
//! The hit point is re-projected onto the surface (scaled to the radius for the sphere and the
//! cylinder, z set to the height for the disk); its error is then bounded by γ₅|p| for the
//! sphere, γ₃|x|, γ₃|y| for the cylinder and 0 for the disk (§6.8.5), with γₙ = nε/(1 − nε).
//! The quadratic's discriminant is taken as 4a(r² − |o − (b/2a) d|²), which keeps its digits
//! when the ray passes far from the centre (§6.8.1's rewriting).

use glam::{Vec2, Vec3};

use super::Quadric;

/// γₙ = nε/(1 − nε) with ε the unit roundoff of f32 (Higham 2002).
pub fn gamma(n: u32) -> f32 {
    let e = n as f32 * f32::EPSILON * 0.5;
    e / (1.0 - e)
}

/// A ray–quadric hit in object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Hit point, on the surface.
    pub p: Vec3,
    /// Per-axis bound on the absolute error of `p`.
    pub p_err: Vec3,
    /// pbrt-v4's (u, v) of the hit.
    pub uv: Vec2,
    /// ∂p/∂u.
    pub dpdu: Vec3,
    /// ∂p/∂v.
    pub dpdv: Vec3,
    /// Unit normal along ∂p/∂u × ∂p/∂v.
    pub n: Vec3,
}

/// The roots t₀ ≤ t₁ of a t² + b t + c = 0 whose discriminant is `disc` (≥ 0), without the
/// cancellation of the textbook formula.
fn roots(a: f32, b: f32, c: f32, disc: f32) -> (f32, f32) {
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    (t0.min(t1), t0.max(t1))
}

/// φ of (x, y) in [0, 2π).
fn azimuth(x: f32, y: f32) -> f32 {
    let phi = y.atan2(x);
    if phi < 0.0 {
        phi + 2.0 * std::f32::consts::PI
    } else {
        phi
    }
}

/// θ(z_min) and θ(z_max) of a sphere, θ = acos(z/r): π and 0 without the arccosine for the
/// uncut poles.
#[inline]
fn sphere_theta_range(radius: f32, z_min: f32, z_max: f32) -> (f32, f32) {
    let theta = |z: f32, pole: f32, at_pole: f32| {
        if z * pole >= radius {
            at_pole
        } else {
            (z / radius).clamp(-1.0, 1.0).acos()
        }
    };
    (theta(z_min, -1.0, std::f32::consts::PI), theta(z_max, 1.0, 0.0))
}

impl Quadric {
    /// The nearest hit of the ray o + t d with t in (0, `t_max`) on the shape, if any.
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<QuadricHit> {
        self.intersect_t(o, d, t_max).map(|t| self.surface_at(o, d, t))
    }

    /// The ray parameter of [`Quadric::intersect`]'s hit, found without the hit's (u, v) and
    /// derivatives.
    pub fn intersect_t(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        match *self {
            Quadric::Sphere { radius, .. } => {
                let a = d.length_squared();
                let b = 2.0 * d.dot(o);
                let c = o.length_squared() - radius * radius;
                let closest = o - (b / (2.0 * a)) * d;
                let disc = 4.0 * a * (radius * radius - closest.length_squared());
                self.first_of_roots((a, b, c, disc), o, d, t_max)
            }
            Quadric::Cylinder { radius, .. } => {
                let a = d.x * d.x + d.y * d.y;
                if a == 0.0 {
                    return None;
                }
                let b = 2.0 * (d.x * o.x + d.y * o.y);
                let c = o.x * o.x + o.y * o.y - radius * radius;
                let f = Vec2::new(o.x, o.y) - (b / (2.0 * a)) * Vec2::new(d.x, d.y);
                let disc = 4.0 * a * (radius * radius - f.length_squared());
                self.first_of_roots((a, b, c, disc), o, d, t_max)
            }
            Quadric::Disk { height, .. } => {
                if d.z == 0.0 {
                    return None;
                }
                let t = (height - o.z) / d.z;
                (t > 0.0 && t < t_max && self.contains(self.projected_point(o, d, t))).then_some(t)
            }
        }
    }

    /// The first root of the sphere's or cylinder's quadratic a t² + b t + c (discriminant
    /// `disc`) in (0, t_max) whose point lies in the shape's ranges.
    fn first_of_roots(&self, (a, b, c, disc): (f32, f32, f32, f32), o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let (t0, t1) = roots(a, b, c, disc);
        [t0, t1].into_iter().find(|&t| t > 0.0 && t < t_max && self.contains(self.projected_point(o, d, t)))
    }

    /// True when the re-projected hit point `p` lies within the shape's z, φ and radius ranges
    /// (φ is found only when the shape is cut in φ).
    fn contains(&self, p: Vec3) -> bool {
        let in_phi = |phi_max: f32| phi_max >= 360.0 || azimuth(p.x, p.y) <= phi_max.to_radians();
        match *self {
            Quadric::Sphere { radius, z_min, z_max, phi_max } => {
                let clipped_z = (z_min > -radius && p.z < z_min) || (z_max < radius && p.z > z_max);
                !clipped_z && in_phi(phi_max)
            }
            Quadric::Cylinder { z_min, z_max, phi_max, .. } => p.z >= z_min && p.z <= z_max && in_phi(phi_max),
            Quadric::Disk { radius, inner_radius, phi_max, .. } => {
                let dist2 = p.x * p.x + p.y * p.y;
                dist2 <= radius * radius && dist2 >= inner_radius * inner_radius && in_phi(phi_max)
            }
        }
    }

    /// The point at ray parameter `t` of o + t d re-projected onto the (unclipped) surface:
    /// scaled to the radius (the sphere: moved off its pole axis by 10⁻⁵ r if on it; the
    /// cylinder), or set to the disk's height.
    #[inline]
    fn projected_point(&self, o: Vec3, d: Vec3, t: f32) -> Vec3 {
        let mut p = o + t * d;
        match *self {
            Quadric::Sphere { radius, .. } => {
                p *= radius / p.length();
                if p.x == 0.0 && p.y == 0.0 {
                    p.x = 1e-5 * radius;
                }
            }
            Quadric::Cylinder { radius, .. } => {
                let rho = (p.x * p.x + p.y * p.y).sqrt();
                if rho > 0.0 {
                    p.x *= radius / rho;
                    p.y *= radius / rho;
                } else {
                    p.x = radius;
                }
            }
            Quadric::Disk { height, .. } => p.z = height,
        }
        p
    }

    /// The surface point at ray parameter `t` of o + t d, re-projected onto the (unclipped)
    /// surface, with its (u, v), derivatives and error bound. The interaction at a hit is
    /// recomputed by this from the hit's t, so both backends shade the same point.
    pub fn surface_at(&self, o: Vec3, d: Vec3, t: f32) -> QuadricHit {
        let p = self.projected_point(o, d, t);
        let (p_err, n) = self.error_and_normal(p);
        match *self {
            Quadric::Sphere { radius, z_min, z_max, phi_max } => {
                let phi = azimuth(p.x, p.y);
                let phi_max = phi_max.to_radians();
                let (theta_min, theta_max) = sphere_theta_range(radius, z_min, z_max);
                let cos_theta = (p.z / radius).clamp(-1.0, 1.0);
                let theta = cos_theta.acos();
                let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
                let rho = (p.x * p.x + p.y * p.y).sqrt();
                let (cos_phi, sin_phi) = (p.x / rho, p.y / rho);
                let dpdu = Vec3::new(-phi_max * p.y, phi_max * p.x, 0.0);
                let dpdv = (theta_max - theta_min) * Vec3::new(p.z * cos_phi, p.z * sin_phi, -radius * sin_theta);
                QuadricHit {
                    t,
                    p,
                    p_err,
                    uv: Vec2::new(phi / phi_max, (theta - theta_min) / (theta_max - theta_min)),
                    dpdu,
                    dpdv,
                    n,
                }
            }
            Quadric::Cylinder { z_min, z_max, phi_max, .. } => {
                let phi = azimuth(p.x, p.y);
                let phi_max = phi_max.to_radians();
                QuadricHit {
                    t,
                    p,
                    p_err,
                    uv: Vec2::new(phi / phi_max, (p.z - z_min) / (z_max - z_min)),
                    dpdu: Vec3::new(-phi_max * p.y, phi_max * p.x, 0.0),
                    dpdv: Vec3::new(0.0, 0.0, z_max - z_min),
                    n,
                }
            }
            Quadric::Disk { radius, inner_radius, phi_max, .. } => {
                let rho = (p.x * p.x + p.y * p.y).sqrt();
                let phi = azimuth(p.x, p.y);
                let phi_max = phi_max.to_radians();
                let dpdv = if rho > 0.0 {
                    Vec3::new(p.x, p.y, 0.0) * ((inner_radius - radius) / rho)
                } else {
                    Vec3::new(inner_radius - radius, 0.0, 0.0)
                };
                QuadricHit {
                    t,
                    p,
                    p_err,
                    uv: Vec2::new(phi / phi_max, (radius - rho) / (radius - inner_radius)),
                    dpdu: Vec3::new(-phi_max * p.y, phi_max * p.x, 0.0),
                    dpdv,
                    n,
                }
            }
        }
    }

    /// [`Quadric::surface_at`]'s point, error bound and normal only, with (u, v) and the
    /// derivatives left zero: what a boundary between media (an interface surface) needs.
    pub fn boundary_at(&self, o: Vec3, d: Vec3, t: f32) -> QuadricHit {
        let p = self.projected_point(o, d, t);
        let (p_err, n) = self.error_and_normal(p);
        QuadricHit { t, p, p_err, uv: Vec2::ZERO, dpdu: Vec3::ZERO, dpdv: Vec3::ZERO, n }
    }

    /// The error bound and unit normal at the re-projected point `p`.
    #[inline]
    fn error_and_normal(&self, p: Vec3) -> (Vec3, Vec3) {
        match *self {
            Quadric::Sphere { radius, .. } => (gamma(5) * p.abs(), p / radius),
            Quadric::Cylinder { radius, .. } => {
                (gamma(3) * Vec3::new(p.x.abs(), p.y.abs(), 0.0), Vec3::new(p.x / radius, p.y / radius, 0.0))
            }
            Quadric::Disk { .. } => (Vec3::ZERO, Vec3::Z),
        }
    }

    /// ∂n/∂u and ∂n/∂v at the surface point `h` (object space), from the second derivatives
    /// of p by the Weingarten equations (PBR 4th ed. §6.2.3, do Carmo 1976 §3.3): for the
    /// sphere ∂²p/∂u² = −φmax² (x, y, 0), ∂²p/∂u∂v = (θmax − θmin) z φmax (−sin φ, cos φ, 0),
    /// ∂²p/∂v² = −(θmax − θmin)² p; for the cylinder only ∂²p/∂u² = −φmax² (x, y, 0); the
    /// disk is flat.
    pub fn normal_derivatives(&self, h: &QuadricHit) -> (Vec3, Vec3) {
        let p = h.p;
        let (duu, duv, dvv) = match *self {
            Quadric::Sphere { radius, z_min, z_max, phi_max } => {
                let phi_max = phi_max.to_radians();
                let (theta_min, theta_max) = sphere_theta_range(radius, z_min, z_max);
                let theta_span = theta_max - theta_min;
                let rho = (p.x * p.x + p.y * p.y).sqrt().max(f32::MIN_POSITIVE);
                (
                    -phi_max * phi_max * Vec3::new(p.x, p.y, 0.0),
                    theta_span * p.z * phi_max * Vec3::new(-p.y / rho, p.x / rho, 0.0),
                    -theta_span * theta_span * p,
                )
            }
            Quadric::Cylinder { phi_max, .. } => {
                let phi_max = phi_max.to_radians();
                (-phi_max * phi_max * Vec3::new(p.x, p.y, 0.0), Vec3::ZERO, Vec3::ZERO)
            }
            Quadric::Disk { .. } => return (Vec3::ZERO, Vec3::ZERO),
        };
        super::weingarten::normal_derivatives(h.dpdu, h.dpdv, [duu, duv, dvv])
    }

    /// The object-space box of the whole shape (pbrt-v4 `Bounds()`).
    pub fn object_bounds(&self) -> super::Bounds3 {
        let (r, lo, hi) = match *self {
            Quadric::Sphere { radius, z_min, z_max, .. } | Quadric::Cylinder { radius, z_min, z_max, .. } => {
                (radius, z_min, z_max)
            }
            Quadric::Disk { height, radius, .. } => (radius, height, height),
        };
        super::Bounds3 { min: Vec3::new(-r, -r, lo), max: Vec3::new(r, r, hi) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::Rng;
    use std::f32::consts::PI;

    fn sphere(radius: f32, z_min: f32, z_max: f32, phi_max: f32) -> Quadric {
        Quadric::Sphere { radius, z_min, z_max, phi_max }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5 * (1.0 + b.length())
    }

    #[test]
    fn sphere_hits_match_hand_computed_points_normals_and_uv() {
        let s = sphere(2.0, -2.0, 2.0, 360.0);
        // Along +z from below: the south pole at t = 3, where θ = π and v = 0.
        let h = s.intersect(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, f32::INFINITY).unwrap();
        assert!((h.t - 3.0).abs() < 1e-6 && close(h.p, Vec3::new(0.0, 0.0, -2.0)) && close(h.n, -Vec3::Z));
        assert!(h.uv.y.abs() < 1e-6, "{:?}", h.uv);
        // Along −x onto the equator at φ = 0: u = 0, v = 1/2, ∂p/∂u = φmax (−y, x, 0) = (0, 4π, 0),
        // ∂p/∂v = (θmax − θmin)(z cos φ, z sin φ, −r sin θ) = −π (0, 0, −2).
        let h = s.intersect(Vec3::new(5.0, 0.0, 0.0), -Vec3::X, f32::INFINITY).unwrap();
        assert!((h.t - 3.0).abs() < 1e-6 && close(h.p, Vec3::new(2.0, 0.0, 0.0)) && close(h.n, Vec3::X));
        assert!((h.uv - Vec2::new(0.0, 0.5)).length() < 1e-6);
        assert!(close(h.dpdu, Vec3::new(0.0, 4.0 * PI, 0.0)) && close(h.dpdv, Vec3::new(0.0, 0.0, 2.0 * PI)));
        assert!(h.dpdu.cross(h.dpdv).normalize().dot(h.n) > 0.999);
        // At φ = π/4 on the equator of a quarter sphere: u = 1/2.
        let q = sphere(2.0, -2.0, 2.0, 90.0);
        let d = -Vec3::new(1.0, 1.0, 0.0).normalize();
        let h = q.intersect(Vec3::new(5.0, 5.0, 0.0), d, f32::INFINITY).unwrap();
        assert!(close(h.p, Vec3::new(2f32.sqrt(), 2f32.sqrt(), 0.0)) && (h.uv.x - 0.5).abs() < 1e-6);
        // A miss, and t_max before the hit.
        assert!(s.intersect(Vec3::new(0.0, 2.5, -5.0), Vec3::Z, f32::INFINITY).is_none());
        assert!(s.intersect(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 2.9).is_none());
    }

    #[test]
    fn clipped_ranges_reject_the_near_hit_and_keep_the_far_one() {
        // zmax = 1: the north pole is cut away, so a ray from above meets the inside of the
        // south pole at t = 7.
        let s = sphere(2.0, -2.0, 1.0, 360.0);
        let h = s.intersect(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, f32::INFINITY).unwrap();
        assert!((h.t - 7.0).abs() < 1e-5 && close(h.p, Vec3::new(0.0, 0.0, -2.0)));
        // zmin = −1 cuts the south pole instead: the same ray stops at the north pole.
        let s = sphere(2.0, -1.0, 2.0, 360.0);
        assert!((s.intersect(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, f32::INFINITY).unwrap().t - 3.0).abs() < 1e-5);
        // φmax = 90°: (−2, 0, 0) has φ = π and is cut away; (2, 0, 0) at t = 7 is kept.
        let s = sphere(2.0, -2.0, 2.0, 90.0);
        let h = s.intersect(Vec3::new(-5.0, 0.0, 0.0), Vec3::X, f32::INFINITY).unwrap();
        assert!((h.t - 7.0).abs() < 1e-5 && h.uv.x.abs() < 1e-6);
        // Both roots cut: no hit.
        assert!(s.intersect(Vec3::new(-5.0, -0.5, 0.0), Vec3::new(1.0, -0.3, 0.0).normalize(), 100.0).is_none());
        // Cylinder r = 1, z ∈ [−1, 1], φmax = 180°: (0, −1, 0) is at φ = 3π/2, cut; (0, 1, 0) kept with
        // u = 1/2, v = 1/2; above zmax nothing.
        let c = Quadric::Cylinder { radius: 1.0, z_min: -1.0, z_max: 1.0, phi_max: 180.0 };
        let h = c.intersect(Vec3::new(0.0, -3.0, 0.0), Vec3::Y, f32::INFINITY).unwrap();
        assert!((h.t - 4.0).abs() < 1e-5 && close(h.p, Vec3::Y) && (h.uv - Vec2::new(0.5, 0.5)).length() < 1e-5);
        assert!(close(h.n, Vec3::Y) && close(h.dpdv, Vec3::new(0.0, 0.0, 2.0)));
        let full = Quadric::Cylinder { radius: 1.0, z_min: -1.0, z_max: 1.0, phi_max: 360.0 };
        let h = full.intersect(Vec3::new(3.0, 0.0, 0.5), -Vec3::X, f32::INFINITY).unwrap();
        assert!((h.t - 2.0).abs() < 1e-5 && (h.uv - Vec2::new(0.0, 0.75)).length() < 1e-5);
        assert!(full.intersect(Vec3::new(3.0, 0.0, 1.5), -Vec3::X, f32::INFINITY).is_none());
        assert!(full.intersect(Vec3::new(0.5, 0.0, -3.0), Vec3::Z, f32::INFINITY).is_none(), "parallel to the axis");
        // Annulus z = 0.5, r ∈ [0.25, 1], φmax = 270°: v = (r − ρ)/(r − rᵢ).
        let d = Quadric::Disk { height: 0.5, radius: 1.0, inner_radius: 0.25, phi_max: 270.0 };
        let h = d.intersect(Vec3::new(0.5, 0.0, 2.0), -Vec3::Z, f32::INFINITY).unwrap();
        assert!((h.t - 1.5).abs() < 1e-6 && h.p == Vec3::new(0.5, 0.0, 0.5) && h.p_err == Vec3::ZERO);
        assert!((h.uv - Vec2::new(0.0, 2.0 / 3.0)).length() < 1e-6 && h.n == Vec3::Z);
        for miss in [Vec3::new(0.1, 0.0, 2.0), Vec3::new(1.1, 0.0, 2.0), Vec3::new(0.3, -0.5, 2.0)] {
            assert!(d.intersect(miss, -Vec3::Z, f32::INFINITY).is_none(), "hole, rim, or φ = 301° > φmax: {miss}");
        }
    }

    /// The hit point's error box p ± p_err holds a point of the exact surface — the closest one
    /// to p, found in f64 — on random rays through each shape (that is what ray spawning needs:
    /// an offset beyond the box leaves the surface behind). Rays start up to 50 units away, so
    /// the raw o + t d is off the surface by far more than the bound.
    #[test]
    fn error_bounds_contain_the_surface() {
        let mut rng = Rng::new(2, 7);
        let mut u = || rng.uniform();
        let shapes = [
            sphere(1.7, -1.7, 1.7, 360.0),
            sphere(0.9, -0.55, 0.65, 290.0),
            Quadric::Cylinder { radius: 0.7, z_min: -0.5, z_max: 1.3, phi_max: 240.0 },
        ];
        let mut hits = 0;
        let mut raw_beyond = 0;
        for q in shapes {
            for _ in 0..20_000 {
                let o = Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5) * 40.0 + Vec3::new(60.0 * u(), 3.0, -2.0);
                let aim = Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5) * 3.0;
                let d = (aim - o).normalize();
                let Some(h) = q.intersect(o, d, f32::INFINITY) else { continue };
                hits += 1;
                let p = h.p.as_dvec3();
                let surface = match q {
                    Quadric::Sphere { radius, .. } => p * (radius as f64 / p.length()),
                    Quadric::Cylinder { radius, .. } => {
                        let rho = (p.x * p.x + p.y * p.y).sqrt();
                        glam::DVec3::new(p.x * radius as f64 / rho, p.y * radius as f64 / rho, p.z)
                    }
                    Quadric::Disk { .. } => unreachable!(),
                };
                let err = (surface - p).abs();
                assert!(err.cmple(h.p_err.as_dvec3()).all(), "{q:?}: {err} off the surface, bound {}", h.p_err);
                // The point before re-projection would not do.
                let raw = (o + h.t * d).as_dvec3();
                let raw_off = match q {
                    Quadric::Sphere { radius, .. } => (raw.length() - radius as f64).abs(),
                    _ => ((raw.x * raw.x + raw.y * raw.y).sqrt() - 0.7).abs(),
                };
                raw_beyond += (raw_off > h.p_err.length() as f64) as usize;
            }
        }
        assert!(raw_beyond * 4 > hits, "the raw points were within the bound too: {raw_beyond} of {hits}");
        assert!(hits > 10_000, "{hits} hits");
    }
}
