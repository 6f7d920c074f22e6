//! χ² tests of `sample_f` against `pdf` (pbrt-v4 `bsdfs_test.cpp` protocol, our harness).

use super::*;
use crate::math::Vec2;
use crate::sampling::chi2::{Chi2Test, Domain};

/// Rough configurations on the whole sphere: 4 α × 4 models + 2 diffuse, × 5 angles × 2 sides.
const SPHERE_ALPHAS: [f32; 4] = [0.05, 0.2, 0.5, 1.0];

fn sample_dirs(bxdf: Bxdf, wo: Vec3) -> impl FnMut(f32, Vec2) -> Option<Vec3> {
    move |uc, u| {
        let s = bxdf.sample_f(wo, uc, u, TransportMode::Radiance)?;
        // Delta samples have no density in the harness's sense: count them as failures.
        (!s.flags.is_specular()).then_some(s.wi)
    }
}

fn run_suite(
    models: Vec<(String, Bxdf)>,
    tests_in_suite: usize,
    domain: impl Fn(&Bxdf, Vec3) -> Domain,
) -> Vec<String> {
    let mut failures = Vec::new();
    for (name, bxdf) in &models {
        for &theta in &ANGLES_DEG {
            for below in [false, true] {
                let mut wo = dir(theta);
                if below {
                    wo.z = -wo.z;
                }
                let test = Chi2Test {
                    domain: domain(bxdf, wo),
                    test_count: tests_in_suite,
                    sample_count: 1_000_000,
                    ..Chi2Test::default()
                };
                let r = test.run(sample_dirs(*bxdf, wo), |wi| {
                    bxdf.pdf(wo, wi, TransportMode::Radiance)
                });
                if !r.passed {
                    failures.push(format!("{name}, θo = {theta}°, below = {below}: {r}"));
                }
            }
        }
    }
    failures
}

#[test]
fn chi2_rough_models_on_the_sphere() {
    let models = rough_models(&SPHERE_ALPHAS);
    let n = models.len() * ANGLES_DEG.len() * 2;
    let failures = run_suite(models, n, |_, _| Domain::SPHERE);
    assert!(
        failures.is_empty(),
        "{} of {n} failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Near-specular lobes (α = 0.001, 0.01) are far narrower than a sphere cell, so the test
/// zooms onto a cap of half-angle 40α around the lobe's centre (mirror or refracted
/// direction); everything outside the cap is one cell.
#[test]
fn chi2_near_specular_lobes_in_a_zoomed_cap() {
    let mut models = Vec::new();
    let (eta, k) = gold();
    for a in [0.001f32, 0.01] {
        models.push((
            format!("conductor α={a}"),
            Bxdf::from(Conductor::new(ggx(a), eta, k)),
            a,
        ));
        models.push((
            format!("dielectric η=1.5 α={a}"),
            Dielectric::new(1.5, ggx(a)).into(),
            a,
        ));
        models.push((
            format!("coated α={a}"),
            CoatedDiffuse::new(spectrum(0.2, 0.5, 0.7, 0.9), 1.5, ggx(a)).into(),
            a,
        ));
    }
    let n = models.len() * ANGLES_DEG.len() * 2;
    let mut failures = Vec::new();
    for (name, bxdf, alpha) in models {
        let domain = |_: &Bxdf, wo: Vec3| {
            let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
            // Dielectric: zoom on the refracted lobe (the mirror lobe is tested by the others).
            let axis = match bxdf {
                Bxdf::Dielectric(d) => local::refract(wo, Vec3::Z, d.eta)
                    .map(|(t, _)| t)
                    .unwrap_or(mirror),
                _ => mirror,
            };
            Domain::Cap {
                axis,
                theta_max: 40.0 * alpha,
            }
        };
        let mut f = run_suite(vec![(name, bxdf)], n, domain);
        failures.append(&mut f);
    }
    assert!(
        failures.is_empty(),
        "{} of {n} failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
