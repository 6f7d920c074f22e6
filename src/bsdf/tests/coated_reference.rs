//! The coated-diffuse model against a random walk through the actual layer: light refracts
//! through the coat (the rough `Dielectric` BSDF), bounces on the Lambertian base, and leaves
//! or reflects back at the coat from inside, until it escapes. With a smooth coat the model
//! is exact, so albedos must agree within noise; with a rough coat the difference is the
//! model's approximation error, reported in docs/bsdf.md.

use super::energy::albedo;
use super::*;
use crate::math::Vec2;
use crate::sampling::Rng;

/// Albedo of the layered reference for light from `wo` (above): mean and standard error.
fn reference_albedo(rho: f32, eta: f32, alpha: f32, wo: Vec3, n: usize) -> (f64, f64) {
    let coat = Bxdf::from(Dielectric::new(eta, ggx(alpha)));
    layer_walk_albedo(coat, Diffuse::new(SampledSpectrum::splat(rho)).into(), wo, n)
}

/// Albedo of a `coat` over a `base` for light from `wo` (above), by following light through
/// the layer with the two BSDFs' own samplers until it escapes: mean and standard error. The
/// layer between them is empty (no absorption, no scattering).
pub(super) fn layer_walk_albedo(coat: Bxdf, base: Bxdf, wo: Vec3, n: usize) -> (f64, f64) {
    let mut rng = Rng::new(1234, 77);
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let mut weight = SampledSpectrum::one();
        let mut incoming = wo; // points back to where the light came from
        let mut escaped = false;
        for _bounce in 0..256 {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let Some(b) = coat.sample_f(incoming, rng.uniform(), u, TransportMode::Importance) else {
                break;
            };
            weight *= b.f * (b.wi.z.abs() / b.pdf);
            if b.wi.z > 0.0 {
                escaped = true; // left the layer upwards (reflected outside or transmitted out)
                break;
            }
            // Travelling down to the base, which reflects it back up.
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let Some(r) = base.sample_f(-b.wi, rng.uniform(), u, TransportMode::Importance) else {
                break;
            };
            weight *= r.f * (r.wi.z.abs() / r.pdf);
            incoming = -r.wi;
        }
        let w = if escaped { weight.average() as f64 } else { 0.0 };
        s += w;
        s2 += w * w;
    }
    let mean = s / n as f64;
    (mean, ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt())
}

#[test]
fn smooth_coat_matches_the_layered_random_walk() {
    for rho in [1.0f32, 0.5] {
        let model = Bxdf::from(CoatedDiffuse::new(SampledSpectrum::splat(rho), 1.5, ggx(0.0)));
        for t in [0.0f32, 45.0, 80.0] {
            let (m, sm) = albedo(&model, dir(t), 100_000, 21);
            let (r, sr) = reference_albedo(rho, 1.5, 0.0, dir(t), 100_000);
            let se = (sm * sm + sr * sr).sqrt();
            assert!((m - r).abs() < 4.0 * se + 1e-4, "ρ={rho} θ={t}: model {m} ± {sm}, walk {r} ± {sr}");
        }
    }
}

/// One row of the rough-coat table: ρ, α, and (model, walk) albedos at θo = 0°, 45°, 80°.
type QuotedRow = (f32, f32, Vec<(f64, f64)>);

/// The rough-coat table of docs/bsdf.md.
fn quoted_rough_coat_albedos() -> Vec<QuotedRow> {
    let doc = include_str!("../../../docs/bsdf.md");
    let table = doc.split("| ρ | α | θo = 0° | 45° | 80° |").nth(1).expect("docs/bsdf.md has the coated table");
    table
        .lines()
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|row| {
            let cells: Vec<&str> = row.split('|').map(str::trim).filter(|c| !c.is_empty()).collect();
            let pairs = cells[2..]
                .iter()
                .map(|c| {
                    let (m, w) = c.split_once(" vs ").expect("model vs walk");
                    (m.parse().unwrap(), w.parse().unwrap())
                })
                .collect();
            (cells[0].parse().unwrap(), cells[1].parse().unwrap(), pairs)
        })
        .collect()
}

#[test]
fn rough_coat_albedos_are_the_ones_docs_bsdf_md_quotes() {
    // docs/bsdf.md quotes each albedo to three decimals from 10⁵ samples: the model's and the
    // walk's estimates must lie within 4 standard errors of it (plus the rounding).
    let quoted = quoted_rough_coat_albedos();
    assert_eq!(quoted.len(), 6, "{quoted:?}");
    let mut report = String::from("coated diffuse albedo, model vs random walk (η = 1.5):\n");
    for (rho, alpha, row) in quoted {
        let model = Bxdf::from(CoatedDiffuse::new(SampledSpectrum::splat(rho), 1.5, ggx(alpha)));
        for (t, (doc_m, doc_r)) in [0.0f32, 45.0, 80.0].into_iter().zip(row) {
            let (m, sm) = albedo(&model, dir(t), 100_000, 21);
            let (r, sr) = reference_albedo(rho, 1.5, alpha, dir(t), 100_000);
            report += &format!(
                "ρ={rho} α={alpha} θ={t:4}°: model {m:.4} ± {sm:.4}, walk {r:.4} ± {sr:.4}, diff {:+.4}\n",
                m - r
            );
            assert!((m - doc_m).abs() <= 4.0 * sm + 5e-4, "ρ={rho} α={alpha} θ={t}: model {m} ± {sm}, docs {doc_m}");
            assert!((r - doc_r).abs() <= 4.0 * sr + 5e-4, "ρ={rho} α={alpha} θ={t}: walk {r} ± {sr}, docs {doc_r}");
            // Both are physically bounded; the model must not create energy.
            assert!(m <= 1.0 + 1e-3 + 4.0 * sm && r <= 1.0 + 1e-3 + 4.0 * sr);
        }
    }
    eprintln!("{report}");
}
