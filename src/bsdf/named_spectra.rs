//! pbrt-v4's named spectra as spectra: the illuminants of [`crate::spectrum`], metals' η and k
//! ([`super::metals`]) and glasses' η ([`super::ior`]); the names are
//! [`crate::spectrum::NAMED_SPECTRA`].

use super::{ior, metals};
use crate::spectrum::Spectrum;

/// pbrt-v4's named spectra that prism knows: illuminants, metals' η and k, glasses' η.
pub fn named_spectrum(name: &str) -> Option<Spectrum> {
    if let Some(s) = Spectrum::named(name) {
        return Some(s);
    }
    if let Some(data) = metals::named_spectrum(name) {
        let (l, x): (Vec<f32>, Vec<f32>) = data.iter().copied().unzip();
        return Spectrum::piecewise_linear(&l, &x);
    }
    let glass = name.strip_prefix("glass-").map(|g| g.to_string())?;
    ior::eta(&glass, 550.0)?;
    let l: Vec<f32> = (360..=830).step_by(5).map(|x| x as f32).collect();
    let v: Vec<f32> = l.iter().map(|&x| ior::eta(&glass, x).unwrap_or(1.5)).collect();
    Spectrum::piecewise_linear(&l, &v)
}
