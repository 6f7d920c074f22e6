//! A diffuse area light on a full sphere, sampled as pbrt-v4 samples spheres (PBR 4th ed.
//! §6.2.4): from a point outside, uniformly over the cone of directions the sphere subtends
//! (density 1/(2π(1 − cos θmax)), sin θmax = r/d); from a point inside, uniformly by area
//! (density d²/(|cos θ_l| A) in solid angle).
//!
//! Rays meet the exact sphere (the analytic quadric the light is attached to), so a shadow ray
//! toward a sampled point stops just short of it (pbrt-v4's shadow epsilon) from outside and
//! from inside alike.

use super::point::spectral_integral;
use super::sampler::LightBounds;
use super::selection_flux::{max_value, visible_flux};
use super::LightSample;
use crate::geometry::Bounds3;
use crate::math::{Frame, PI};
use crate::sampling::warp::{sample_uniform_sphere, sin_cos_turn};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// Below sin²θmax = sin²(1.5°), 1 − cos θ loses its digits in f32: pbrt-v4 switches to the
/// expansions 1 − cos θmax ≈ sin²θmax / 2 and sin²θ ≈ u·sin²θmax there.
const SMALL_SIN2: f32 = 0.000_685_23;

/// An emitting sphere of constant radiance L = `scale · spectrum(λ)` [W/(sr·m²·nm)].
#[derive(Clone, Debug)]
pub struct SphereLight {
    /// Centre [scene units].
    pub center: Vec3,
    /// Radius [scene units].
    pub radius: f32,
    /// Spectral shape of the radiance.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` into radiance L.
    pub scale: f32,
    /// Emits from both sides.
    pub two_sided: bool,
    /// The emitting side faces the centre (reversed orientation).
    pub inward: bool,
}

/// Distances along the unit `d` from `o` where the ray meets the sphere of radius `r` about `c`
/// (smaller first), from the quadratic with the cancellation-free root pair (PBR 4th ed. §6.8.1
/// discusses the same rewriting).
fn sphere_roots(o: Vec3, d: Vec3, c: Vec3, r: f32) -> Option<(f32, f32)> {
    let f = o - c;
    let b = f.dot(d);
    // b² − (|f|² − r²) with |f|² − b² = |f − b d|², the squared distance of the closest approach.
    let closest = (f - b * d).length_squared();
    let disc = r * r - closest;
    if disc < 0.0 {
        return None;
    }
    let q = -b - disc.sqrt().copysign(b);
    let c_term = f.length_squared() - r * r;
    let (t0, t1) = if q != 0.0 { (c_term / q, q) } else { (0.0, 0.0) };
    Some((t0.min(t1), t0.max(t1)))
}

impl SphereLight {
    /// Area 4πr² [scene units²].
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// Radiance leaving the surface with normal `n` on its emitting side toward `w`.
    #[inline]
    pub fn radiance(&self, n: Vec3, w: Vec3, lambdas: &SampledWavelengths) -> SampledSpectrum {
        if !self.two_sided && n.dot(w) <= 0.0 {
            return SampledSpectrum::zero();
        }
        self.spectrum.sample(lambdas) * self.scale
    }

    /// Normal of the emitting side at the point `q` of the sphere.
    fn emitting_normal(&self, q: Vec3) -> Vec3 {
        let n = (q - self.center) / self.radius;
        if self.inward {
            -n
        } else {
            n
        }
    }

    /// 1 − cos θmax and sin²θmax of the cone the sphere subtends at squared distance `d2` from
    /// its centre.
    fn cone(&self, d2: f32) -> (f32, f32) {
        let sin2_max = self.radius * self.radius / d2;
        let one_minus_cos = if sin2_max < SMALL_SIN2 { 0.5 * sin2_max } else { 1.0 - (1.0 - sin2_max).max(0.0).sqrt() };
        (one_minus_cos, sin2_max)
    }

    pub(super) fn sample_li(&self, p: Vec3, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let to_center = self.center - p;
        let d2 = to_center.length_squared();
        let (q, wi, pdf, target) = if d2 > self.radius * self.radius {
            let (one_minus_cos_max, sin2_max) = self.cone(d2);
            // θ from the axis toward the centre, uniform in cos θ over [cos θmax, 1].
            let (cos_theta, sin2_theta) = if sin2_max < SMALL_SIN2 {
                let s2 = sin2_max * u.x;
                ((1.0 - s2).sqrt(), s2)
            } else {
                let c = 1.0 - u.x * one_minus_cos_max;
                (c, (1.0 - c * c).max(0.0))
            };
            // The angle α at the centre between −axis and the point hit (law of sines in the
            // triangle p, centre, point): cos α = sin²θ / sin θmax + cos θ √(1 − sin²θ / sin²θmax).
            let sin_max = sin2_max.sqrt();
            let cos_alpha = sin2_theta / sin_max + cos_theta * (1.0 - sin2_theta / sin2_max).max(0.0).sqrt();
            let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
            let (sin_phi, cos_phi) = sin_cos_turn(u.y);
            let frame = Frame::from_normal(to_center / d2.sqrt());
            let local = Vec3::new(sin_alpha * cos_phi, sin_alpha * sin_phi, cos_alpha);
            let q = self.center - self.radius * frame.to_world(local);
            let wi = (q - p).normalize_or_zero();
            (q, wi, 1.0 / (2.0 * PI * one_minus_cos_max), q)
        } else {
            let q = self.center + self.radius * sample_uniform_sphere(u);
            let d = q - p;
            let dist2 = d.length_squared();
            let wi = d / dist2.sqrt();
            let cos_l = ((q - self.center) / self.radius).dot(wi).abs();
            (q, wi, dist2 / (cos_l * self.area()), q)
        };
        if !(pdf.is_finite() && pdf > 0.0) || wi == Vec3::ZERO {
            return None;
        }
        let li = self.radiance(self.emitting_normal(q), -wi, w);
        let dist = (target - p).length();
        (!li.is_black() && dist > 0.0).then_some(LightSample { li, wi, pdf, p_light: target, dist })
    }

    /// Solid-angle density with which `sample_li` at `p` picks the unit direction `wi`: the cone's
    /// uniform density for directions inside it from outside, the area density at the exit point
    /// from inside; 0 for directions that miss the sphere.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3) -> f32 {
        let to_center = self.center - p;
        let d2 = to_center.length_squared();
        if d2 > self.radius * self.radius {
            let (one_minus_cos_max, _) = self.cone(d2);
            // Inside the cone: the closest approach of the ray is within the sphere.
            let along = to_center.dot(wi);
            // (A relative tolerance keeps the sampled silhouette directions against rounding.)
            if along <= 0.0 || d2 - along * along > self.radius * self.radius * (1.0 + 1e-5) {
                return 0.0;
            }
            return 1.0 / (2.0 * PI * one_minus_cos_max);
        }
        let Some((_, t)) = sphere_roots(p, wi, self.center, self.radius) else { return 0.0 };
        let q = p + wi * t;
        let cos_l = ((q - self.center) / self.radius).dot(wi).abs();
        if cos_l == 0.0 {
            return 0.0;
        }
        t * t / (cos_l * self.area())
    }

    /// The radiant flux Φ = π L A per emitting side [W], L integrated over 360–830 nm (what it
    /// emits; [`SphereLight::power`] is the weight light samplers choose it by).
    pub fn radiant_flux(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        PI * self.area() * sides * self.scale * spectral_integral(&self.spectrum)
    }

    /// pbrt-v4's `DiffuseAreaLight::Phi` for the power sampler: π L A per emitting side, L's
    /// spectrum by `visible_flux` (see `selection_flux`).
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        PI * self.area() * sides * self.scale * visible_flux(&self.spectrum)
    }

    /// pbrt-v4's `DiffuseAreaLight::Bounds` flux: π A scale MaxValue(L) for one side, two-sided
    /// or not (see `selection_flux`).
    pub fn bound_flux(&self) -> f32 {
        PI * self.area() * self.scale * max_value(&self.spectrum)
    }

    /// Bounds for many-light sampling, emitting flux `phi`: the sphere's box, emitting along
    /// every normal (θ_o = π) up to θ_e = π/2.
    pub(super) fn bounds(&self, phi: f32) -> LightBounds {
        let bounds =
            Bounds3 { min: self.center - Vec3::splat(self.radius), max: self.center + Vec3::splat(self.radius) };
        LightBounds { bounds, w: Vec3::Z, phi, cos_theta_o: -1.0, cos_theta_e: 0.0, two_sided: self.two_sided }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::Rng;

    fn light(center: Vec3, radius: f32) -> SphereLight {
        SphereLight {
            center,
            radius,
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 1.0,
            two_sided: false,
            inward: false,
        }
    }

    fn uniform2(rng: &mut Rng) -> Vec2 {
        Vec2::new(rng.uniform(), rng.uniform())
    }

    #[test]
    fn samples_from_outside_lie_on_the_near_side_and_pdf_li_agrees() {
        let w = SampledWavelengths::sample_visible(0.5);
        let mut rng = Rng::new(11, 2);
        // Far (small-angle branch: sin²θmax = 10⁻⁴) and near.
        for (c, r) in [(Vec3::new(0.0, 0.0, 100.0), 1.0f32), (Vec3::new(0.3, -2.0, 1.0), 1.2)] {
            let s = light(c, r);
            for _ in 0..20_000 {
                let ls = s.sample_li(Vec3::ZERO, uniform2(&mut rng), &w).expect("a point outside sees its light");
                let q = ls.p_light;
                assert!(((q - c).length() - r).abs() < 2e-5 * c.length(), "sample {q} not on the sphere");
                // On the near side: the outward normal faces the reference point.
                assert!((q - c).dot(-q) >= -1e-3 * r * c.length(), "sample {q} on the far side");
                assert!((ls.wi - q.normalize()).length() < 1e-4);
                let pdf = s.pdf_li(Vec3::ZERO, ls.wi);
                assert!((pdf - ls.pdf).abs() <= 1e-4 * ls.pdf, "pdf_li {pdf} vs sampled {}", ls.pdf);
            }
            // A direction outside the cone has density 0.
            assert_eq!(s.pdf_li(Vec3::ZERO, -c.normalize()), 0.0);
        }
    }

    /// χ² test of the cone sampling against the density `pdf_li` reports: directions binned in
    /// (cos θ, φ) about the axis to the centre, expected counts from the analytic density
    /// (uniform over the cone, so each bin's share is its solid angle over the cone's).
    #[test]
    fn cone_sampling_passes_chi_square_against_its_density() {
        let s = light(Vec3::new(0.5, 1.0, 2.5), 1.3);
        let p = Vec3::ZERO;
        let axis = (s.center - p).normalize();
        let frame = Frame::from_normal(axis);
        let cos_max = (1.0 - s.radius * s.radius / (s.center - p).length_squared()).sqrt();
        let (n_theta, n_phi) = (10usize, 12usize);
        let mut counts = vec![0u32; n_theta * n_phi];
        let w = SampledWavelengths::sample_visible(0.5);
        let mut rng = Rng::new(5, 9);
        let n = 200_000;
        for _ in 0..n {
            let ls = s.sample_li(p, uniform2(&mut rng), &w).unwrap();
            let l = frame.to_local(ls.wi);
            let t = ((1.0 - l.z) / (1.0 - cos_max) * n_theta as f32).min(n_theta as f32 - 1.0) as usize;
            let mut phi = l.y.atan2(l.x);
            if phi < 0.0 {
                phi += 2.0 * PI;
            }
            let k = ((phi / (2.0 * PI) * n_phi as f32) as usize).min(n_phi - 1);
            counts[t * n_phi + k] += 1;
        }
        // Expected share of a bin from the reported density integrated over it (midpoint rule
        // over a sub-grid; the density is constant, so this checks pdf_li's value too).
        let mut chi2 = 0.0f64;
        for t in 0..n_theta {
            for k in 0..n_phi {
                let mut mass = 0.0f64;
                let sub = 8;
                for a in 0..sub {
                    for b in 0..sub {
                        let c = 1.0 - (t as f32 + (a as f32 + 0.5) / sub as f32) / n_theta as f32 * (1.0 - cos_max);
                        let phi = (k as f32 + (b as f32 + 0.5) / sub as f32) / n_phi as f32 * 2.0 * PI;
                        let sin = (1.0 - c * c).sqrt();
                        let d = frame.to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), c));
                        let d_omega = (1.0 - cos_max) / (n_theta * sub) as f32 * 2.0 * PI / (n_phi * sub) as f32;
                        mass += (s.pdf_li(p, d) * d_omega) as f64;
                    }
                }
                let expected = mass * n as f64;
                let o = counts[t * n_phi + k] as f64;
                chi2 += (o - expected).powi(2) / expected;
            }
        }
        // 119 degrees of freedom: the 99.9th percentile of χ² is 170.
        assert!(chi2 < 170.0, "χ² = {chi2}");
    }

    /// E = ∫ L cos θ dω over the cone = π L sin²θmax for a normal facing the centre (PBR 4th ed.
    /// §4.2): the estimator Σ L cos θ / pdf over cone samples must agree within 3.5 standard
    /// errors (measured from the same samples), near and in the small-angle branch (there plus
    /// the expansion's own bias).
    #[test]
    fn irradiance_from_a_sphere_matches_pi_l_sin2_theta_max() {
        let w = SampledWavelengths::sample_visible(0.5);
        let mut rng = Rng::new(1, 4);
        for (d, r) in [(3.0f32, 1.0f32), (1.3, 1.0), (200.0, 1.0)] {
            let s = light(Vec3::new(0.0, d, 0.0), r);
            let n = 100_000;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let ls = s.sample_li(Vec3::ZERO, uniform2(&mut rng), &w).unwrap();
                let f = (ls.li[0] * ls.wi.y.max(0.0) / ls.pdf) as f64;
                sum += f;
                sum2 += f * f;
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            let sin2_max = (r as f64 / d as f64).powi(2);
            let exact = std::f64::consts::PI * sin2_max;
            // In the small-angle branch 1 − cos θmax ≈ sin²θmax/2 drops sin⁴θmax/8: a relative
            // bias of sin²θmax/4 (2.5·10⁻⁶ at d = 200), beside f32 rounding of each sample.
            let bias = if sin2_max < SMALL_SIN2 as f64 { sin2_max / 4.0 + 1e-6 } else { 0.0 } * exact;
            assert!(se > 0.0 && (mean - exact).abs() < 3.5 * se + bias, "d {d}: E {mean} ± {se} vs {exact}");
        }
    }

    #[test]
    fn from_inside_points_are_sampled_by_area_on_the_sphere() {
        let mut s = light(Vec3::new(1.0, 0.0, 0.0), 2.0);
        s.inward = true;
        let w = SampledWavelengths::sample_visible(0.5);
        let mut rng = Rng::new(8, 8);
        let p = Vec3::new(1.5, 0.4, -0.3);
        // E at the centre of an inward sphere of radiance L: π L on each side of any plane;
        // here a point off centre still sees the whole sphere: ∫ L |cos θ| dω over all
        // directions = 2π L.
        let n = 200_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let ls = s.sample_li(p, uniform2(&mut rng), &w).unwrap();
            assert!(((ls.p_light - s.center).length() - s.radius).abs() <= 1e-5 * s.radius);
            let pdf = s.pdf_li(p, ls.wi);
            assert!((pdf - ls.pdf).abs() <= 1e-3 * ls.pdf, "pdf_li {pdf} vs sampled {}", ls.pdf);
            let f = (ls.li[0] * ls.wi.z.abs() / ls.pdf) as f64;
            sum += f;
            sum2 += f * f;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!((mean - 2.0 * std::f64::consts::PI).abs() < 3.5 * se, "∫ L |cos| dω = {mean} ± {se}");
        // An outward one-sided sphere sends nothing inside.
        s.inward = false;
        assert!(s.sample_li(p, Vec2::new(0.3, 0.6), &w).is_none());
    }
}
