//! How the integer codes of an image file map to linear values (pbrt-v4 `ColorEncoding`, the
//! imagemap "encoding" parameter): the sRGB curve, none ("linear"), or a power law
//! ("gamma G": linear = code^G).

use std::fmt;

/// A transfer curve from encoded values in [0, 1] to linear ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorEncoding {
    /// The value is the code (normalised to [0, 1]).
    Linear,
    /// IEC 61966-2-1 sRGB.
    Srgb,
    /// linear = code^γ.
    Gamma(f32),
}

impl ColorEncoding {
    /// Parses pbrt-v4's names: "linear", "sRGB", "gamma G" (G > 0).
    pub fn parse(s: &str) -> Option<Self> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("linear") {
            return Some(ColorEncoding::Linear);
        }
        if s.eq_ignore_ascii_case("srgb") {
            return Some(ColorEncoding::Srgb);
        }
        let g: f32 = s.strip_prefix("gamma")?.trim().parse().ok()?;
        (g.is_finite() && g > 0.0).then_some(ColorEncoding::Gamma(g))
    }

    /// The linear value of the normalised code `v` ∈ [0, 1].
    pub fn to_linear(self, v: f32) -> f32 {
        match self {
            ColorEncoding::Linear => v,
            ColorEncoding::Srgb => crate::spectrum::srgb_decode(v),
            ColorEncoding::Gamma(g) => v.max(0.0).powf(g),
        }
    }
}

impl fmt::Display for ColorEncoding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ColorEncoding::Linear => write!(f, "linear"),
            ColorEncoding::Srgb => write!(f, "sRGB"),
            ColorEncoding::Gamma(g) => write!(f, "gamma {g}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_pbrt_names() {
        assert_eq!(ColorEncoding::parse("linear"), Some(ColorEncoding::Linear));
        assert_eq!(ColorEncoding::parse("sRGB"), Some(ColorEncoding::Srgb));
        assert_eq!(ColorEncoding::parse("gamma 2.2"), Some(ColorEncoding::Gamma(2.2)));
        assert_eq!(ColorEncoding::parse("gamma"), None);
        assert_eq!(ColorEncoding::parse("gamma -1"), None);
        assert_eq!(ColorEncoding::parse("log"), None);
    }

    #[test]
    fn curves_map_codes_to_linear_values() {
        assert_eq!(ColorEncoding::Linear.to_linear(0.5), 0.5);
        assert!((ColorEncoding::Gamma(2.0).to_linear(0.5) - 0.25).abs() < 1e-7);
        // sRGB: code 0.5 is linear 0.214 (((0.5 + 0.055)/1.055)^2.4); below 0.04045 it is v/12.92.
        assert!((ColorEncoding::Srgb.to_linear(0.5) - 0.214_041).abs() < 1e-5);
        assert!((ColorEncoding::Srgb.to_linear(0.02) - 0.02 / 12.92).abs() < 1e-7);
    }
}
