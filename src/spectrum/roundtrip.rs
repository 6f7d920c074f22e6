//! RGB → spectrum → XYZ → RGB round trips, the yardstick for the upsampling methods
//! (reflectances lit by the colour space's white, linear RGB).

use super::color_space::ColorSpace;
use super::smits::{smits_spectrum, SmitsKind};
use super::spd::{RgbKind, Spectrum};
use glam::DVec3;
use rayon::prelude::*;

/// An RGB → reflectance method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Upsampler {
    /// Jakob–Hanika with per-colour Newton refinement (`Spectrum::from_rgb`).
    JakobHanika,
    /// Jakob–Hanika from the coarse table alone (trilinear coefficients, no refinement).
    JakobHanikaTable,
    /// Smits 1999 reflectance basis.
    Smits,
}

impl Upsampler {
    /// The reflectance for `rgb` in `cs`.
    pub fn reflectance(self, rgb: [f64; 3], cs: &ColorSpace) -> Spectrum {
        match self {
            Upsampler::JakobHanika => Spectrum::from_rgb(rgb.map(|v| v as f32), RgbKind::Albedo, cs),
            Upsampler::JakobHanikaTable => {
                Spectrum::Sigmoid { poly: cs.rgb_to_spectrum_table().lookup(rgb), scale: 1.0 }
            }
            Upsampler::Smits => smits_spectrum(rgb, SmitsKind::Reflectance, cs),
        }
    }
}

/// Linear RGB of reflectance `s` lit by the white of `cs`.
pub fn reflectance_rgb(s: &Spectrum, cs: &ColorSpace) -> DVec3 {
    cs.xyz_to_rgb_f64 * s.clone().product(cs.illuminant.clone()).to_xyz_f64()
}

/// The round-trip RGB of `rgb` through `method`.
pub fn roundtrip(rgb: [f64; 3], method: Upsampler, cs: &ColorSpace) -> DVec3 {
    reflectance_rgb(&method.reflectance(rgb, cs), cs)
}

/// Round-trip errors over a grid.
#[derive(Clone, Copy, Debug)]
pub struct GridErrors {
    /// Largest max-abs-component error (NaN counts as infinite).
    pub max: f64,
    /// RMS over all components.
    pub rms: f64,
    /// Fraction of grid points with max abs error below 1e-3.
    pub within_1e3: f64,
}

/// Linear-RGB round-trip errors over the `n`³ grid on [0, 1]³.
pub fn grid_errors(n: usize, method: Upsampler, cs: &ColorSpace) -> GridErrors {
    let n = n.max(2);
    let errs: Vec<(f64, f64)> = (0..n * n * n)
        .into_par_iter()
        .map(|k| {
            let c = [k % n, (k / n) % n, k / (n * n)].map(|i| i as f64 / (n - 1) as f64);
            let d = roundtrip(c, method, cs) - DVec3::from_array(c);
            if d.is_finite() {
                (d.abs().max_element(), d.length_squared())
            } else {
                (f64::INFINITY, f64::INFINITY)
            }
        })
        .collect();
    let max = errs.iter().map(|e| e.0).fold(0.0, f64::max);
    let rms = (errs.iter().map(|e| e.1).sum::<f64>() / (3 * errs.len()) as f64).sqrt();
    let within = errs.iter().filter(|e| e.0 < 1e-3).count() as f64 / errs.len() as f64;
    GridErrors { max, rms, within_1e3: within }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jakob_hanika_grid_roundtrip_below_1e3() {
        let e = grid_errors(16, Upsampler::JakobHanika, ColorSpace::srgb());
        assert!(e.max < 1e-3, "{e:?}");
    }

    #[test]
    fn other_spaces_roundtrip() {
        // Fewer points per space (each table builds on first use), and only colours a
        // reflectance can have: saturated wide-gamut primaries lie outside the object-colour
        // solid (e.g. Rec.2020 (0.05, 0.9, 0.1) misses by 0.05; see docs/colour.md).
        for n in ["rec2020", "acescg", "dci-p3", "aces2065-1"] {
            let cs = ColorSpace::by_name(n).unwrap();
            for rgb in [[0.6, 0.2, 0.5], [0.7, 0.5, 0.2], [0.3, 0.6, 0.3], [0.2, 0.3, 0.7]] {
                let e = (roundtrip(rgb, Upsampler::JakobHanika, cs) - DVec3::from_array(rgb)).abs();
                assert!(e.max_element() < 1e-3, "{n} {rgb:?} {e}");
            }
        }
    }

    #[test]
    fn wide_gamut_spectra_stay_finite_and_bounded() {
        // Colours no reflectance reaches still give a finite spectrum in [0, 1].
        let cs = ColorSpace::by_name("aces2065-1").unwrap();
        for rgb in [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0]] {
            let p = cs.rgb_to_spectrum_table().lookup(rgb.map(|v| v as f64));
            assert!(p.c.iter().all(|v| v.is_finite()), "table {rgb:?}");
            let s = Spectrum::from_rgb(rgb, RgbKind::Albedo, cs);
            for l in (360..=830).step_by(10) {
                let v = s.eval(l as f32);
                assert!(v.is_finite() && (0.0..=1.0).contains(&v), "{rgb:?} {l} {v}");
            }
        }
    }

    #[test]
    fn unbounded_and_illuminant_kinds() {
        let cs = ColorSpace::srgb();
        let rgb = [3.0f32, 1.5, 0.4];
        let u = Spectrum::from_rgb(rgb, RgbKind::Unbounded, cs);
        let got = reflectance_rgb(&u, cs);
        let want = DVec3::new(3.0, 1.5, 0.4);
        assert!((got - want).abs().max_element() < 3e-3, "{got}");
        // Illuminant: the emitted spectrum's own XYZ gives the RGB (white has Y = 1).
        let e = Spectrum::from_rgb(rgb, RgbKind::Illuminant, cs);
        let got = cs.xyz_to_rgb_f64 * e.to_xyz_f64();
        assert!((got - want).abs().max_element() < 3e-3, "{got}");
        let w = Spectrum::from_rgb([1.0; 3], RgbKind::Illuminant, cs);
        assert!((w.to_xyz_f64().y - 1.0).abs() < 1e-9);
        assert_eq!(Spectrum::from_rgb([0.0; 3], RgbKind::Unbounded, cs).eval(500.0), 0.0);
        let v = Spectrum::from_rgb([f32::NAN, 2.0, 2.0], RgbKind::Albedo, cs).eval(400.0);
        assert!(v.is_finite() && (0.0..=1.0).contains(&v), "{v}");
    }
}
