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

#[test]
fn smooth_coat_mirror_carries_the_fresnel_reflectance() {
    let b = CoatedDiffuse::new(SampledSpectrum::splat(0.5), 1.5, ggx(0.0));
    for &t in &ANGLES_DEG[..4] {
        let wo = dir(t);
        let s = b.sample_f(wo, 0.0, U, TransportMode::Radiance).unwrap();
        assert!(s.is_specular() && s.wi == Vec3::new(-wo.x, -wo.y, wo.z));
        let w = s.f.average() * s.wi.z / s.pdf;
        let want = fresnel::fr_dielectric(wo.z, 1.5) / s.pdf;
        assert!((w - want).abs() < 1e-5);
    }
}
