//! Delta lobes: exact directions and weights.

use super::*;
use crate::math::Vec2;

const U: Vec2 = Vec2::new(0.37, 0.61);

#[test]
fn smooth_conductor_is_a_mirror_weighted_by_fresnel() {
    let (eta, k) = gold();
    for a in [0.0f32, 1e-4, 0.000_999] {
        let b = Bxdf::from(Conductor::new(ggx(a), eta, k));
        assert!(b.flags().is_specular());
        for &t in &ANGLES_DEG {
            let wo = dir(t);
            let s = b.sample_f(wo, 0.5, U, TransportMode::Radiance).unwrap();
            assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
            assert!(s.is_specular() && s.is_reflection() && s.pdf == 1.0);
            let weight = s.f * s.wi.z.abs() / s.pdf;
            let want = fresnel::fr_complex_spectrum(wo.z, eta, k);
            assert!((weight - want).0.abs().max_element() < 1e-5, "{weight:?} vs {want:?}");
            assert_eq!(b.pdf(wo, s.wi, TransportMode::Radiance), 0.0);
            assert!(b.f(wo, s.wi, TransportMode::Radiance).is_black());
        }
    }
}

#[test]
fn smooth_dielectric_obeys_snell_and_fresnel() {
    for eta in [1.5f32, 1.0 / 1.5, 2.417] {
        let b = Bxdf::from(Dielectric::new(eta, ggx(0.0)));
        for &t in &ANGLES_DEG {
            for below in [false, true] {
                let mut wo = dir(t);
                if below {
                    wo.z = -wo.z;
                }
                let r = fresnel::fr_dielectric(wo.z, eta);
                // uc below R picks reflection, above picks refraction.
                let s = b.sample_f(wo, r * 0.5, U, TransportMode::Radiance).unwrap();
                assert!(s.is_reflection() && s.is_specular());
                assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
                assert!((s.f.average() * s.wi.z.abs() / s.pdf - 1.0).abs() < 1e-5);
                if r >= 1.0 {
                    continue; // total internal reflection
                }
                let s = b.sample_f(wo, r + (1.0 - r) * 0.5, U, TransportMode::Radiance).unwrap();
                assert!(s.is_transmission() && s.is_specular());
                let (ni, nt) = if wo.z > 0.0 { (1.0, eta) } else { (eta, 1.0) };
                // Snell: ηi sin θi = ηt sin θt, the refracted ray in the plane of incidence on
                // the other side.
                let (sin_i, sin_t) = (wo.truncate().length(), s.wi.truncate().length());
                assert!((ni * sin_i - nt * sin_t).abs() < 1e-5, "η={eta} θ={t}");
                assert!(wo.z * s.wi.z < 0.0);
                assert!(wo.truncate().perp_dot(s.wi.truncate()).abs() < 1e-5);
                assert!((s.eta - nt / ni).abs() < 1e-5);
                // Radiance mode: (1 − R)/pdf · 1/η² = 1/η².
                let w = s.f.average() * s.wi.z.abs() / s.pdf;
                assert!((w - (ni / nt).powi(2)).abs() < 1e-4, "{w}");
                let si = b.sample_f(wo, r + (1.0 - r) * 0.5, U, TransportMode::Importance).unwrap();
                assert!((si.f.average() * si.wi.z.abs() / si.pdf - 1.0).abs() < 1e-5);
            }
        }
    }
}

#[test]
fn thin_dielectric_passes_straight_through() {
    let b = Bxdf::from(ThinDielectric::new(1.5));
    for &t in &ANGLES_DEG[..4] {
        let wo = dir(t);
        let s = b.sample_f(wo, 0.999, U, TransportMode::Radiance).unwrap();
        assert_eq!(s.wi, -wo);
        assert!(s.is_transmission());
        // Slab reflectance R′ = 2R/(1 + R) for one interface's R.
        let r = fresnel::fr_dielectric(wo.z, 1.5);
        let s = b.sample_f(wo, 0.0, U, TransportMode::Radiance).unwrap();
        assert!((s.pdf - 2.0 * r / (1.0 + r)).abs() < 1e-5);
    }
}

/// Unpolarised Fresnel reflectance of a smooth interface into index `eta` from outside, from
/// the Fresnel equations and Snell's law in f64 (Born & Wolf §1.5), written apart from
/// `fresnel.rs` so the tests below check it rather than reuse it.
fn fresnel_outside(cos_i: f64, eta: f64) -> f64 {
    let cos_t = (1.0 - (1.0 - cos_i * cos_i) / (eta * eta)).sqrt();
    let r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_s * r_s + r_p * r_p)
}

#[test]
fn smooth_coat_mirror_is_chosen_by_its_share_of_the_albedo_and_weighted_by_fresnel() {
    // The coat's mirror reflects F(θo); the base returns (1 − F(θo)) ρ / (1 − ρ F̄_int) (the
    // geometric series of internal bounces, F̄_int = 1 − (1 − F̄)/η² by reciprocity, F̄ =
    // 2∫₀¹ F(μ) μ dμ). The mirror is chosen with probability p = F / (F + (1 − F) ρ / (1 − ρ F̄_int))
    // and its estimator weight f cos θ / p is then F / p.
    let (rho, eta) = (0.5f64, 1.5f64);
    let n = 100_000;
    let f_avg = (0..n).map(|i| (i as f64 + 0.5) / n as f64).map(|mu| 2.0 * fresnel_outside(mu, eta) * mu).sum::<f64>()
        / n as f64;
    // The published hemispherical reflectance of a glass (η = 1.5) surface lit from outside.
    assert!((f_avg - 0.0918).abs() < 1e-4, "F̄ = {f_avg}");
    let base = rho / (1.0 - rho * (1.0 - (1.0 - f_avg) / (eta * eta)));
    let b = CoatedDiffuse::new(SampledSpectrum::splat(rho as f32), eta as f32, ggx(0.0));
    for &t in &ANGLES_DEG[..4] {
        let wo = dir(t);
        let f = fresnel_outside(wo.z as f64, eta);
        let p = f / (f + (1.0 - f) * base);
        // Just below p the mirror is sampled, just above it the base.
        let s = b.sample_f(wo, (p * 0.999) as f32, U, TransportMode::Radiance).unwrap();
        assert!(s.is_specular() && s.wi == Vec3::new(-wo.x, -wo.y, wo.z), "θ={t}");
        assert!((s.pdf as f64 - p).abs() < 1e-4 * p, "θ={t}: pdf {} vs {p}", s.pdf);
        let w = (s.f.average() * s.wi.z / s.pdf) as f64;
        assert!((w - f / p).abs() < 1e-4 * (f / p), "θ={t}: weight {w} vs {}", f / p);
        let s = b.sample_f(wo, (p * 1.001) as f32, U, TransportMode::Radiance).unwrap();
        assert!(!s.is_specular() && s.is_reflection(), "θ={t}: above p the base is sampled");
    }
}
