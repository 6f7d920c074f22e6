//! χ² tests of `sample_f` against `pdf` (pbrt-v4 `bsdfs_test.cpp` protocol, our harness).

use super::*;
use crate::math::Vec2;
use crate::sampling::chi2::{Chi2Test, Domain};
use rayon::prelude::*;

/// Roughnesses tested on the whole sphere (4 rough models each, plus the 2 diffuse ones).
const SPHERE_ALPHAS: [f32; 3] = [0.1, 0.4, 1.0];

/// Samples per test: half of pbrt-v4's 10⁶, to keep the suite near 30 s on two shared cores.
const SAMPLES: usize = 500_000;

fn sample_dirs(bxdf: Bxdf, wo: Vec3) -> impl FnMut(f32, Vec2) -> Option<Vec3> {
    move |uc, u| {
        let s = bxdf.sample_f(wo, uc, u, TransportMode::Radiance)?;
        // Delta samples have no density in the harness's sense: count them as failures.
        (!s.flags.is_specular()).then_some(s.wi)
    }
}

/// Number of χ² tests a suite runs (for the Šidák correction).
fn suite_size<'a>(models: impl Iterator<Item = &'a Bxdf>) -> usize {
    models.map(|b| if b.flags().is_transmissive() { 2 } else { 1 }).sum::<usize>() * ANGLES_DEG.len()
}

fn run_suite(
    models: Vec<(String, Bxdf)>,
    tests_in_suite: usize,
    domain: impl Fn(&Bxdf, Vec3) -> Domain + Sync,
) -> Vec<String> {
    let configs: Vec<(&String, &Bxdf, f32)> =
        models.iter().flat_map(|(n, b)| ANGLES_DEG.iter().map(move |&t| (n, b, t))).collect();
    let failures = configs.par_iter().map(|&(name, bxdf, theta)| {
        let mut failures = Vec::new();
        {
            // From below only where it differs (transmission); the others are two-sided copies.
            let sides: &[bool] = if bxdf.flags().is_transmissive() { &[false, true] } else { &[false] };
            for &below in sides {
                let mut wo = dir(theta);
                if below {
                    wo.z = -wo.z;
                }
                let test = Chi2Test {
                    domain: domain(bxdf, wo),
                    test_count: tests_in_suite,
                    sample_count: SAMPLES,
                    ..Chi2Test::default()
                };
                let r = test.run(sample_dirs(bxdf.clone(), wo), |wi| bxdf.pdf(wo, wi, TransportMode::Radiance));
                if !r.passed {
                    failures.push(format!("{name}, θo = {theta}°, below = {below}: {r}"));
                }
            }
        }
        failures
    });
    failures.flatten().collect()
}

#[test]
fn chi2_rough_models_on_the_sphere() {
    let models = rough_models(&SPHERE_ALPHAS);
    let n = suite_size(models.iter().map(|m| &m.1));
    let failures = run_suite(models, n, |_, _| Domain::SPHERE);
    assert!(failures.is_empty(), "{} of {n} failed:\n{}", failures.len(), failures.join("\n"));
}

/// Near-specular lobes (α = 0.001, 0.01) are far narrower than a sphere cell, so the test
/// zooms onto a cap of half-angle 40α around the lobe's centre (mirror or refracted
/// direction); everything outside the cap is one cell.
#[test]
fn chi2_near_specular_lobes_in_a_zoomed_cap() {
    let mut models = Vec::new();
    let (eta, k) = gold();
    for a in [0.001f32, 0.01] {
        models.push((format!("conductor α={a}"), Bxdf::from(Conductor::new(ggx(a), eta, k)), a));
        models.push((format!("dielectric η=1.5 α={a}"), Dielectric::new(1.5, ggx(a)).into(), a));
        models.push((format!("coated α={a}"), CoatedDiffuse::new(spectrum(0.2, 0.5, 0.7, 0.9), 1.5, ggx(a)).into(), a));
    }
    let n = suite_size(models.iter().map(|m| &m.1));
    let mut failures = Vec::new();
    for (name, bxdf, alpha) in models {
        let domain = |_: &Bxdf, wo: Vec3| {
            let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
            // Dielectric: zoom on the refracted lobe (the mirror lobe is tested by the others).
            let axis = match bxdf {
                Bxdf::Dielectric(d) => local::refract(wo, Vec3::Z, d.eta).map(|(t, _)| t).unwrap_or(mirror),
                _ => mirror,
            };
            Domain::Cap { axis, theta_max: 40.0 * alpha }
        };
        let mut f = run_suite(vec![(name, bxdf.clone())], n, domain);
        failures.append(&mut f);
    }
    assert!(failures.is_empty(), "{} of {n} failed:\n{}", failures.len(), failures.join("\n"));
}

/// Hair fibres with absorption (so the lobe choice differs from the attenuations), at
/// several offsets across the fibre and roughnesses.
#[test]
fn chi2_hair_on_the_sphere() {
    let sigma_a = spectrum(0.2, 0.5, 1.0, 2.0);
    let mut models = Vec::new();
    for (h, beta_m, beta_n) in [(-0.6f32, 0.3f32, 0.3f32), (0.1, 0.7, 0.9), (0.85, 0.4, 0.6)] {
        let hair = Hair::new(h, 1.55, sigma_a, beta_m, beta_n, 2.0);
        models.push((format!("hair h={h} β_m={beta_m} β_n={beta_n}"), Bxdf::from(hair)));
    }
    let n = suite_size(models.iter().map(|m| &m.1));
    let failures = run_suite(models, n, |_, _| Domain::SPHERE);
    assert!(failures.is_empty(), "{} of {n} failed:\n{}", failures.len(), failures.join("\n"));
}
