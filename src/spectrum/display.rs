//! A display described by the emission spectra of its three channels (an additive
//! display): the colour of r·R(λ) + g·G(λ) + b·B(λ) is M (r, g, b)ᵀ with
//! M_ij = ∫ Pⱼ(λ) X̄ᵢ(λ) dλ / ∫ Ȳ dλ (P = R, G, B; X̄ᵢ = x̄, ȳ, z̄), so the drive values that
//! reproduce a spectrum S on the display are M⁻¹ XYZ(S).
//!
//! pbrt differs: its colour spaces are defined by primary *chromaticities* and a white
//! point, with the matrix scaled so that RGB (1,1,1) is the white at Y = 1; this M
//! keeps the panels' absolute emission (a brighter blue panel gives a larger column) and has
//! no white-point constraint. See docs/colour.md.

use super::spd::Spectrum;
use glam::{DMat3, DVec3};

/// A display given by its channels' emission spectra.
#[derive(Clone, Debug)]
pub struct EmissionDisplay {
    /// M: drive values → XYZ (the ∫ȳ normalisation (see `spectrum::cie`)).
    pub rgb_to_xyz: DMat3,
    /// M⁻¹: XYZ → drive values.
    pub xyz_to_rgb: DMat3,
}

impl EmissionDisplay {
    /// Builds M from the three emission spectra; `None` if they are linearly dependent in
    /// XYZ (M singular: the display cannot show a three-dimensional gamut).
    pub fn new(red: &Spectrum, green: &Spectrum, blue: &Spectrum) -> Option<Self> {
        let m = DMat3::from_cols(red.to_xyz_f64(), green.to_xyz_f64(), blue.to_xyz_f64());
        let det = m.determinant();
        let largest = m.to_cols_array().iter().map(|v| v.abs()).fold(0.0, f64::max);
        // Singular relative to the entries' scale (also rejects NaN).
        let invertible = det.abs() > 1e-12 * largest.powi(3);
        if !invertible {
            return None;
        }
        Some(Self { rgb_to_xyz: m, xyz_to_rgb: m.inverse() })
    }

    /// Drive values that make the display match the colour of `s` (may be negative or above
    /// 1 when `s` is outside the display's gamut).
    pub fn drive_values(&self, s: &Spectrum) -> DVec3 {
        self.xyz_to_rgb * s.to_xyz_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gaussian(mu: f64, sigma: f64) -> Spectrum {
        let l: Vec<f64> = (0..=470).map(|i| 360.0 + i as f64).collect();
        let v = l.iter().map(|x| (-0.5 * ((x - mu) / sigma).powi(2)).exp()).collect();
        Spectrum::piecewise_linear_f64(l, v).unwrap()
    }

    #[test]
    fn mixing_the_panels_reproduces_the_target_colour() {
        let (r, g, b) = (gaussian(610.0, 15.0), gaussian(545.0, 20.0), gaussian(450.0, 12.0));
        let d = EmissionDisplay::new(&r, &g, &b).unwrap();
        // A spectrum inside the gamut: the display's mix is a metamer of it.
        let target = Spectrum::named("stdillum-D65").unwrap().scaled(0.3);
        let drive = d.drive_values(&target);
        let mix = |l: f64| drive.x * r.eval_f64(l) + drive.y * g.eval_f64(l) + drive.z * b.eval_f64(l);
        let shown = crate::spectrum::cie::xyz_of(mix, &[]);
        assert!((shown - target.to_xyz_f64()).abs().max_element() < 1e-9);
        assert!(drive.min_element() > 0.0, "{drive}");
        // Each column is the panel's own XYZ.
        assert!((d.rgb_to_xyz.col(0) - r.to_xyz_f64()).abs().max_element() < 1e-15);
    }

    #[test]
    fn dependent_panels_are_rejected() {
        let r = gaussian(610.0, 15.0);
        assert!(EmissionDisplay::new(&r, &r.clone().scaled(2.0), &gaussian(450.0, 12.0)).is_none());
    }
}
