//! A measuring instrument: irradiance at a point by Monte Carlo with the full integrator, reported
//! as mean ± standard error. This is how the renderer's radiometry is checked against closed forms.

use crate::integrator::{PathIntegrator, Stats};
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::{SampledWavelengths, CIE_Y_INTEGRAL};
use glam::Vec3;

/// Luminous efficacy of radiation at 555 nm [lm/W] (SI definition of the candela).
pub const K_M: f64 = 683.0;

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

/// Measures irradiance at `p` on a surface with unit normal `n` from `samples` independent
/// estimates (uniform wavelength sampling, so the radiometric integral has no visual weighting).
pub fn irradiance(
    scene: &Scene,
    integrator: &PathIntegrator,
    p: Vec3,
    n: Vec3,
    samples: u64,
    seed: u64,
) -> IrradianceMeasurement {
    let n = n.normalize();
    let mut sampler = Sampler::independent();
    let mut stats = Stats::default();
    let (mut e_acc, mut lux_acc) = ((0.0, 0.0), (0.0, 0.0));
    for i in 0..samples {
        sampler.start_pixel_sample((0, 0), i, seed);
        let mut w = SampledWavelengths::sample_uniform(sampler.get_1d());
        let e = integrator.irradiance(scene, p, n, &mut w, &mut sampler, &mut stats);
        // ∫E dλ ≈ mean over the wavelengths of E(λ)/pdf(λ).
        let total = e.safe_div(w.pdf()).average() as f64;
        let lux = K_M * CIE_Y_INTEGRAL as f64 * e.to_xyz(&w).y as f64;
        if total.is_finite() && lux.is_finite() {
            push(&mut e_acc, total);
            push(&mut lux_acc, lux);
        }
    }
    IrradianceMeasurement { irradiance: finish(e_acc, samples), illuminance: finish(lux_acc, samples), samples }
}
