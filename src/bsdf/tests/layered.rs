//! The stochastic layered BSDFs (pbrt-v4 `coateddiffuse`, `coatedconductor`).
//!
//! Their f and pdf are random estimates, so the tests check what is true in expectation:
//! - energy: albedo ≤ 1, and = 1 for lossless layers (a white Lambertian or a perfect mirror
//!   under a smooth coat, with an empty or a white scattering slab);
//! - the exact answer where one exists: a smooth coat over Lambert with an empty slab is the
//!   closed-form coated diffuse model (exact in that case), in f and in sampled directions
//!   (χ² of the walk's samples against the exact f cos θ);
//! - an independent walk through the two interfaces (rough coats, metal bases);
//! - sampling and evaluation describe one BSDF: cell by cell over the hemisphere, the mean
//!   sample weight f cos θ / pdf equals ∫ f cos θ from evaluation;
//! - reciprocity of the mean of f; pbrt-v4's pdf is positive, finite, and exactly its uniform
//!   floor where the layer cannot send light.

use super::coated_reference::layer_walk_albedo;
use super::energy::{albedo, assert_no_energy_created};
use super::*;
use crate::math::{Vec2, PI};
use crate::sampling::chi2::{chi2_survival, Chi2Test};
use crate::sampling::Rng;

/// A slab that neither absorbs nor scatters (the thinnest pbrt-v4 allows), walked long enough
/// that truncation loses nothing measurable.
fn empty_slab() -> Slab {
    Slab::new(0.0, SampledSpectrum::zero(), 0.0, 200, 1)
}

/// A non-absorbing scattering slab of `thickness` mean free paths.
fn white_slab(thickness: f32, g: f32) -> Slab {
    Slab::new(thickness, SampledSpectrum::one(), g, 2000, 1)
}

fn coated_diffuse(rho: SampledSpectrum, alpha: f32, slab: Slab) -> Bxdf {
    LayeredDiffuse::new(Dielectric::new(1.5, ggx(alpha)), Diffuse::new(rho), slab).into()
}

/// Gold under a coat of η = 1.5 (the metal's index relative to the coat).
fn coated_gold(coat_alpha: f32, metal_alpha: f32, slab: Slab) -> Bxdf {
    let (eta, k) = gold();
    let metal = Conductor::new(ggx(metal_alpha), eta / 1.5, k / 1.5);
    LayeredConductor::new(Dielectric::new(1.5, ggx(coat_alpha)), metal, slab).into()
}

/// A conductor with F = 1 − O(10⁻⁴) at every angle.
fn perfect_mirror(alpha: f32) -> Conductor {
    Conductor::new(ggx(alpha), SampledSpectrum::splat(1e-4), SampledSpectrum::splat(1e4))
}

#[test]
fn lossless_layers_conserve_energy_exactly() {
    let white = SampledSpectrum::one();
    let smooth = Dielectric::new(1.5, ggx(0.0));
    let models: Vec<(&str, Bxdf)> = vec![
        ("white lambert, empty slab", coated_diffuse(white, 0.0, empty_slab())),
        ("white lambert, white slab", coated_diffuse(white, 0.0, white_slab(0.5, 0.5))),
        ("mirror, empty slab", LayeredConductor::new(smooth, perfect_mirror(0.0), empty_slab()).into()),
        ("mirror, white slab", LayeredConductor::new(smooth, perfect_mirror(0.0), white_slab(1.0, -0.3)).into()),
    ];
    let mut report = String::new();
    for (name, b) in &models {
        // At θo → 90° the light refracted into the coat meets the mirror and then the coat at
        // the critical angle, where the coat reflects almost all of it, at the same angle every
        // time: it takes more bounces than any walk is allowed to get out.
        let angles = if name.starts_with("mirror") { &ANGLES_DEG[..4] } else { &ANGLES_DEG[..] };
        for &t in angles {
            let (m, se) = albedo(b, dir(t), 50_000, 3);
            report += &format!("{name:28} θ={t:5}°: albedo {m:.6} ± {se:.6}\n");
            assert!((m - 1.0).abs() <= 2e-4 + 4.0 * se, "{name} θ={t}: {m} ± {se}");
        }
    }
    eprintln!("{report}");
}

#[test]
fn no_layered_model_creates_energy() {
    let white = SampledSpectrum::one();
    let mut models: Vec<(String, Bxdf)> = Vec::new();
    for a in [0.0f32, 0.05, 0.3, 1.0] {
        models.push((format!("coated white α={a}"), coated_diffuse(white, a, empty_slab())));
        models.push((format!("coated white α={a}, white slab"), coated_diffuse(white, a, white_slab(0.3, 0.6))));
        let mirror = LayeredConductor::new(Dielectric::new(1.5, ggx(a)), perfect_mirror(0.3), empty_slab());
        models.push((format!("coated mirror α={a}"), mirror.into()));
    }
    assert_no_energy_created(&models, 20_000, 1e-2);
}

/// Mean and standard error, per wavelength, of f(ωo, ωi) over `k` directions within 10⁻⁴ rad
/// of `wi`: each is a different random stream, and f does not change measurably over the spread.
fn mean_f(b: &Bxdf, wo: Vec3, wi: Vec3, k: usize) -> (SampledSpectrum, SampledSpectrum) {
    let mut rng = Rng::new(17, 5);
    let (mut s, mut s2) = (SampledSpectrum::zero(), SampledSpectrum::zero());
    for _ in 0..k {
        let jitter = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 2e-4;
        let f = b.f(wo, (wi + jitter).normalize(), TransportMode::Radiance);
        s += f;
        s2 += f * f;
    }
    let mean = s / k as f32;
    let var = (s2 / k as f32 - mean * mean).map(|v| v.max(0.0));
    (mean, (var / k as f32).sqrt())
}

#[test]
fn smooth_coat_walk_matches_the_exact_coated_diffuse() {
    // A smooth coat over Lambert with nothing between: the closed-form model is exact here.
    let rho = spectrum(0.2, 0.5, 0.7, 1.0);
    let layered = coated_diffuse(rho, 0.0, empty_slab());
    let exact = Bxdf::from(CoatedDiffuse::new(rho, 1.5, ggx(0.0)));
    for (to, ti) in [(0.0f32, 30.0f32), (45.0, 10.0), (60.0, 75.0), (85.0, 40.0)] {
        let wo = dir(to);
        let wi =
            Vec3::new(-0.3 * ti.to_radians().sin(), 0.95 * ti.to_radians().sin(), ti.to_radians().cos()).normalize();
        let (m, se) = mean_f(&layered, wo, wi, 4000);
        let want = exact.f(wo, wi, TransportMode::Radiance);
        for i in 0..4 {
            assert!(
                (m[i] - want[i]).abs() <= 4.0 * se[i] + 1e-4,
                "θo={to} θi={ti} λ{i}: {} ± {} vs {}",
                m[i],
                se[i],
                want[i]
            );
        }
    }
    for &t in &ANGLES_DEG {
        let (a, sa) = albedo(&layered, dir(t), 100_000, 21);
        let (b, sb) = albedo(&exact, dir(t), 100_000, 22);
        assert!((a - b).abs() <= 4.0 * (sa * sa + sb * sb).sqrt() + 1e-4, "θ={t}: walk {a} ± {sa}, exact {b} ± {sb}");
    }
}

#[test]
fn smooth_lossless_coat_samples_the_exact_density() {
    // White Lambert, smooth coat, empty slab: every walk weighs exactly 1, so the directions
    // it samples are distributed as f cos θ of the exact model (its mirror part, a delta,
    // lands in the harness's failure cell with mass F(θo) = 1 − ∫ f cos θ).
    let white = SampledSpectrum::one();
    let layered = coated_diffuse(white, 0.0, empty_slab());
    let exact = Bxdf::from(CoatedDiffuse::new(white, 1.5, ggx(0.0)));
    let angles = [0.0f32, 40.0, 80.0];
    for t in angles {
        let wo = dir(t);
        let test = Chi2Test { sample_count: 300_000, test_count: angles.len(), ..Chi2Test::default() };
        let r = test.run(
            |uc, u| {
                let s = layered.sample_f(wo, uc, u, TransportMode::Radiance)?;
                (!s.flags.is_specular()).then_some(s.wi)
            },
            |wi| exact.f(wo, wi, TransportMode::Radiance).average() * wi.z.max(0.0),
        );
        assert!(r.passed, "θo = {t}: {r}");
    }
}

#[test]
fn rough_layers_match_a_walk_through_the_interfaces() {
    // The same physics followed by the interfaces' own samplers (an empty slab between).
    let cases: Vec<(&str, Bxdf, Bxdf, Bxdf)> = vec![
        (
            "rough coat α=0.3 over lambert 0.6",
            coated_diffuse(SampledSpectrum::splat(0.6), 0.3, empty_slab()),
            Dielectric::new(1.5, ggx(0.3)).into(),
            Diffuse::new(SampledSpectrum::splat(0.6)).into(),
        ),
        (
            "rough coat α=0.8 over white lambert",
            coated_diffuse(SampledSpectrum::one(), 0.8, empty_slab()),
            Dielectric::new(1.5, ggx(0.8)).into(),
            Diffuse::new(SampledSpectrum::one()).into(),
        ),
        ("coat α=0.2 over gold α=0.3", coated_gold(0.2, 0.3, empty_slab()), Dielectric::new(1.5, ggx(0.2)).into(), {
            let (eta, k) = gold();
            Conductor::new(ggx(0.3), eta / 1.5, k / 1.5).into()
        }),
    ];
    let mut report = String::new();
    for (name, layered, coat, base) in &cases {
        for t in [0.0f32, 50.0, 80.0] {
            let (m, sm) = albedo(layered, dir(t), 100_000, 31);
            let (r, sr) = layer_walk_albedo(coat.clone(), base.clone(), dir(t), 100_000);
            report += &format!("{name:36} θ={t:4}°: layered {m:.4} ± {sm:.4}, walk {r:.4} ± {sr:.4}\n");
            assert!((m - r).abs() <= 4.0 * (sm * sm + sr * sr).sqrt() + 1e-4, "{name} θ={t}: {m} ± {sm} vs {r} ± {sr}");
        }
    }
    eprintln!("{report}");
}

/// Cells over the upper hemisphere, uniform in cos θ and φ.
const MU_BINS: usize = 8;
const PHI_BINS: usize = 16;

fn cell_of(w: Vec3) -> Option<usize> {
    if w.z <= 0.0 {
        return None;
    }
    let mu = ((w.z * MU_BINS as f32) as usize).min(MU_BINS - 1);
    let mut phi = w.y.atan2(w.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let ph = ((phi / (2.0 * PI) * PHI_BINS as f32) as usize).min(PHI_BINS - 1);
    Some(mu * PHI_BINS + ph)
}

/// Per cell: (mean, variance of the mean) of the sample weight f cos θ / pdf summed in the
/// cell, from `n` samples (delta samples left out: f has no such part).
fn sampled_cells(b: &Bxdf, wo: Vec3, n: usize) -> Vec<(f64, f64)> {
    let mut rng = Rng::new(41, 3);
    let (mut s, mut s2) = (vec![0.0f64; MU_BINS * PHI_BINS], vec![0.0f64; MU_BINS * PHI_BINS]);
    for _ in 0..n {
        let (uc, u) = (rng.uniform(), Vec2::new(rng.uniform(), rng.uniform()));
        let Some(smp) = b.sample_f(wo, uc, u, TransportMode::Radiance) else { continue };
        let Some(c) = cell_of(smp.wi).filter(|_| !smp.flags.is_specular()) else { continue };
        let w = (smp.f * (smp.wi.z.abs() / smp.pdf)).average() as f64;
        s[c] += w;
        s2[c] += w * w;
    }
    let n = n as f64;
    s.iter().zip(&s2).map(|(&a, &b)| (a / n, (b / n - (a / n) * (a / n)).max(0.0) / n)).collect()
}

/// Per cell: (∫ f cos θ dω, variance) by a 12 × 12 midpoint rule in (cos θ, φ); the variance
/// is that of the mean of the points (it also holds f's true variation over the cell, so it
/// overstates the noise).
fn evaluated_cells(b: &Bxdf, wo: Vec3) -> Vec<(f64, f64)> {
    const K: usize = 12;
    let cell_area = 2.0 * std::f64::consts::PI / (MU_BINS * PHI_BINS) as f64;
    let mut out = Vec::with_capacity(MU_BINS * PHI_BINS);
    for im in 0..MU_BINS {
        for ip in 0..PHI_BINS {
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for a in 0..K {
                for c in 0..K {
                    let mu = (im as f64 + (a as f64 + 0.5) / K as f64) / MU_BINS as f64;
                    let phi = (ip as f64 + (c as f64 + 0.5) / K as f64) / PHI_BINS as f64 * 2.0 * std::f64::consts::PI;
                    let st = (1.0 - mu * mu).sqrt();
                    let wi = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, mu as f32);
                    let g = b.f(wo, wi, TransportMode::Radiance).average() as f64 * mu;
                    s += g;
                    s2 += g * g;
                }
            }
            let m = (K * K) as f64;
            let mean = s / m;
            out.push((cell_area * mean, cell_area * cell_area * (s2 / m - mean * mean).max(0.0) / m));
        }
    }
    out
}

#[test]
fn sampling_and_evaluation_describe_one_bsdf() {
    // Walks long enough that both truncate nothing measurable (they truncate the series of
    // bounces differently at pbrt-v4's default depth 10).
    let slab = |d: f32, a: f32, g: f32| Slab::new(d, SampledSpectrum::splat(a), g, 100, 8);
    let rho = spectrum(0.2, 0.5, 0.7, 0.9);
    let models: Vec<(&str, Bxdf)> = vec![
        ("smooth coat, lambert, scattering slab", coated_diffuse(rho, 0.0, slab(0.3, 0.8, 0.5))),
        ("rough coat α=0.4, lambert, thin absorbing slab", coated_diffuse(rho, 0.4, slab(0.01, 0.0, 0.0))),
        ("smooth coat, gold α=0.3, absorbing slab", coated_gold(0.0, 0.3, slab(0.2, 0.0, 0.0))),
        ("coat α=0.3, gold α=0.2, scattering slab", coated_gold(0.3, 0.2, slab(0.5, 0.7, -0.4))),
    ];
    let angles = [30.0f32, 70.0];
    let tests = models.len() * angles.len();
    let significance = 1.0 - (1.0 - 0.01f64).powf(1.0 / tests as f64);
    let mut failures = Vec::new();
    let mut report = String::new();
    for (name, b) in &models {
        for t in angles {
            let wo = dir(t);
            let sampled = sampled_cells(b, wo, 400_000);
            let evaluated = evaluated_cells(b, wo);
            let (mut stat, mut dof) = (0.0f64, 0usize);
            let (mut ta, mut tb, mut tv) = (0.0f64, 0.0f64, 0.0f64);
            for (&(a, va), &(e, ve)) in sampled.iter().zip(&evaluated) {
                ta += a;
                tb += e;
                tv += va + ve;
                if va + ve > 0.0 {
                    stat += (a - e).powi(2) / (va + ve);
                    dof += 1;
                }
            }
            let p = chi2_survival(stat, dof as f64);
            report += &format!(
                "{name:48} θo={t}°: Σ sampled {ta:.4}, Σ evaluated {tb:.4} ± {:.4}; χ² {stat:.1} / {dof}, p = {p:.3}\n",
                tv.sqrt()
            );
            if p < significance || (ta - tb).abs() > 4.0 * tv.sqrt() {
                failures.push(format!("{name} θo={t}: χ² {stat:.1} / {dof} (p = {p:.2e}), totals {ta:.4} vs {tb:.4}"));
            }
        }
    }
    eprintln!("{report}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_mean_of_f_is_reciprocal() {
    let rho = spectrum(0.2, 0.5, 0.7, 0.9);
    let models: Vec<(&str, Bxdf)> = vec![
        (
            "rough coat, lambert, scattering slab",
            coated_diffuse(rho, 0.3, Slab::new(0.4, SampledSpectrum::splat(0.8), 0.4, 10, 1)),
        ),
        ("rough coat, rough gold", coated_gold(0.2, 0.4, Slab::new(0.05, SampledSpectrum::zero(), 0.0, 10, 1))),
    ];
    for (name, b) in &models {
        for (wo, wi) in [(dir(20.0), dir(55.0)), (dir(70.0), Vec3::new(0.1, -0.5, 0.86).normalize())] {
            let (a, sa) = mean_f(b, wo, wi, 4000);
            let (c, sc) = mean_f(b, wi, wo, 4000);
            for i in 0..4 {
                let tol = 4.0 * (sa[i] * sa[i] + sc[i] * sc[i]).sqrt() + 1e-5;
                assert!(
                    (a[i] - c[i]).abs() <= tol,
                    "{name} λ{i}: f(ωo, ωi) {} ± {} vs f(ωi, ωo) {} ± {}",
                    a[i],
                    sa[i],
                    c[i],
                    sc[i]
                );
            }
        }
    }
}

#[test]
fn layered_pdf_is_positive_finite_and_floored_where_no_light_goes() {
    let floor = 0.1 / (4.0 * PI);
    let models = [
        coated_diffuse(spectrum(0.2, 0.5, 0.7, 0.9), 0.3, Slab::new(0.3, SampledSpectrum::splat(0.5), 0.2, 10, 2)),
        coated_gold(0.0, 0.2, Slab::new(0.01, SampledSpectrum::zero(), 0.0, 10, 1)),
    ];
    let mut rng = Rng::new(3, 9);
    for b in &models {
        for _ in 0..2000 {
            let wo = crate::sampling::warp::sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let wi = crate::sampling::warp::sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let p = b.pdf(wo, wi, TransportMode::Radiance);
            assert!(p.is_finite() && p >= floor * (1.0 - 1e-6), "{wo} {wi}: {p}");
            // Deterministic: the same call gives the same answer.
            assert_eq!(p, b.pdf(wo, wi, TransportMode::Radiance));
            if wo.z * wi.z < 0.0 {
                // Opaque bases: nothing leaves through the bottom, only the uniform floor remains.
                assert!((p - floor).abs() < 1e-7, "{wo} {wi}: {p}");
                assert!(b.f(wo, wi, TransportMode::Radiance).is_black());
            }
        }
    }
}

#[test]
fn layered_calls_are_deterministic() {
    let b = coated_gold(0.3, 0.2, Slab::new(0.5, SampledSpectrum::splat(0.7), -0.4, 10, 1));
    let (wo, wi) = (dir(35.0), dir(60.0));
    let f = b.f(wo, wi, TransportMode::Radiance);
    let s = b.sample_f(wo, 0.7, Vec2::new(0.2, 0.9), TransportMode::Radiance);
    for _ in 0..5 {
        assert_eq!(b.f(wo, wi, TransportMode::Radiance), f);
        assert_eq!(b.sample_f(wo, 0.7, Vec2::new(0.2, 0.9), TransportMode::Radiance), s);
    }
    // Different directions get different random streams.
    let g = b.f(wo, (wi + Vec3::splat(1e-5)).normalize(), TransportMode::Radiance);
    assert_ne!(f, g);
}

#[test]
fn layered_flags_follow_the_interfaces() {
    let empty = empty_slab();
    let smooth_lambert = coated_diffuse(SampledSpectrum::one(), 0.0, empty).flags();
    assert!(smooth_lambert.is_specular() && smooth_lambert.is_diffuse() && !smooth_lambert.is_transmissive());
    let rough_gold = coated_gold(0.2, 0.3, empty).flags();
    assert!(rough_gold.is_glossy() && !rough_gold.is_specular() && !rough_gold.is_diffuse());
    let scattering = coated_gold(0.2, 0.3, white_slab(0.1, 0.0)).flags();
    assert!(scattering.is_diffuse());
    let all_delta = coated_gold(0.0, 0.0, empty).flags();
    assert!(all_delta.is_specular() && !all_delta.is_non_specular());
}
