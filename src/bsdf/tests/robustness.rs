//! Degenerate inputs: grazing directions, α → 0, bad parameters. Nothing may be NaN or ∞.

use super::*;
use crate::math::Vec2;
use crate::sampling::Rng;

#[test]
fn values_stay_finite_at_grazing_angles_and_vanishing_roughness() {
    let mut models = rough_models(&[0.0, 1e-8, 1e-4, 0.000_999, 0.001, 0.002, 1.0, 5.0]);
    models.push(("thin".into(), ThinDielectric::new(1.5).into()));
    models.push(("bad eta".into(), Dielectric::new(f32::NAN, ggx(0.3)).into()));
    models.push(("bad alpha".into(), Conductor::new(ggx(f32::NAN), gold().0, gold().1).into()));
    for a in [0.0f32, 1e-4, 0.3] {
        let slab = Slab::new(0.2, SampledSpectrum::splat(0.7), 0.5, 10, 1);
        let lambert = Diffuse::new(spectrum(0.2, 0.5, 0.7, 0.9));
        models.push((
            format!("layered diffuse α={a}"),
            LayeredDiffuse::new(Dielectric::new(1.5, ggx(a)), lambert, slab).into(),
        ));
        let metal = Conductor::new(ggx(a), gold().0, gold().1);
        models.push((
            format!("layered gold α={a}"),
            LayeredConductor::new(Dielectric::new(1.5, ggx(a)), metal, slab).into(),
        ));
    }
    // Degenerate slabs: nothing thick, infinitely thick, bad numbers.
    for slab in [
        Slab::new(0.0, SampledSpectrum::one(), 0.99, 10, 1),
        Slab::new(f32::INFINITY, SampledSpectrum::one(), -1.0, 10, 1),
        Slab::new(f32::NAN, SampledSpectrum::splat(f32::NAN), f32::NAN, 0, 0),
    ] {
        let lambert = Diffuse::new(SampledSpectrum::one());
        models.push((
            format!("layered {slab:?}"),
            LayeredDiffuse::new(Dielectric::new(1.5, ggx(0.2)), lambert, slab).into(),
        ));
    }
    let zs = [1.0f32, 0.5, 1e-2, 1e-4, 1e-6, 1e-8, 0.0, -1e-8, -1e-4, -0.5];
    let dirs: Vec<Vec3> = zs
        .iter()
        .flat_map(|&z| {
            let r = (1.0 - z * z).max(0.0).sqrt();
            [Vec3::new(r, 0.0, z), Vec3::new(0.6 * r, -0.8 * r, z)]
        })
        .collect();
    let mut rng = Rng::new(5, 5);
    for (name, b) in &models {
        for &wo in &dirs {
            for &wi in &dirs {
                for mode in [TransportMode::Radiance, TransportMode::Importance] {
                    assert!(b.f(wo, wi, mode).is_finite(), "{name} f {wo} {wi}");
                    let p = b.pdf(wo, wi, mode);
                    assert!(p.is_finite() && p >= 0.0, "{name} pdf {wo} {wi}: {p}");
                }
            }
            for _ in 0..200 {
                let u = Vec2::new(rng.uniform(), rng.uniform());
                if let Some(s) = b.sample_f(wo, rng.uniform(), u, TransportMode::Radiance) {
                    assert!(s.f.is_finite() && s.pdf.is_finite() && s.wi.is_finite(), "{name} {wo}: {s:?}");
                    assert!(s.pdf >= 0.0 && s.f.min_value() >= 0.0, "{name} {wo}: {s:?}");
                }
            }
        }
    }
}

#[test]
fn world_bsdf_rejects_tangent_wo_and_maps_frames() {
    let ns = Vec3::new(0.0, 0.6, 0.8);
    let b = Bsdf::new(ns, Vec3::X, ns, Diffuse::new(SampledSpectrum::splat(0.5)).into());
    // ωo in the tangent plane.
    let tangent = Vec3::X;
    assert!(b.f(tangent, ns, TransportMode::Radiance).is_black());
    assert_eq!(b.pdf(tangent, ns, TransportMode::Radiance), 0.0);
    assert!(b.sample_f(tangent, 0.5, Vec2::splat(0.5), TransportMode::Radiance).is_none());
    // A sampled direction is on the side of ns and has the local density.
    let wo = Vec3::new(0.3, 0.2, 0.9).normalize();
    let s = b.sample_f(wo, 0.5, Vec2::new(0.3, 0.8), TransportMode::Radiance).unwrap();
    assert!(s.wi.dot(ns) > 0.0 && (s.wi.length() - 1.0).abs() < 1e-5);
    assert!((s.pdf - b.pdf(wo, s.wi, TransportMode::Radiance)).abs() < 1e-5);
    assert!((s.pdf - s.wi.dot(ns) / crate::math::PI).abs() < 1e-5);
    // A black BxDF samples nothing.
    let black = Bsdf::new(ns, Vec3::X, ns, Diffuse::new(SampledSpectrum::zero()).into());
    assert!(black.sample_f(wo, 0.5, Vec2::splat(0.5), TransportMode::Radiance).is_none());
}

#[test]
fn flags_describe_the_lobes() {
    let (eta, k) = gold();
    assert!(Bxdf::from(Conductor::new(ggx(0.0), eta, k)).flags().is_specular());
    let rough = Bxdf::from(Conductor::new(ggx(0.3), eta, k)).flags();
    assert!(rough.is_glossy() && rough.is_reflective() && !rough.is_transmissive());
    let glass = Bxdf::from(Dielectric::new(1.5, ggx(0.0))).flags();
    assert!(glass.is_specular() && glass.is_reflective() && glass.is_transmissive() && !glass.is_non_specular());
    let index_matched = Bxdf::from(Dielectric::new(1.0, ggx(0.3))).flags();
    assert!(!index_matched.is_reflective() && index_matched.is_transmissive());
    let coated = Bxdf::from(CoatedDiffuse::new(SampledSpectrum::one(), 1.5, ggx(0.0))).flags();
    assert!(coated.is_specular() && coated.is_diffuse() && coated.is_non_specular());
    assert!(Bxdf::from(Diffuse::new(SampledSpectrum::zero())).flags().is_empty());
}

#[test]
fn world_bsdf_sampling_matches_its_pdf_in_a_tilted_frame() {
    use crate::sampling::chi2::Chi2Test;
    let ns = Vec3::new(0.3, -0.5, 0.81).normalize();
    let bxdf = Bxdf::from(Dielectric::new(1.5, ggx(0.3)));
    let b = Bsdf::new(ns, Vec3::new(1.0, 0.2, 0.0), ns, bxdf);
    let wo = Vec3::new(-0.2, 0.7, 0.4).normalize();
    let t = Chi2Test { sample_count: 300_000, ..Chi2Test::default() };
    let r = t.run(
        |uc, u| b.sample_f(wo, uc, u, TransportMode::Radiance).map(|s| s.wi),
        |wi| b.pdf(wo, wi, TransportMode::Radiance),
    );
    assert!(r.passed, "{r}");
}
