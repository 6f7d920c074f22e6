//! Proof of the BSDFs: χ² of every sampler against its pdf, white furnace, reciprocity,
//! delta lobes, degenerate inputs. Shared fixtures live here.

mod chi2;
mod coated_reference;
mod delta;
mod energy;
mod layered;
mod measured;
mod robustness;

use super::*;
use crate::math::Vec3;
use crate::spectrum::SampledSpectrum;

/// Incident zenith angles [deg] every model is tested at, including grazing.
pub(super) const ANGLES_DEG: [f32; 5] = [0.0, 30.0, 60.0, 85.0, 89.9];

/// Direction at zenith `theta_deg` and a fixed, non-symmetric azimuth.
pub(super) fn dir(theta_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), 0.7f32);
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// Spectrally varying values, so per-wavelength bugs show.
pub(super) fn spectrum(a: f32, b: f32, c: f32, d: f32) -> SampledSpectrum {
    SampledSpectrum::new([a, b, c, d])
}

/// Gold-like complex IOR at four wavelengths (450, 550, 650, 750 nm; Johnson & Christy).
pub(super) fn gold() -> (SampledSpectrum, SampledSpectrum) {
    (spectrum(1.38, 0.43, 0.14, 0.14), spectrum(1.91, 2.45, 3.70, 4.54))
}

pub(super) fn ggx(alpha: f32) -> TrowbridgeReitz {
    TrowbridgeReitz::new(alpha, alpha)
}

/// Every non-delta configuration worth a χ² test, with a label; `alphas` for the rough ones.
pub(super) fn rough_models(alphas: &[f32]) -> Vec<(String, Bxdf)> {
    let (eta, k) = gold();
    let mut v: Vec<(String, Bxdf)> = vec![
        ("diffuse".into(), Diffuse::new(spectrum(0.2, 0.5, 0.7, 0.9)).into()),
        (
            "diffuse-transmission".into(),
            DiffuseTransmission::new(spectrum(0.2, 0.5, 0.1, 0.3), spectrum(0.5, 0.2, 0.6, 0.1)).into(),
        ),
    ];
    for &a in alphas {
        v.push((format!("conductor α={a}"), Conductor::new(ggx(a), eta, k).into()));
        v.push((format!("dielectric η=1.5 α={a}"), Dielectric::new(1.5, ggx(a)).into()));
        v.push((format!("coated α={a}"), CoatedDiffuse::new(spectrum(0.2, 0.5, 0.7, 0.9), 1.5, ggx(a)).into()));
    }
    v
}
