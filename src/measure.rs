//! A measuring instrument: irradiance at a point, or the radiance through a point in a direction,
//! by Monte Carlo with the full integrator, reported as mean ± standard error. This is how the
//! renderer's radiometry is checked against closed forms.

use crate::geometry::Ray;
use crate::integrator::{Integrator, Stats};
use crate::sampling::Sampler;
use crate::scene::Scene;
pub use crate::spectrum::K_M;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, CIE_Y_INTEGRAL};
use glam::Vec3;

/// A measured quantity: mean and standard error of the mean.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Estimate {
    /// Sample mean.
    pub mean: f64,
    /// Standard error of the mean.
    pub std_err: f64,
}

/// Irradiance measured at a point.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct IrradianceMeasurement {
    /// E integrated over 360–830 nm [W/m²].
    pub irradiance: Estimate,
    /// Illuminance K_m ∫ E(λ) ȳ(λ) dλ [lux].
    pub illuminance: Estimate,
    /// Samples taken.
    pub samples: u64,
}

fn push(acc: &mut (f64, f64), v: f64) {
    acc.0 += v;
    acc.1 += v * v;
}

fn finish(acc: (f64, f64), n: u64) -> Estimate {
    let n = n as f64;
    let mean = acc.0 / n;
    let var = (acc.1 / n - mean * mean).max(0.0) * n / (n - 1.0).max(1.0);
    Estimate { mean, std_err: (var / n).sqrt() }
}

/// Radiance measured through a point in a direction.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct RadianceMeasurement {
    /// L integrated over 360–830 nm [W/(sr·m²)].
    pub radiance: Estimate,
    /// Luminance K_m ∫ L(λ) ȳ(λ) dλ [cd/m²].
    pub luminance: Estimate,
    /// Samples taken.
    pub samples: u64,
}

/// `samples` independent estimates of a spectral quantity, uniform in wavelength so the
/// radiometric integral has no visual weighting: (∫ x dλ, K_m ∫ x ȳ dλ). Non-finite estimates
/// count as 0.
fn spectral_estimates(
    samples: u64,
    seed: u64,
    mut estimate: impl FnMut(&mut SampledWavelengths, &mut Sampler, &mut Stats) -> SampledSpectrum,
) -> (Estimate, Estimate) {
    let mut sampler = Sampler::independent();
    let mut stats = Stats::default();
    let (mut radiometric, mut photometric) = ((0.0, 0.0), (0.0, 0.0));
    for i in 0..samples {
        sampler.start_pixel_sample((0, 0), i, seed);
        let mut w = SampledWavelengths::sample_uniform(sampler.get_1d());
        let x = estimate(&mut w, &mut sampler, &mut stats);
        // ∫x dλ ≈ mean over the wavelengths of x(λ)/pdf(λ).
        let total = x.safe_div(w.pdf()).average() as f64;
        let visual = K_M * CIE_Y_INTEGRAL as f64 * x.to_xyz(&w).y as f64;
        if total.is_finite() && visual.is_finite() {
            push(&mut radiometric, total);
            push(&mut photometric, visual);
        }
    }
    (finish(radiometric, samples), finish(photometric, samples))
}

/// Measures irradiance at `p` on a surface with unit normal `n` from `samples` independent
/// estimates, by `integrator` as it renders `scene` ([`Integrator::for_scene`]); `p` is in the
/// camera's medium.
pub fn irradiance(
    scene: &Scene,
    integrator: &Integrator,
    p: Vec3,
    n: Vec3,
    samples: u64,
    seed: u64,
) -> IrradianceMeasurement {
    let n = n.normalize();
    let integrator = integrator.for_scene(scene);
    let (irradiance, illuminance) =
        spectral_estimates(samples, seed, |w, sampler, stats| integrator.irradiance(scene, p, n, w, sampler, stats));
    IrradianceMeasurement { irradiance, illuminance, samples }
}

/// Measures the radiance travelling through `p + ε dir` in direction `dir` (ε = 10⁻⁴ (1 + ‖p‖∞),
/// so for `p` on a surface that faces `dir` it is the radiance that surface sends toward `dir`)
/// from `samples` independent estimates by `integrator` as it renders `scene`
/// ([`Integrator::for_scene`]); `p` is in the camera's medium.
pub fn radiance(
    scene: &Scene,
    integrator: &Integrator,
    p: Vec3,
    dir: Vec3,
    samples: u64,
    seed: u64,
) -> RadianceMeasurement {
    let dir = dir.normalize();
    let integrator = integrator.for_scene(scene);
    let eps = 1e-4 * (1.0 + p.abs().max_element());
    let ray = Ray::new(p + dir * eps, -dir);
    let (radiance, luminance) =
        spectral_estimates(samples, seed, |w, sampler, stats| integrator.li(scene, ray, w, sampler, stats));
    RadianceMeasurement { radiance, luminance, samples }
}
