//! The viridis colormap: perceptually uniform, readable in greyscale and by colour-blind viewers.
//!
//! Data: every 16th entry (plus the last) of the 256-entry table by van der Walt & Smith,
//! matplotlib `lib/matplotlib/_cm_listed.py` (`_viridis_data`, CC0). Between anchors we
//! interpolate linearly in the table's sRGB-encoded space; the error against the full table is
//! below 1/255 because the curve is smooth.

/// (table index 0–255, sRGB-encoded R, G, B).
const VIRIDIS: [(u8, [f32; 3]); 17] = [
    (0, [0.267004, 0.004874, 0.329415]),
    (16, [0.282327, 0.094955, 0.417331]),
    (32, [0.278826, 0.175490, 0.483397]),
    (48, [0.258965, 0.251537, 0.524736]),
    (64, [0.229739, 0.322361, 0.545706]),
    (80, [0.199430, 0.387607, 0.554642]),
    (96, [0.172719, 0.448791, 0.557885]),
    (112, [0.149039, 0.508051, 0.557250]),
    (128, [0.127568, 0.566949, 0.550556]),
    (144, [0.120638, 0.625828, 0.533488]),
    (160, [0.157851, 0.683765, 0.501686]),
    (176, [0.246070, 0.738910, 0.452024]),
    (192, [0.369214, 0.788888, 0.382914]),
    (208, [0.515992, 0.831158, 0.294279]),
    (224, [0.678489, 0.863742, 0.189503]),
    (240, [0.845561, 0.887322, 0.099702]),
    (255, [0.993248, 0.906157, 0.143936]),
];

/// Viridis at `t` ∈ [0,1] (clamped; NaN → 1, so invalid pixels stand out as yellow), as
/// sRGB-encoded RGB.
pub(crate) fn viridis_srgb(t: f32) -> [f32; 3] {
    let t = if t.is_nan() { 1.0 } else { t.clamp(0.0, 1.0) };
    let x = t * 255.0;
    let k = VIRIDIS.windows(2).position(|w| x <= f32::from(w[1].0)).unwrap_or(VIRIDIS.len() - 2);
    let (i0, c0) = VIRIDIS[k];
    let (i1, c1) = VIRIDIS[k + 1];
    let f = (x - f32::from(i0)) / f32::from(i1 - i0);
    [0, 1, 2].map(|j| c0[j] + f * (c1[j] - c0[j]))
}

/// A `width × height` RGB image of `values` (row-major) through viridis, 0 at the bottom of the
/// map and `max` at the top, in linear values so that a PNG of it shows viridis exactly.
pub fn viridis_image(values: &[f32], width: u32, height: u32, max: f32) -> super::Image {
    let data = values.iter().flat_map(|v| viridis_srgb(v / max).map(super::srgb::decode)).collect();
    super::Image { width, height, channels: 3, data }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_anchors_and_ends() {
        assert_eq!(viridis_srgb(0.0), VIRIDIS[0].1);
        assert_eq!(viridis_srgb(1.0), VIRIDIS[16].1);
        assert_eq!(viridis_srgb(-3.0), VIRIDIS[0].1);
        assert_eq!(viridis_srgb(f32::NAN), VIRIDIS[16].1);
        let mid = viridis_srgb(128.0 / 255.0);
        for (m, anchor) in mid.iter().zip(VIRIDIS[8].1) {
            assert!((m - anchor).abs() < 1e-6);
        }
    }

    #[test]
    fn lightness_increases_monotonically() {
        // Viridis is designed with monotone lightness; Rec. 709 luma of the encoded values
        // is a good enough proxy to catch a mistyped anchor.
        let luma = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let mut prev = -1.0;
        for i in 0..=100 {
            let l = luma(viridis_srgb(i as f32 / 100.0));
            assert!(l > prev, "luma not increasing at t = {}", i as f32 / 100.0);
            prev = l;
        }
    }
}
