//! The pixel sensor between a sample's spectral radiance and the film's XYZ (pbrt-v4's
//! `PixelSensor`). Its three channels integrate the radiance against their spectral
//! responses, scaled by the imaging ratio exposure time × ISO / 100 (1 by default, so scenes
//! not written for a physical camera render unchanged); a matrix then maps the response to
//! XYZ. The "cie1931" sensor's responses are the CIE 1931 matching functions, so its response
//! is XYZ, and its matrix an optional von Kries white balance that maps the white of a
//! daylight illuminant of the given temperature to the output colour space's white. A camera
//! sensor ([`crate::spectrum::camera_sensitivities`]) responds with its measured r, g, b
//! curves, and its matrix is fitted ([`super::sensor_fit`]). pbrt-v4's film
//! `maxcomponentvalue` clamps each sample's response, after the imaging ratio and before the
//! matrix.

use crate::spectrum::{
    camera_rgb_bar, camera_sensitivities, CameraCurves, ColorSpace, SampledSpectrum, SampledWavelengths, Spectrum,
    CIE_Y_INTEGRAL, N_SPECTRUM_SAMPLES,
};
use glam::{DMat3, DVec3, Mat3, Vec3};

/// The spectral responses of a sensor's three channels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Response {
    /// The CIE 1931 matching functions x̄, ȳ, z̄: the response is XYZ.
    Cie1931,
    /// A camera's measured r, g, b sensitivities.
    Camera(&'static CameraCurves),
}

/// The sensor's response to spectral radiance `l` at wavelengths `w`: the Monte Carlo estimate
/// of ∫ r̄ L dλ / ∫ ȳ dλ (and so for g, b), the normalisation `SampledSpectrum::to_xyz` uses, so
/// that the fitted matrix yields XYZ on prism's scale.
#[inline]
fn camera_response(curves: &CameraCurves, l: &SampledSpectrum, w: &SampledWavelengths) -> Vec3 {
    let mut acc = Vec3::ZERO;
    for i in 0..N_SPECTRUM_SAMPLES {
        if w.pdf[i] != 0.0 {
            acc += camera_rgb_bar(curves, w.lambda[i]) * (l.0[i] / w.pdf[i]);
        }
    }
    acc / (N_SPECTRUM_SAMPLES as f32 * CIE_Y_INTEGRAL)
}

/// A sensor: its responses, imaging ratio, clamp and XYZ-from-response matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sensor {
    /// The channels' spectral responses.
    pub response: Response,
    /// Exposure time [s] × ISO / 100.
    pub imaging_ratio: f32,
    /// XYZ from the (clamped) response: the white balance of a cie1931 sensor (none: the
    /// identity), a camera's fitted matrix.
    pub xyz_from_sensor: Option<Mat3>,
    /// Largest component a sample's sensor response may have; a larger one scales the whole
    /// sample down to it (pbrt-v4's `maxcomponentvalue`, +∞ by default). A biased but bounded
    /// estimator that removes fireflies.
    pub max_component: f32,
}

impl Default for Sensor {
    fn default() -> Self {
        Self { response: Response::Cie1931, imaging_ratio: 1.0, xyz_from_sensor: None, max_component: f32::INFINITY }
    }
}

impl Sensor {
    /// The cie1931 sensor with ISO `iso`, exposure `exposure_time` [s], and a white balance for
    /// daylight of `white_balance_kelvin` (0: none) into `space`'s white.
    pub fn new(iso: f32, exposure_time: f32, white_balance_kelvin: f32, space: &ColorSpace) -> Self {
        let xyz_from_sensor = (white_balance_kelvin > 0.0)
            .then(|| von_kries(daylight_white(white_balance_kelvin as f64), space.white).as_mat3());
        Self { imaging_ratio: exposure_time * iso / 100.0, xyz_from_sensor, ..Self::default() }
    }

    /// pbrt-v4's camera sensor `name` (e.g. "canon_eos_5d"), white balanced for daylight of
    /// `white_balance_kelvin` (pbrt-v4 uses 6500 K when the scene gives 0), its output in
    /// `space`; `None` for a name pbrt-v4 has no curves for.
    pub fn camera(
        name: &str,
        iso: f32,
        exposure_time: f32,
        white_balance_kelvin: f32,
        space: &ColorSpace,
    ) -> Option<Self> {
        let curves = camera_sensitivities(name)?;
        let kelvin = if white_balance_kelvin > 0.0 { white_balance_kelvin } else { 6500.0 };
        let m = crate::sensor_fit::xyz_from_camera(curves, &white_balance_illuminant(kelvin as f64), space);
        Some(Self {
            response: Response::Camera(curves),
            imaging_ratio: exposure_time * iso / 100.0,
            xyz_from_sensor: Some(m.as_mat3()),
            max_component: f32::INFINITY,
        })
    }

    /// This sensor with each sample's largest component clamped to `max_component`.
    pub fn with_max_component(self, max_component: f32) -> Self {
        Self { max_component, ..self }
    }

    /// The XYZ the sensor records for spectral radiance `l` at wavelengths `w`.
    #[inline]
    pub fn record(&self, l: &SampledSpectrum, w: &SampledWavelengths) -> Vec3 {
        match self.response {
            Response::Cie1931 => self.apply(l.to_xyz(w)),
            Response::Camera(curves) => self.apply(camera_response(curves, l, w)),
        }
    }

    /// XYZ from the channels' response `response` (for cie1931, XYZ itself): the imaging
    /// ratio, the clamp, then the matrix.
    #[inline]
    pub fn apply(&self, response: Vec3) -> Vec3 {
        let mut xyz = response * self.imaging_ratio;
        let m = xyz.max_element();
        if m > self.max_component {
            xyz *= self.max_component / m;
        }
        match self.xyz_from_sensor {
            Some(m) => m * xyz,
            None => xyz,
        }
    }
}

/// pbrt-v4's white-balance illuminant for temperature `t` [K] (`Spectra::D`): CIE daylight at
/// `t` rescaled from c₂ = 1.4380 to 1.4388 cm·K, the blackbody below 4000 K.
pub fn white_balance_illuminant(t: f64) -> Spectrum {
    let cct = t * 1.4388 / 1.4380;
    if cct < 4000.0 {
        return Spectrum::blackbody(cct as f32);
    }
    crate::spectrum::daylight(cct.min(25_000.0)).unwrap_or_else(|| Spectrum::constant(1.0))
}

/// Bradford's cone-response (LMS) matrix, the one pbrt-v4 and ICC profiles adapt in.
const LMS_FROM_XYZ: DMat3 = DMat3::from_cols_array(&[
    0.8951, -0.7502, 0.0389, // column 1
    0.2664, 1.7135, -0.0685, // column 2
    -0.1614, 0.0367, 1.0296, // column 3
]);

/// XYZ with Y = 1 of chromaticity `xy`.
fn xyz_of(xy: [f64; 2]) -> DVec3 {
    DVec3::new(xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1])
}

/// von Kries adaptation from white `src` to white `dst` (xy): each cone response is scaled by
/// dst/src, so `src`'s XYZ maps to `dst`'s.
pub fn von_kries(src: [f64; 2], dst: [f64; 2]) -> DMat3 {
    let (s, d) = (LMS_FROM_XYZ * xyz_of(src), LMS_FROM_XYZ * xyz_of(dst));
    LMS_FROM_XYZ.inverse() * DMat3::from_diagonal(d / s) * LMS_FROM_XYZ
}

/// Chromaticity of CIE daylight at correlated colour temperature `t` [K] (CIE 015:2018 eq. 4.7
/// and 4.8), with the temperature rescaled from c₂ = 1.4380 to 1.4388 cm·K as for the tabulated
/// D illuminants; below 4000 K, where daylight is undefined, the blackbody's (as pbrt-v4 does).
pub fn daylight_white(t: f64) -> [f64; 2] {
    let t = t * 1.4388 / 1.4380;
    if t < 4000.0 {
        let xyz = Spectrum::blackbody(t as f32).to_xyz_f64();
        let sum = xyz.x + xyz.y + xyz.z;
        return [xyz.x / sum, xyz.y / sum];
    }
    let t = t.min(25_000.0);
    let (a, b, c, d) = if t <= 7000.0 {
        (-4.6070e9, 2.9678e6, 0.09911e3, 0.244063)
    } else {
        (-2.0064e9, 1.9018e6, 0.24748e3, 0.237040)
    };
    let x = a / (t * t * t) + b / (t * t) + c / t + d;
    [x, -3.0 * x * x + 2.870 * x - 0.275]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn daylight_6504_k_is_d65_and_the_blackbody_takes_over_below_4000_k() {
        // D65 is daylight at 6504 K (6500 K on the old c₂ scale): xy = (0.3127, 0.3290).
        let d65 = daylight_white(6500.0);
        assert!((d65[0] - 0.3127).abs() < 2e-4 && (d65[1] - 0.3290).abs() < 2e-4, "{d65:?}");
        // D50 (5003 K): (0.3457, 0.3585).
        let d50 = daylight_white(5000.0);
        assert!((d50[0] - 0.3457).abs() < 2e-4 && (d50[1] - 0.3585).abs() < 2e-4, "{d50:?}");
        // Illuminant A is a 2856 K blackbody: (0.4476, 0.4074).
        let a = daylight_white(2856.0 * 1.4380 / 1.4388);
        assert!((a[0] - 0.4476).abs() < 1e-3 && (a[1] - 0.4074).abs() < 1e-3, "{a:?}");
    }

    #[test]
    fn white_balance_maps_the_illuminant_white_to_the_space_white_and_keeps_y_scale() {
        let srgb = ColorSpace::srgb();
        let sensor = Sensor::new(100.0, 1.0, 3200.0, srgb);
        let src = xyz_of(daylight_white(3200.0)).as_vec3();
        let out = sensor.apply(src * 2.0);
        let dst = xyz_of(srgb.white).as_vec3() * 2.0;
        assert!((out - dst).length() < 1e-4 * dst.length(), "{out:?} vs {dst:?}");
        // White balancing to the space's own white is the identity.
        let same = von_kries(srgb.white, srgb.white);
        assert!((same - DMat3::IDENTITY).to_cols_array().iter().all(|v| v.abs() < 1e-12));
    }

    #[test]
    fn max_component_scales_the_sample_after_the_imaging_ratio() {
        let s = Sensor::new(200.0, 1.0, 0.0, ColorSpace::srgb()).with_max_component(4.0);
        // Ratio 2: (1, 3, 0.5) → (2, 6, 1), whose largest component 6 becomes 4.
        let got = s.apply(Vec3::new(1.0, 3.0, 0.5));
        assert!((got - Vec3::new(4.0 / 3.0, 4.0, 2.0 / 3.0)).abs().max_element() < 1e-6, "{got}");
        assert_eq!(s.apply(Vec3::new(1.0, 1.5, 0.0)), Vec3::new(2.0, 3.0, 0.0));
    }

    #[test]
    fn imaging_ratio_is_exposure_times_iso_over_100() {
        let s = Sensor::new(400.0, 0.5, 0.0, ColorSpace::srgb());
        assert_eq!(s.imaging_ratio, 2.0);
        assert_eq!(s.apply(Vec3::new(1.0, 2.0, 3.0)), Vec3::new(2.0, 4.0, 6.0));
        assert_eq!(Sensor::default().apply(Vec3::ONE), Vec3::ONE);
    }
}
