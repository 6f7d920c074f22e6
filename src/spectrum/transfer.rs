//! The sRGB transfer function (IEC 61966-2-1:1999 §4.7), for 8-bit display output.

/// Linear → sRGB-encoded: 12.92·L for L ≤ 0.0031308, else 1.055·L^(1/2.4) − 0.055.
/// Negative inputs give 0 and NaN gives 0 (images must stay displayable).
pub fn srgb_encode(linear: f32) -> f32 {
    if linear.is_nan() || linear <= 0.0 {
        0.0
    } else if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB-encoded → linear, the inverse of [`srgb_encode`]: V/12.92 for V ≤ 0.04045, else
/// ((V + 0.055)/1.055)^2.4.
pub fn srgb_decode(encoded: f32) -> f32 {
    if encoded.is_nan() || encoded <= 0.0 {
        0.0
    } else if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear value → 8-bit sRGB code, clamped to [0, 255] and rounded.
pub fn srgb_to_u8(linear: f32) -> u8 {
    (srgb_encode(linear).clamp(0.0, 1.0) * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        // Mid grey: linear 0.18 → 0.46135 (IEC formula evaluated in f64).
        assert!((srgb_encode(0.18) - 0.461_356).abs() < 1e-5);
        assert!((srgb_encode(0.002) - 0.025_84).abs() < 1e-6);
        assert_eq!(srgb_to_u8(0.5), 188);
        assert_eq!(srgb_to_u8(2.0), 255);
        assert_eq!(srgb_encode(f32::NAN), 0.0);
        assert_eq!(srgb_encode(-1.0), 0.0);
    }

    #[test]
    fn inverse_and_continuity() {
        for i in 0..=1000 {
            let l = i as f32 / 1000.0;
            assert!((srgb_decode(srgb_encode(l)) - l).abs() < 2e-6, "{l}");
        }
        // Both branches meet at the threshold (to the standard's rounding of its constants).
        let t = 0.003_130_8f32;
        let lin = 12.92 * t;
        let pow = 1.055 * t.powf(1.0 / 2.4) - 0.055;
        assert!((lin - pow).abs() < 1e-6);
        for code in 0..=255u8 {
            let v = code as f32 / 255.0;
            assert_eq!(srgb_to_u8(srgb_decode(v)), code);
        }
    }
}
