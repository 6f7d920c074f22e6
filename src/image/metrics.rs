//! Error metrics between a test image and a reference, and a false-colour difference image,
//! for `prism compare`.

use std::fmt;

use super::colormap::viridis_srgb;
use super::{srgb, Image, ImageError};

/// ε in relMSE's denominator: keeps near-black reference pixels from dominating.
pub const REL_MSE_EPSILON: f64 = 1e-2;

/// Percentile of per-pixel error used as the robust maximum (scale of the false-colour map).
pub const ROBUST_PERCENTILE: f64 = 0.99;

/// Differences between an image `a` and a reference `b`, over all samples (every channel of
/// every pixel) that are finite in both.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Samples compared.
    pub samples: usize,
    /// Samples skipped because `a` or `b` is NaN or infinite there.
    pub non_finite: usize,
    /// Mean squared error, mean((a−b)²).
    pub mse: f64,
    /// Root mean squared error, √mse.
    pub rmse: f64,
    /// Relative MSE, mean((a−b)² / (b² + ε)) with ε = [`REL_MSE_EPSILON`] (as in e.g.
    /// Rousselle et al. 2011 and the denoising literature).
    pub rel_mse: f64,
    /// Mean absolute error, mean(|a−b|).
    pub mae: f64,
    /// Largest |a−b|.
    pub max_abs: f64,
    /// [`ROBUST_PERCENTILE`] percentile of the per-pixel mean |a−b| over channels: the
    /// scale of [`false_colour_difference`].
    pub robust_max_abs: f64,
    /// Mean of `a`.
    pub mean_a: f64,
    /// Mean of `b`.
    pub mean_b: f64,
    /// Peak signal-to-noise ratio for peak 1, 10·log10(1/mse) dB; +∞ for identical images.
    pub psnr: f64,
}

/// A small table for `prism compare`, one metric per line.
impl fmt::Display for Metrics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "samples    {} ({} non-finite skipped)", self.samples, self.non_finite)?;
        writeln!(f, "mean       {:.6e} vs reference {:.6e}", self.mean_a, self.mean_b)?;
        writeln!(f, "MSE        {:.6e}", self.mse)?;
        writeln!(f, "RMSE       {:.6e}", self.rmse)?;
        writeln!(f, "relMSE     {:.6e} (eps {REL_MSE_EPSILON})", self.rel_mse)?;
        writeln!(f, "MAE        {:.6e}", self.mae)?;
        writeln!(f, "max |a-b|  {:.6e} (p99 per pixel {:.6e})", self.max_abs, self.robust_max_abs)?;
        write!(f, "PSNR       {:.2} dB", self.psnr)
    }
}

fn check_same_size(a: &Image, b: &Image) -> Result<(), ImageError> {
    a.validate()?;
    b.validate()?;
    if a.width != b.width || a.height != b.height || a.channels != b.channels {
        return Err(ImageError::SizeMismatch {
            a_width: a.width,
            a_height: a.height,
            a_channels: a.channels,
            b_width: b.width,
            b_height: b.height,
            b_channels: b.channels,
        });
    }
    Ok(())
}

/// Compares `a` against the reference `b`; the two must have equal size and channels.
/// With no finite sample pair every average is NaN.
pub fn compare(a: &Image, b: &Image) -> Result<Metrics, ImageError> {
    check_same_size(a, b)?;
    let (mut n, mut non_finite) = (0usize, 0usize);
    let (mut se, mut rel, mut ae, mut max_abs, mut sum_a, mut sum_b) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (&x, &y) in a.data.iter().zip(&b.data) {
        if !(x.is_finite() && y.is_finite()) {
            non_finite += 1;
            continue;
        }
        let (x, y) = (f64::from(x), f64::from(y));
        let d = x - y;
        n += 1;
        se += d * d;
        rel += d * d / (y * y + REL_MSE_EPSILON);
        ae += d.abs();
        max_abs = max_abs.max(d.abs());
        sum_a += x;
        sum_b += y;
    }
    let inv = if n > 0 { 1.0 / n as f64 } else { f64::NAN };
    let mse = se * inv;
    Ok(Metrics {
        samples: n,
        non_finite,
        mse,
        rmse: mse.sqrt(),
        rel_mse: rel * inv,
        mae: ae * inv,
        max_abs: if n > 0 { max_abs } else { f64::NAN },
        robust_max_abs: robust_max(&per_pixel_error(a, b)),
        mean_a: sum_a * inv,
        mean_b: sum_b * inv,
        psnr: -10.0 * mse.log10(),
    })
}

/// x/(1+x) of a non-negative sample (negative and NaN samples map to 0, +∞ to 1): a tone map
/// that keeps emitters and fireflies from dominating an error over the whole image.
fn compress(x: f32) -> f64 {
    let x = f64::from(x.max(0.0));
    if x.is_infinite() {
        1.0
    } else {
        x / (1.0 + x)
    }
}

/// RMSE between `a` and the reference `b` over their first three channels after mapping each
/// sample through x/(1+x) (so the error is bounded by 1 per sample whatever the dynamic range).
/// Both images must have equal size and at least three channels.
pub fn compressed_rgb_rmse(a: &Image, b: &Image) -> Result<f64, ImageError> {
    check_same_size(a, b)?;
    let c = a.channels as usize;
    if c < 3 {
        return Err(ImageError::InvalidImage(format!("{c} channels; RGB needs 3")));
    }
    let mut se = 0.0;
    for (pa, pb) in a.data.chunks_exact(c).zip(b.data.chunks_exact(c)) {
        for k in 0..3 {
            let d = compress(pa[k]) - compress(pb[k]);
            se += d * d;
        }
    }
    Ok((se / (3 * a.data.len() / c).max(1) as f64).sqrt())
}

/// Mean of each of the first three channels over the finite samples (NaN for a channel with
/// none, or for an image with fewer channels).
pub fn channel_means(img: &Image) -> [f64; 3] {
    let c = img.channels as usize;
    let mut sum = [0.0f64; 3];
    let mut n = [0usize; 3];
    if c >= 3 {
        for p in img.data.chunks_exact(c) {
            for k in 0..3 {
                if p[k].is_finite() {
                    sum[k] += f64::from(p[k]);
                    n[k] += 1;
                }
            }
        }
    }
    [0, 1, 2].map(|k| if n[k] > 0 { sum[k] / n[k] as f64 } else { f64::NAN })
}

/// Mean |a−b| over each pixel's channels; NaN where any sample is non-finite.
fn per_pixel_error(a: &Image, b: &Image) -> Vec<f32> {
    let c = a.channels as usize;
    a.data
        .chunks_exact(c)
        .zip(b.data.chunks_exact(c))
        .map(|(pa, pb)| {
            let sum: f32 = pa.iter().zip(pb).map(|(x, y)| (x - y).abs()).sum();
            if sum.is_finite() {
                sum / c as f32
            } else {
                f32::NAN
            }
        })
        .collect()
}

/// The [`ROBUST_PERCENTILE`] percentile of the finite values (nearest rank); 0 if none.
fn robust_max(values: &[f32]) -> f64 {
    let mut finite: Vec<f32> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return 0.0;
    }
    let rank = ((ROBUST_PERCENTILE * finite.len() as f64).ceil() as usize).clamp(1, finite.len());
    let (_, v, _) = finite.select_nth_unstable_by(rank - 1, f32::total_cmp);
    f64::from(*v)
}

/// An RGB image showing the per-pixel mean |a−b| through the viridis colormap, scaled so the
/// robust maximum ([`Metrics::robust_max_abs`], or the true maximum if that is 0) maps to the
/// top of the map. Non-finite pixels show as the top colour (yellow). Linear values, so
/// [`super::write`] reproduces viridis exactly in PNG.
pub fn false_colour_difference(a: &Image, b: &Image) -> Result<Image, ImageError> {
    check_same_size(a, b)?;
    let err = per_pixel_error(a, b);
    let mut scale = robust_max(&err) as f32;
    if scale <= 0.0 {
        scale = err.iter().copied().filter(|v| v.is_finite()).fold(0.0, f32::max);
    }
    let mut data = Vec::with_capacity(err.len() * 3);
    for e in err {
        let t = if scale > 0.0 { e / scale } else { e * 0.0 };
        data.extend(viridis_srgb(t).map(srgb::decode));
    }
    Ok(Image { width: a.width, height: a.height, channels: 3, data })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, channels: u32, data: Vec<f32>) -> Image {
        Image { width, height, channels, data }
    }

    #[test]
    fn identical_images_have_zero_error() {
        let a = image(2, 1, 3, vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6]);
        let m = compare(&a, &a).unwrap();
        assert_eq!(m.samples, 6);
        assert_eq!((m.mse, m.rel_mse, m.mae, m.max_abs), (0.0, 0.0, 0.0, 0.0));
        assert_eq!(m.psnr, f64::INFINITY);
        assert!((m.mean_a - 0.35).abs() < 1e-7);
    }

    #[test]
    fn known_differences() {
        // a − b = (+1, −1, +2, 0) over b = (1, 0, 2, 5).
        let b = image(2, 2, 1, vec![1.0, 0.0, 2.0, 5.0]);
        let a = image(2, 2, 1, vec![2.0, -1.0, 4.0, 5.0]);
        let m = compare(&a, &b).unwrap();
        assert!((m.mse - 6.0 / 4.0).abs() < 1e-12);
        assert!((m.rmse - 1.5f64.sqrt()).abs() < 1e-12);
        assert!((m.mae - 1.0).abs() < 1e-12);
        assert_eq!(m.max_abs, 2.0);
        let rel = (1.0 / 1.01 + 1.0 / 0.01 + 4.0 / 4.01 + 0.0) / 4.0;
        assert!((m.rel_mse - rel).abs() < 1e-9, "{} vs {rel}", m.rel_mse);
        assert!((m.psnr - (-10.0 * 1.5f64.log10())).abs() < 1e-9);
        assert!((m.mean_a - 2.5).abs() < 1e-12 && (m.mean_b - 2.0).abs() < 1e-12);
        let table = m.to_string();
        assert!(table.contains("MSE        1.500000e0"), "{table}");
        assert!(table.contains("samples    4 (0 non-finite skipped)"), "{table}");
    }

    #[test]
    fn compressed_rmse_and_channel_means_by_hand() {
        // One pixel: x/(1+x) of (1, 3, 0) is (1/2, 3/4, 0), of (0, 1, ∞) is (0, 1/2, 1).
        let a = image(1, 1, 3, vec![1.0, 3.0, 0.0]);
        let b = image(1, 1, 3, vec![0.0, 1.0, f32::INFINITY]);
        let e = compressed_rgb_rmse(&a, &b).unwrap();
        let want = ((0.25f64 + 0.0625 + 1.0) / 3.0).sqrt();
        assert!((e - want).abs() < 1e-12, "{e} vs {want}");
        assert_eq!(compressed_rgb_rmse(&a, &a).unwrap(), 0.0);
        assert!(compressed_rgb_rmse(&image(1, 1, 1, vec![0.0]), &image(1, 1, 1, vec![0.0])).is_err());
        let m = channel_means(&image(2, 1, 4, vec![1.0, 2.0, f32::NAN, 9.0, 3.0, 4.0, 5.0, 9.0]));
        assert_eq!(m, [2.0, 3.0, 5.0]);
    }

    #[test]
    fn non_finite_samples_are_counted_not_averaged() {
        let b = image(3, 1, 1, vec![0.0, 0.0, 0.0]);
        let a = image(3, 1, 1, vec![f32::NAN, f32::INFINITY, 0.5]);
        let m = compare(&a, &b).unwrap();
        assert_eq!((m.samples, m.non_finite), (1, 2));
        assert_eq!(m.mse, 0.25);
    }

    #[test]
    fn size_mismatch_is_an_error() {
        let a = Image::new(2, 2, 3);
        let b = Image::new(2, 3, 3);
        let err = compare(&a, &b).unwrap_err();
        assert_eq!(err.to_string(), "image size mismatch: 2x2x3 vs 2x3x3");
        assert!(false_colour_difference(&a, &Image::new(2, 2, 4)).is_err());
        let broken = image(2, 2, 3, vec![0.0; 5]);
        assert!(matches!(compare(&broken, &broken), Err(ImageError::InvalidImage(_))));
    }

    #[test]
    fn robust_max_ignores_rare_outliers() {
        // 1000 pixels with error i/1000 and one huge outlier: the 99th percentile stays
        // near 0.99 while max_abs sees the outlier.
        let n = 1001;
        let b = image(n, 1, 1, vec![0.0; n as usize]);
        let mut data: Vec<f32> = (0..1000).map(|i| i as f32 / 1000.0).collect();
        data.push(1e6);
        let a = image(n, 1, 1, data);
        let m = compare(&a, &b).unwrap();
        assert_eq!(m.max_abs, 1e6);
        // Nearest rank ⌈0.99·1001⌉ = 991 → the 991st smallest value, 0.990.
        assert!((m.robust_max_abs - 0.990).abs() < 1e-6, "{}", m.robust_max_abs);
    }

    #[test]
    fn false_colour_maps_zero_to_dark_and_scale_to_yellow() {
        // Per-pixel errors 0, 0.5, 1 (one channel of three differs by 3× that).
        let b = Image::new(3, 1, 3);
        let a = image(3, 1, 3, vec![0.0, 0.0, 0.0, 1.5, 0.0, 0.0, 3.0, 0.0, 0.0]);
        let fc = false_colour_difference(&a, &b).unwrap();
        assert_eq!((fc.width, fc.height, fc.channels), (3, 1, 3));
        let enc = |p: &[f32]| [srgb::encode(p[0]), srgb::encode(p[1]), srgb::encode(p[2])];
        let close = |x: [f32; 3], y: [f32; 3]| (0..3).all(|j| (x[j] - y[j]).abs() < 1e-4);
        assert!(close(enc(fc.pixel(0, 0).unwrap()), viridis_srgb(0.0)));
        assert!(close(enc(fc.pixel(1, 0).unwrap()), viridis_srgb(0.5)));
        assert!(close(enc(fc.pixel(2, 0).unwrap()), viridis_srgb(1.0)));
    }

    #[test]
    fn false_colour_of_identical_images_is_uniformly_dark() {
        let a = image(2, 1, 1, vec![0.3, 0.7]);
        let fc = false_colour_difference(&a, &a).unwrap();
        let dark = viridis_srgb(0.0).map(srgb::decode);
        for p in fc.data.chunks(3) {
            assert_eq!(p, dark);
        }
    }
}
