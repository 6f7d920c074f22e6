//! Integer quantisation of sRGB-encoded images; the transfer curve itself is the spectrum
//! module's (IEC 61966-2-1:1999).

pub(crate) use crate::spectrum::{srgb_decode as decode, srgb_encode as encode};

/// Whether channel `c` of a `channels`-channel pixel is alpha (Y A or R G B A): alpha is
/// coverage, not light, so it is stored without the transfer curve.
pub(crate) fn is_alpha(c: usize, channels: usize) -> bool {
    (channels == 2 || channels == 4) && c == channels - 1
}

/// Quantises an encoded value to an integer code in `0..=max_code` by clamping and rounding
/// to nearest; NaN maps to 0.
pub(crate) fn quantise(encoded: f32, max_code: u32) -> u32 {
    let v = if encoded.is_nan() { 0.0 } else { encoded.clamp(0.0, 1.0) };
    (v * max_code as f32).round() as u32
}

/// Linear pixels → integer codes with the sRGB curve on colour channels and none on alpha.
pub(crate) fn encode_to_codes(data: &[f32], channels: usize, max_code: u32) -> Vec<u32> {
    data.iter()
        .enumerate()
        .map(|(i, &v)| {
            let e = if is_alpha(i % channels, channels) { v } else { encode(v) };
            quantise(e, max_code)
        })
        .collect()
}

/// Normalised integer samples in [0,1] → linear values, decoding colour channels only.
///
/// Each sample is first snapped to the exact `code / max_code`: readers normalise in
/// slightly different ways (OIIO multiplies by 1/255), and snapping makes every backend
/// return bit-identical values for the same file.
pub(crate) fn decode_normalised_in_place(data: &mut [f32], channels: usize, max_code: u32) {
    let max = max_code as f32;
    for (i, v) in data.iter_mut().enumerate() {
        let snapped = (*v * max).round() / max;
        *v = if is_alpha(i % channels, channels) { snapped } else { decode(snapped) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curve_round_trips_and_hits_reference_points() {
        // Reference: 18% grey encodes to ≈0.4614 (sRGB 118/255).
        assert!((encode(0.18) - 0.461_356).abs() < 1e-5);
        assert_eq!(encode(0.0), 0.0);
        assert!((encode(1.0) - 1.0).abs() < 1e-6);
        for i in 0..=1000 {
            let x = i as f32 / 1000.0;
            assert!((decode(encode(x)) - x).abs() < 2e-6, "x = {x}");
        }
        // The two pieces meet continuously at the breakpoint.
        let below = encode(0.003_130_8);
        let above = encode(0.003_130_9);
        assert!((above - below).abs() < 1e-5);
    }

    #[test]
    fn quantise_clamps_rounds_and_maps_nan_to_zero() {
        assert_eq!(quantise(-1.0, 255), 0);
        assert_eq!(quantise(2.0, 255), 255);
        assert_eq!(quantise(f32::NAN, 255), 0);
        assert_eq!(quantise(0.5, 255), 128); // 127.5 rounds away from zero
        assert_eq!(quantise(1.0, 65535), 65535);
    }

    #[test]
    fn alpha_is_not_encoded() {
        let codes = encode_to_codes(&[0.18, 0.18, 0.18, 0.18], 4, 255);
        assert_eq!(codes, vec![118, 118, 118, 46]);
    }
}
