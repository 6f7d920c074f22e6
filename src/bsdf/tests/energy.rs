//! White furnace and reciprocity.

use super::*;
use crate::math::Vec2;
use crate::sampling::Rng;

/// Directional albedo ∫ f cos θi dωi (+ delta lobes) by importance sampling: mean and standard
/// error of f |cos θi| / pdf, per wavelength averaged. Importance mode, so refraction carries
/// no 1/η² and a lossless interface has albedo exactly 1.
pub(super) fn albedo(bxdf: &Bxdf, wo: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = Rng::new(seed, 11);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let u = Vec2::new(rng.uniform(), rng.uniform());
        let w = match bxdf.sample_f(wo, rng.uniform(), u, TransportMode::Importance) {
            Some(b) if b.pdf > 0.0 => (b.f * (b.wi.z.abs() / b.pdf)).average() as f64,
            _ => 0.0,
        };
        s += w;
        s2 += w * w;
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt())
}

const N: usize = 200_000;

#[test]
fn no_model_creates_energy() {
    // Every model with its most reflective parameters, every angle, both sides.
    let white = SampledSpectrum::one();
    let mut models: Vec<(String, Bxdf)> = vec![
        ("lambert ρ=1".into(), Diffuse::new(white).into()),
        (
            "diffuse-transmission r+t=1".into(),
            DiffuseTransmission::new(SampledSpectrum::splat(0.4), SampledSpectrum::splat(0.6)).into(),
        ),
        ("thin dielectric".into(), ThinDielectric::new(1.5).into()),
    ];
    let (eta, k) = gold();
    for a in [0.0f32, 0.001, 0.01, 0.1, 0.3, 0.6, 1.0] {
        models.push((format!("conductor α={a}"), Conductor::new(ggx(a), eta, k).into()));
        models.push((format!("dielectric 1.5 α={a}"), Dielectric::new(1.5, ggx(a)).into()));
        models.push((format!("dielectric 1/1.5 α={a}"), Dielectric::new(1.0 / 1.5, ggx(a)).into()));
        models.push((format!("coated ρ=1 α={a}"), CoatedDiffuse::new(white, 1.5, ggx(a)).into()));
    }
    eprintln!("{}", assert_no_energy_created(&models, N, 2e-3));
}

/// Asserts albedo ≤ 1 + 10⁻³ (allowing 4 standard errors) for every model at every angle from
/// both sides, by `n` samples each, and that each estimate's standard error is below `max_se`;
/// returns the table of albedos.
pub(super) fn assert_no_energy_created(models: &[(String, Bxdf)], n: usize, max_se: f64) -> String {
    let mut report = String::new();
    for (name, b) in models {
        for &t in &ANGLES_DEG {
            for below in [false, true] {
                let mut wo = dir(t);
                if below {
                    wo.z = -wo.z;
                }
                let (m, se) = albedo(b, wo, n, 7);
                report += &format!("{name:28} θ={t:5}° below={below:5}: albedo {m:.5} ± {se:.5}\n");
                assert!(m <= 1.0 + 1e-3 + 4.0 * se, "{name} θ={t} below={below}: {m} ± {se}");
                assert!(se < max_se, "{name}: noisy estimate {se}");
            }
        }
    }
    report
}

#[test]
fn lossless_models_conserve_energy_exactly() {
    // Lambert ρ = 1, smooth dielectric R + T, thin dielectric, DiffuseTransmission r + t = 1,
    // smooth-coated Lambert ρ = 1: albedo 1 (exact model property).
    let white = SampledSpectrum::one();
    let models: Vec<(&str, Bxdf)> = vec![
        ("lambert", Diffuse::new(white).into()),
        ("smooth dielectric 1.5", Dielectric::new(1.5, ggx(0.0)).into()),
        ("smooth dielectric 1/1.5", Dielectric::new(1.0 / 1.5, ggx(0.0)).into()),
        ("thin dielectric", ThinDielectric::new(1.5).into()),
        (
            "diffuse transmission",
            DiffuseTransmission::new(SampledSpectrum::splat(0.4), SampledSpectrum::splat(0.6)).into(),
        ),
        ("smooth coated ρ=1", CoatedDiffuse::new(white, 1.5, ggx(0.0)).into()),
    ];
    for (name, b) in &models {
        for &t in &ANGLES_DEG {
            let (m, se) = albedo(b, dir(t), N, 3);
            assert!((m - 1.0).abs() <= 1e-4 + 4.0 * se, "{name} θ={t}: {m} ± {se}");
        }
    }
}

/// Single-scattering GGX loses the energy of light that would scatter between microfacets
/// more than once (Heitz et al. 2016, "Multiple-Scattering Microfacet BSDFs with the Smith
/// Model"). Measured here for a perfect conductor (F = 1) and a rough η = 1.5 dielectric
/// (R + T, Importance mode); the numbers are in docs/bsdf.md.
#[test]
fn single_scattering_microfacet_loss_is_measured() {
    // η ≈ 0, k = 10⁴: F = 1 − O(10⁻⁴) at every angle.
    let perfect =
        |a: f32| Bxdf::from(Conductor::new(ggx(a), SampledSpectrum::splat(1e-4), SampledSpectrum::splat(1e4)));
    let mut report = String::from("single-scattering loss 1 − albedo:\n   α   θo   conductor(F=1)  dielectric(1.5)\n");
    let mut prev_loss = -1.0f64;
    for a in [0.1f32, 0.3, 0.6, 1.0] {
        for t in [0.0f32, 60.0, 85.0] {
            let (mc, sc) = albedo(&perfect(a), dir(t), N, 5);
            let (md, sd) = albedo(&Dielectric::new(1.5, ggx(a)).into(), dir(t), N, 5);
            report += &format!("{a:5} {t:5}°  {:.4} ± {sc:.4}   {:.4} ± {sd:.4}\n", 1.0 - mc, 1.0 - md);
            assert!(mc <= 1.0 + 4.0 * sc && md <= 1.0 + 1e-3 + 4.0 * sd);
            if t == 0.0 {
                // The loss grows with roughness (more inter-facet scattering ignored).
                assert!(1.0 - mc > prev_loss - 4.0 * sc, "α={a}");
                prev_loss = 1.0 - mc;
            }
        }
    }
    // Closed form at α = 1, normal incidence, F = 1: D = 1/π, ωi = reflect(z, ωm) at θi = 2θm,
    // Λ(ωi) = (1/cos θi − 1)/2, so albedo = ∫₀^{π/4} 2 cos θ sin θ / (1 + Λ(2θ)) dθ = 1 − ln 2.
    let (m1, s1) = albedo(&perfect(1.0), dir(0.0), N, 9);
    let exact = 1.0 - std::f64::consts::LN_2;
    assert!((m1 - exact).abs() < 4.0 * s1 + 1e-4, "{m1} ± {s1} vs 1 − ln 2 = {exact}");
    eprintln!("{report}");
}

#[test]
fn reflection_is_reciprocal_and_transmission_adjoint() {
    let mut rng = Rng::new(99, 1);
    let mut rnd_dir = |upper: bool| loop {
        let v = Vec3::new(rng.uniform() * 2.0 - 1.0, rng.uniform() * 2.0 - 1.0, rng.uniform());
        // |cos θ| ≥ 0.1: away from the ill-conditioned grazing half vectors.
        if v.length_squared() <= 1.0 && v.length_squared() > 1e-4 && v.z >= 0.1 * v.length() {
            let v = v.normalize();
            return if upper { v } else { Vec3::new(v.x, v.y, -v.z) };
        }
    };
    // Relative tolerance: f32 rounding of the (generalized) half vector, which the two
    // orders compute from differently scaled sums (η′ωi + ωo vs ωi + ωo/η′).
    // Where ωm is nearly perpendicular to ωi or ωo, f is tiny (≲ 1e-5) and those products
    // cancel badly, hence the absolute floor (typical values are 0.01–10).
    let close_to = |a: SampledSpectrum, b: SampledSpectrum, rel: f32, abs: f32| {
        (a - b).0.abs().max_element() <= rel * a.0.abs().max_element().max(b.0.abs().max_element()) + abs
    };
    let close = |a, b| close_to(a, b, 1e-4, 1e-7);
    let models = rough_models(&[0.05, 0.3, 1.0]);
    for (name, b) in &models {
        for _ in 0..2000 {
            let (wo, wi) = (rnd_dir(true), rnd_dir(true));
            let (f1, f2) = (b.f(wo, wi, TransportMode::Radiance), b.f(wi, wo, TransportMode::Radiance));
            assert!(close(f1, f2), "{name}: {f1:?} vs {f2:?}");
            // Transmission: f_radiance(ωo, ωi) = f_importance(ωi, ωo) (Veach 1997 §5.3.2).
            let wt = rnd_dir(false);
            let (r, i) = (b.f(wo, wt, TransportMode::Radiance), b.f(wt, wo, TransportMode::Importance));
            assert!(close_to(r, i, 1e-3, 1e-5), "{name} transmission: {r:?} vs {i:?}");
        }
    }
}
