//! Named spectra as spectra: pbrt-v4's ([`Spectrum::named`], from pbrt-v4's tables), then
//! prism's own: measured metals' η and k ([`super::metals`], `prism-metal-Ag-eta` …,
//! `metal-Cr-k` …) and Sellmeier glasses' η ([`super::ior`], `glass-water`, `prism-glass-BK7`
//! …); the names are [`crate::spectrum::NAMED_SPECTRA`] and the camera channels.

use super::{ior, metals};
use crate::spectrum::Spectrum;

/// The spectrum called `name`, pbrt-v4's or prism's own.
pub fn named_spectrum(name: &str) -> Option<Spectrum> {
    if let Some(s) = Spectrum::named(name) {
        return Some(s);
    }
    let own = name.strip_prefix("prism-").unwrap_or(name);
    if let Some(data) = metals::named_spectrum(own) {
        let (l, x): (Vec<f32>, Vec<f32>) = data.iter().copied().unzip();
        return Spectrum::piecewise_linear(&l, &x);
    }
    let glass = own.strip_prefix("glass-")?;
    ior::eta(glass, 550.0)?;
    let l: Vec<f32> = (360..=830).step_by(5).map(|x| x as f32).collect();
    let v: Vec<f32> = l.iter().map(|&x| ior::eta(glass, x).unwrap_or(1.5)).collect();
    Spectrum::piecewise_linear(&l, &v)
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_listed_name_has_data() {
        for n in crate::spectrum::NAMED_SPECTRA {
            assert!(super::named_spectrum(n).is_some(), "{n}");
        }
    }
}
