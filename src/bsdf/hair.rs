//! Scattering from a hair fibre: Chiang, Bitterli, Tappan & Burley 2016, "A Practical and
//! Controllable Hair and Fur Model for Production Path Tracing" (the model of pbrt-v4's
//! `HairBxDF`, book §9.9 of the 3rd edition).
//!
//! The fibre is a dielectric cylinder with an absorbing interior. In the local frame x runs
//! along the fibre (∂p/∂u of the curve), so for a direction ω the longitudinal angle θ has
//! sin θ = ω.x and the azimuth is φ = atan2(ω.z, ω.y). Light leaving after p internal path
//! segments (p = 0: R, 1: TT, 2: TRT, and p ≥ 3 summed in one term) is the product of
//! - a longitudinal lobe M_p(θi, θo): d'Eon et al. 2011's normalised lobe around the mirror
//!   angle −θo, tilted by the cuticle scales (−2α for R, α for TT, 4α for TRT), with variance
//!   v_p from β_m (Chiang et al. eq. 7; v₁ = v₀/4, v₂ = v₃ = 4 v₀);
//! - an attenuation A_p: Fresnel at the entry and each internal bounce and Beer–Lambert
//!   absorption along the chord 2 cos γt / cos θt (in fibre radii);
//! - an azimuthal lobe N_p(φ): a logistic of scale s (from β_n, eq. 8) around the deflection
//!   Φ(p) = 2p γt − 2γo + pπ, trimmed to [−π, π];
//!
//! so that f |cos θ_n| = Σ_p M_p A_p N_p, θ_n measured from the local z axis. With no absorption
//! Σ_p A_p = 1 and each lobe integrates to 1, so the fibre scatters exactly the energy it
//! receives. The model is not reciprocal: A_p and the chord depend on ωo alone, as in the paper.

use super::fresnel::fr_dielectric;
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Vec2, Vec3};
use crate::spectrum::SampledSpectrum;
use std::f32::consts::PI;

/// Number of explicit lobes (R, TT, TRT); higher orders are one term.
const P_MAX: usize = 3;

/// The fibre's BSDF at one hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hair {
    /// Offset of the hit across the fibre, h = sin γo ∈ [−1, 1].
    h: f32,
    /// Relative index of refraction of the fibre (pbrt-v4's default 1.55).
    eta: f32,
    /// Absorption coefficient of the interior [1 / fibre radius].
    sigma_a: SampledSpectrum,
    /// Longitudinal variance of the R lobe.
    v0: f32,
    /// Azimuthal logistic scale.
    s: f32,
    /// sin and cos of the cuticle scale angle α.
    sin_alpha: f32,
    cos_alpha: f32,
}

impl Hair {
    /// A fibre hit at offset `h`, with index `eta`, interior absorption `sigma_a` [1/radius],
    /// longitudinal and azimuthal roughness `beta_m`, `beta_n` ∈ [0, 1] and scale tilt
    /// `alpha_deg` [degrees].
    pub fn new(h: f32, eta: f32, sigma_a: SampledSpectrum, beta_m: f32, beta_n: f32, alpha_deg: f32) -> Self {
        let (bm, bn) = (beta_m.clamp(1e-3, 1.0), beta_n.clamp(1e-3, 1.0));
        // Chiang et al. 2016 eqs. 7 and 8: roughness to lobe widths.
        let v0 = (0.726 * bm + 0.812 * bm * bm + 3.7 * bm.powi(20)).powi(2);
        let s = (PI / 8.0).sqrt() * (0.265 * bn + 1.194 * bn * bn + 5.372 * bn.powi(22));
        let (sin_alpha, cos_alpha) = alpha_deg.to_radians().sin_cos();
        Self { h: h.clamp(-1.0, 1.0), eta, sigma_a: sigma_a.map(|x| x.max(0.0)), v0, s, sin_alpha, cos_alpha }
    }

    /// Longitudinal variance of lobe p.
    fn v(&self, p: usize) -> f32 {
        match p {
            0 => self.v0,
            1 => 0.25 * self.v0,
            _ => 4.0 * self.v0,
        }
    }

    /// (sin, cos) of the scale tilt of lobe p < P_MAX: −2α, α, 4α.
    fn tilt(&self, p: usize) -> (f32, f32) {
        let (s1, c1) = (self.sin_alpha, self.cos_alpha);
        let (s2, c2) = (2.0 * s1 * c1, c1 * c1 - s1 * s1);
        match p {
            0 => (-s2, c2),
            1 => (s1, c1),
            _ => (2.0 * s2 * c2, c2 * c2 - s2 * s2),
        }
    }

    /// The geometry every evaluation needs for ωo.
    fn exit(&self, wo: Vec3) -> Exit {
        let sin_o = wo.x.clamp(-1.0, 1.0);
        let cos_o = safe_sqrt(1.0 - sin_o * sin_o);
        let phi_o = wo.z.atan2(wo.y);
        // Refraction into the fibre: the longitudinal angle by Snell's law, the azimuthal one
        // with Bravais's index η' (Marschner et al. 2003).
        let sin_t = sin_o / self.eta;
        let cos_t = safe_sqrt(1.0 - sin_t * sin_t);
        let eta_p = safe_sqrt(self.eta * self.eta - sin_o * sin_o) / cos_o;
        let sin_gamma_t = (self.h / eta_p).clamp(-1.0, 1.0);
        let cos_gamma_t = safe_sqrt(1.0 - sin_gamma_t * sin_gamma_t);
        let transmittance = (self.sigma_a * (-2.0 * cos_gamma_t / cos_t)).exp();
        let ap = attenuation(cos_o, self.eta, self.h, transmittance);
        Exit { sin_o, cos_o, phi_o, gamma_o: self.h.asin(), gamma_t: sin_gamma_t.asin(), ap }
    }

    /// The probability of each lobe when sampling: its attenuation averaged over the
    /// wavelengths, normalised.
    fn lobe_pmf(ap: &[SampledSpectrum; P_MAX + 1]) -> [f32; P_MAX + 1] {
        let y = ap.map(|a| a.average().max(0.0));
        let total: f32 = y.iter().sum();
        if total > 0.0 {
            y.map(|v| v / total)
        } else {
            [0.25; P_MAX + 1]
        }
    }

    /// Σ_p M_p w_p N_p for lobe weights `w(p)`, at ωi (the shared body of `f` and `pdf`).
    fn lobe_sum<T>(&self, e: &Exit, wi: Vec3, zero: T, w: impl Fn(usize) -> T) -> T
    where
        T: std::ops::Add<Output = T> + std::ops::Mul<f32, Output = T>,
    {
        let sin_i = wi.x.clamp(-1.0, 1.0);
        let cos_i = safe_sqrt(1.0 - sin_i * sin_i);
        let phi = wi.z.atan2(wi.y) - e.phi_o;
        let mut sum = zero;
        for p in 0..P_MAX {
            let (st, ct) = self.tilt(p);
            let sin_op = e.sin_o * ct + e.cos_o * st;
            let cos_op = (e.cos_o * ct - e.sin_o * st).abs();
            let m = longitudinal(cos_i, cos_op, sin_i, sin_op, self.v(p));
            sum = sum + w(p) * (m * azimuthal(phi, p, self.s, e.gamma_o, e.gamma_t));
        }
        let m = longitudinal(cos_i, e.cos_o, sin_i, e.sin_o, self.v(P_MAX));
        sum + w(P_MAX) * (m / (2.0 * PI))
    }

    /// f(ωo, ωi) [1/sr], divided by |cos θ_n| so that the integrator's cosine cancels.
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        self.f_at(&self.exit(wo), wi)
    }

    /// [`Self::f`] for the exit geometry `e` of ωo.
    fn f_at(&self, e: &Exit, wi: Vec3) -> SampledSpectrum {
        let f = self.lobe_sum(e, wi, SampledSpectrum::zero(), |p| e.ap[p]);
        let cos_n = wi.z.abs();
        if cos_n > 0.0 {
            f * (1.0 / cos_n)
        } else {
            f
        }
    }

    /// Chooses a lobe by its attenuation with `uc`, then θi from M_p (d'Eon et al. 2011's
    /// sampling of the lobe about −θo) with `u`, and φi from N_p with the remainder of `uc`.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let e = self.exit(wo);
        let pmf = Self::lobe_pmf(&e.ap);
        let (mut p, mut uc) = (P_MAX, uc.clamp(0.0, 1.0 - f32::EPSILON));
        for (i, &q) in pmf.iter().enumerate() {
            if uc < q || i == P_MAX {
                p = i;
                uc = (uc / q).min(1.0 - f32::EPSILON);
                break;
            }
            uc -= q;
        }
        let (sin_op, cos_op) = if p < P_MAX {
            let (st, ct) = self.tilt(p);
            (e.sin_o * ct + e.cos_o * st, (e.cos_o * ct - e.sin_o * st).abs())
        } else {
            (e.sin_o, e.cos_o)
        };
        let v = self.v(p);
        let cos_theta = 1.0 + v * (u.x.max(1e-5) + (1.0 - u.x) * (-2.0 / v).exp()).ln();
        let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
        let cos_phi = (2.0 * PI * u.y).cos();
        let sin_i = (-cos_theta * sin_op + sin_theta * cos_phi * cos_op).clamp(-1.0, 1.0);
        let cos_i = safe_sqrt(1.0 - sin_i * sin_i);
        let dphi = if p < P_MAX {
            deflection(p, e.gamma_o, e.gamma_t) + sample_trimmed_logistic(uc, self.s)
        } else {
            2.0 * PI * uc
        };
        let phi_i = e.phi_o + dphi;
        let wi = Vec3::new(sin_i, cos_i * phi_i.cos(), cos_i * phi_i.sin());
        let pdf = self.lobe_sum(&e, wi, 0.0, |q| pmf[q]);
        Some(BsdfSample::new(self.f_at(&e, wi), wi, pdf, BxdfFlags::GLOSSY_REFLECTION))
    }

    /// Density of [`Self::sample_f`] [1/sr].
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        let e = self.exit(wo);
        let pmf = Self::lobe_pmf(&e.ap);
        self.lobe_sum(&e, wi, 0.0, |p| pmf[p])
    }

    /// Lobes present: glossy, in every direction (pbrt-v4 reports it as reflection).
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::GLOSSY_REFLECTION
    }
}

/// The outgoing direction's angles and the lobes' attenuations.
struct Exit {
    sin_o: f32,
    cos_o: f32,
    phi_o: f32,
    gamma_o: f32,
    gamma_t: f32,
    ap: [SampledSpectrum; P_MAX + 1],
}

fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// A_p: Fresnel reflectance f at the entry (cos θ = cos θo cos γo), then (1 − f)² T for TT,
/// one more T f per internal bounce, and the geometric series of the rest.
fn attenuation(cos_o: f32, eta: f32, h: f32, t: SampledSpectrum) -> [SampledSpectrum; P_MAX + 1] {
    let f = fr_dielectric(cos_o * safe_sqrt(1.0 - h * h), eta);
    let a0 = SampledSpectrum::splat(f);
    let a1 = t * ((1.0 - f) * (1.0 - f));
    let a2 = a1 * t * f;
    let tf = t * f;
    let a3 = (a2 * tf).safe_div(SampledSpectrum::one() - tf);
    [a0, a1, a2, a3]
}

/// d'Eon et al. 2011's longitudinal lobe of variance v, normalised over the sphere, in the
/// log domain for narrow lobes where sinh(1/v) and I₀ overflow.
fn longitudinal(cos_i: f32, cos_o: f32, sin_i: f32, sin_o: f32, v: f32) -> f32 {
    let a = cos_i * cos_o / v;
    let b = sin_i * sin_o / v;
    if v <= 0.1 {
        (log_bessel_i0(a) - b - 1.0 / v + std::f32::consts::LN_2 + (1.0 / (2.0 * v)).ln()).exp()
    } else {
        (-b).exp() * bessel_i0(a) / ((1.0 / v).sinh() * 2.0 * v)
    }
}

/// The modified Bessel function I₀ by its power series Σ (x²/4)^k / (k!)², summed until the
/// terms fall below single precision (ten fixed terms, as pbrt-v4 sums, leave I₀(12) 2% low and
/// the lobe under-normalised).
fn bessel_i0(x: f32) -> f32 {
    let q = x * x / 4.0;
    let (mut term, mut sum) = (1.0f32, 1.0f32);
    for k in 1..64 {
        term *= q / (k * k) as f32;
        sum += term;
        if term < 1e-8 * sum {
            break;
        }
    }
    sum
}

/// ln I₀(x), for large x by the asymptotic expansion I₀(x) ≈ eˣ / √(2πx) · (1 + 1/(8x) +
/// 9/(128x²) + 225/(3072x³)) (Abramowitz & Stegun 9.7.1), whose next term is below 10⁻⁵ at 12.
fn log_bessel_i0(x: f32) -> f32 {
    if x > 12.0 {
        let r = 1.0 / x;
        x - 0.5 * (2.0 * PI * x).ln() + (1.0 + r * (1.0 / 8.0 + r * (9.0 / 128.0 + r * 225.0 / 3072.0))).ln()
    } else {
        bessel_i0(x).ln()
    }
}

/// Φ(p): the azimuthal deflection of lobe p.
fn deflection(p: usize, gamma_o: f32, gamma_t: f32) -> f32 {
    let p = p as f32;
    2.0 * p * gamma_t - 2.0 * gamma_o + p * PI
}

/// N_p(φ): the logistic of scale s about Φ(p), trimmed to [−π, π] and normalised there.
fn azimuthal(phi: f32, p: usize, s: f32, gamma_o: f32, gamma_t: f32) -> f32 {
    let d = (phi - deflection(p, gamma_o, gamma_t) + PI).rem_euclid(2.0 * PI) - PI;
    logistic(d, s) / (logistic_cdf(PI, s) - logistic_cdf(-PI, s))
}

fn logistic(x: f32, s: f32) -> f32 {
    let e = (-x.abs() / s).exp();
    e / (s * (1.0 + e) * (1.0 + e))
}

fn logistic_cdf(x: f32, s: f32) -> f32 {
    1.0 / (1.0 + (-x / s).exp())
}

/// Inverts the trimmed logistic's distribution function on [−π, π].
fn sample_trimmed_logistic(u: f32, s: f32) -> f32 {
    let (lo, hi) = (logistic_cdf(-PI, s), logistic_cdf(PI, s));
    let x = -s * (1.0 / (u * (hi - lo) + lo) - 1.0).ln();
    x.clamp(-PI, PI)
}

/// σa [1/radius] that gives a fibre the colour `c` (a multiple-scattering albedo ∈ (0, 1)) at
/// azimuthal roughness β_n: Chiang et al. 2016 eq. 9.
pub fn sigma_a_from_reflectance(c: f32, beta_n: f32) -> f32 {
    let b = beta_n;
    let d = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b.powi(3) + 5.574 * b.powi(4) + 0.245 * b.powi(5);
    (c.clamp(1e-4, 1.0).ln() / d).powi(2)
}

/// σa [1/radius] in linear sRGB of melanin concentrations (d'Eon et al. 2011's absorption of
/// eumelanin and pheomelanin, as pbrt-v4 tabulates them).
pub fn sigma_a_from_melanin(eumelanin: f32, pheomelanin: f32) -> [f32; 3] {
    const EU: [f32; 3] = [0.419, 0.697, 1.37];
    const PHEO: [f32; 3] = [0.187, 0.4, 1.05];
    let (ce, cp) = (eumelanin.max(0.0), pheomelanin.max(0.0));
    std::array::from_fn(|i| ce * EU[i] + cp * PHEO[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::Rng;

    fn uniform_sphere(u: Vec2) -> Vec3 {
        let z = 1.0 - 2.0 * u.x;
        let r = safe_sqrt(1.0 - z * z);
        let phi = 2.0 * PI * u.y;
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    #[test]
    fn bessel_i0_matches_tabulated_values() {
        // Abramowitz & Stegun table 9.8 (I₀(x) e^{−x} tabulated): I₀(1), I₀(2), I₀(5), I₀(10).
        for (x, i0) in [(1.0, 1.266_066), (2.0, 2.279_585), (5.0, 27.239_872), (10.0, 2815.717)] {
            assert!((bessel_i0(x) - i0).abs() < 2e-5 * i0, "I0({x}) = {}", bessel_i0(x));
        }
        // The asymptotic log form agrees with the series where both hold.
        assert!((log_bessel_i0(12.5) - bessel_i0(12.5).ln()).abs() < 2e-5);
    }

    #[test]
    fn each_lobe_integrates_to_one() {
        // ∫ M_p cos θi dθi = 1 for any θo and v (midpoint rule), and ∫ N_p dφ = 1.
        let n = 20_000;
        for v in [0.02f32, 0.1, 0.3, 1.0] {
            for theta_o in [-1.2f32, 0.0, 0.7] {
                let (so, co) = theta_o.sin_cos();
                let sum: f64 = (0..n)
                    .map(|k| {
                        let t = -PI / 2.0 + PI * (k as f32 + 0.5) / n as f32;
                        let (si, ci) = t.sin_cos();
                        (longitudinal(ci, co, si, so, v) * ci) as f64 * (PI / n as f32) as f64
                    })
                    .sum();
                assert!((sum - 1.0).abs() < 5e-4, "M: v = {v}, θo = {theta_o}: {sum}");
            }
        }
        for s in [0.05f32, 0.3, 1.0] {
            let sum: f64 = (0..n)
                .map(|k| azimuthal(-PI + 2.0 * PI * (k as f32 + 0.5) / n as f32, 1, s, 0.3, 0.1) as f64)
                .sum::<f64>()
                * (2.0 * PI / n as f32) as f64;
            assert!((sum - 1.0).abs() < 1e-3, "N: s = {s}: {sum}");
        }
    }

    /// A non-absorbing fibre scatters exactly what it receives: the Monte Carlo estimate of
    /// ∫ f |cos θ_n| dωi with uniform sphere sampling is 1 within 4 standard errors.
    #[test]
    fn white_furnace_without_absorption() {
        let mut rng = Rng::new(7, 3);
        for beta_m in [0.1f32, 0.3, 0.8] {
            for beta_n in [0.1f32, 0.5, 1.0] {
                let hair = Hair::new(rng.uniform() * 2.0 - 1.0, 1.55, SampledSpectrum::zero(), beta_m, beta_n, 2.0);
                let wo = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
                let n = 200_000;
                let (mut s, mut s2) = (0.0f64, 0.0f64);
                for _ in 0..n {
                    let wi = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
                    let x = (hair.f(wo, wi, TransportMode::Radiance)[0] * wi.z.abs() * 4.0 * PI) as f64;
                    s += x;
                    s2 += x * x;
                }
                let mean = s / n as f64;
                let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!((mean - 1.0).abs() < 4.0 * se, "β_m {beta_m} β_n {beta_n}: {mean} ± {se}");
            }
        }
    }

    /// With no absorption the lobe probabilities equal the attenuations and each lobe is
    /// sampled exactly, so every sample's weight f |cos θ_n| / pdf is 1.
    #[test]
    fn sampling_weights_are_one_without_absorption() {
        let mut rng = Rng::new(11, 5);
        for _ in 0..20_000 {
            let (bm, bn) = (0.1 + 0.9 * rng.uniform(), 0.1 + 0.9 * rng.uniform());
            let hair = Hair::new(rng.uniform() * 2.0 - 1.0, 1.55, SampledSpectrum::zero(), bm, bn, 2.0);
            let wo = uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let Some(s) = hair.sample_f(wo, rng.uniform(), u, TransportMode::Radiance) else { continue };
            if s.wi.z.abs() < 1e-3 {
                continue;
            }
            let w = s.f[0] * s.wi.z.abs() / s.pdf;
            assert!((w - 1.0).abs() < 1e-3, "weight {w} at wo {wo}, wi {}", s.wi);
        }
    }

    #[test]
    fn absorption_darkens_and_reflectance_inverts_to_its_colour_order() {
        let wo = Vec3::new(0.3, 0.9, 0.3).normalize();
        let wi = Vec3::new(-0.2, -0.9, 0.4).normalize();
        let clear = Hair::new(0.2, 1.55, SampledSpectrum::zero(), 0.3, 0.3, 2.0).f(wo, wi, TransportMode::Radiance);
        let dark = Hair::new(0.2, 1.55, SampledSpectrum::splat(2.0), 0.3, 0.3, 2.0).f(wo, wi, TransportMode::Radiance);
        assert!(dark[0] < clear[0] && dark[0] > 0.0);
        // A brighter colour needs less absorption.
        assert!(sigma_a_from_reflectance(0.8, 0.3) < sigma_a_from_reflectance(0.2, 0.3));
        assert!(sigma_a_from_reflectance(1.0, 0.3) < 1e-6);
        // Eumelanin absorbs blue most: brown and black hair.
        let s = sigma_a_from_melanin(1.3, 0.0);
        assert!(s[2] > s[1] && s[1] > s[0]);
    }
}
