//! Photometric scaling: lights given in lumens or lux, turned into radiometric quantities.
//!
//! Luminous flux Φ_v = K_m ∫ Φ_e(λ) ȳ(λ) dλ [lm] with K_m = 683 lm/W (CIE 1931 ȳ, peak 1 at
//! 555 nm; SI definition of the candela). A source of spectral shape s(λ) therefore has the
//! luminous efficacy of radiation K = K_m ∫ s ȳ dλ / ∫ s dλ [lm/W], and a bulb of Φ_v lumens
//! emits Φ_e = Φ_v / K watts. pbrt-v4 scales lights the same way (`SpectrumToPhotometric`,
//! `src/pbrt/lights.cpp`): divide the spectrum by its photometric integral, then multiply by the
//! requested quantity over the light's geometric factor k_e (4π for a point light, the cone's
//! solid angle for a spotlight, π·A per side for an area light, π for a uniform sky).

pub(crate) use super::point::spectral_integral;
use crate::spectrum::{Spectrum, CIE_Y_INTEGRAL};

/// Maximum luminous efficacy K_m [lm/W] ([`crate::spectrum::K_M`]).
pub const K_M: f32 = crate::spectrum::K_M as f32;

/// Lumens per watt of a spectrum with luminance Y = 1 in the ∫ȳ normalisation (see `spectrum::cie`)
/// (∫ s ȳ dλ = ∫ ȳ dλ): K_m ∫ ȳ dλ ≈ 72 983 [lm/W·nm].
pub fn lumens_per_unit_y() -> f32 {
    K_M * CIE_Y_INTEGRAL
}

/// K_m ∫ s ȳ dλ: the photometric value of one unit of `s` (pbrt-v4's `SpectrumToPhotometric`
/// with K_m made explicit), e.g. lm per W/nm of flux or lux per W/(m²·nm) of irradiance.
pub fn photometric_integral(s: &Spectrum) -> f32 {
    lumens_per_unit_y() * s.y()
}

/// Luminous efficacy of radiation K = K_m ∫ s ȳ dλ / ∫ s dλ over 360–830 nm [lm/W]
/// (0 for a black spectrum).
pub fn luminous_efficacy(s: &Spectrum) -> f32 {
    let radiometric = spectral_integral(s);
    if radiometric > 0.0 {
        photometric_integral(s) / radiometric
    } else {
        0.0
    }
}

/// Radiant flux Φ_e = Φ_v / K [W] of a source emitting `lumens` with spectral shape `s`.
pub fn radiant_flux_from_lumens(lumens: f32, s: &Spectrum) -> f32 {
    let k = luminous_efficacy(s);
    if k > 0.0 {
        lumens / k
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn efficacy_of_monochromatic_555_nm_is_k_m_and_white_is_lower() {
        // A narrow triangle 545–555–565 nm (linear between whole nanometres, so the 1 nm rule of
        // `spectral_integral` is exact): K is K_m times the mean of ȳ ≈ 0.99 over it.
        let mono = Spectrum::piecewise_linear(&[545.0, 555.0, 565.0], &[0.0, 1.0, 0.0]).unwrap();
        let k = luminous_efficacy(&mono);
        assert!(k < 683.0 && k > 0.98 * 683.0, "{k}");
        // Equal-energy white over 360–830 nm: K = K_m ∫ȳ / 470 nm ≈ 155.3 lm/W.
        let k_e = luminous_efficacy(&Spectrum::constant(1.0));
        let expected = K_M * CIE_Y_INTEGRAL / 470.0;
        assert!((k_e - expected).abs() < 1e-3 * expected, "{k_e} vs {expected}");
        // An incandescent-like 2700 K blackbody wastes most of the visible band on red.
        let k_bb = luminous_efficacy(&Spectrum::blackbody(2700.0));
        assert!(k_bb > 50.0 && k_bb < k_e, "{k_bb}");
        assert_eq!(luminous_efficacy(&Spectrum::constant(0.0)), 0.0);
    }

    #[test]
    fn a_bulb_in_lumens_gives_watts_through_its_efficacy() {
        let s = Spectrum::blackbody(2700.0);
        let watts = radiant_flux_from_lumens(800.0, &s);
        eprintln!("2700 K: K = {} lm/W, 800 lm = {watts} W", luminous_efficacy(&s));
        // Back: Φ_v = K_m ∫ Φ_e(λ) ȳ dλ with Φ_e(λ) = watts · s(λ) / ∫ s.
        let back = watts * photometric_integral(&s) / spectral_integral(&s);
        assert!((back - 800.0).abs() < 1e-3 * 800.0, "{back}");
    }
}
