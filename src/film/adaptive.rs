//! What adaptive sampling keeps of each pixel besides its sums: how many sample indices it has
//! taken, how many the next pass adds, and the moments of its samples in output RGB, from which
//! the pixel's contribution to the image's expected error is estimated.

use super::gbuffer::Moments;
use super::Pixel;
use glam::{DVec3, Mat3, Vec3};

/// One pixel's sample count and statistics under adaptive sampling.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AdaptivePixel {
    /// Sample indices taken: the pixel holds samples 0..taken of its stream (a non-finite one
    /// is dropped from the sums but counted here, as in a uniform render).
    pub taken: u64,
    /// Sample indices the next pass adds: taken..taken + planned.
    pub planned: u64,
    /// Moments of the finite samples' filter-weighted output RGB, w·RGB.
    pub moments: Moments,
}

impl AdaptivePixel {
    /// Records a finite sample's sensor response `xyz` with filter weight `w`; `to_rgb` is the
    /// output colour space's XYZ → RGB matrix.
    #[inline]
    pub fn add(&mut self, to_rgb: &Mat3, xyz: Vec3, w: f32) {
        self.moments.add((*to_rgb * xyz * w).as_dvec3());
    }

    /// The variance one sample adds to the pixel's x/(1+x)-mapped RGB, summed over the three
    /// channels: Σₖ c′(mₖ)² s²ₖ / w̄², where `rgb` is the pixel's estimate m, s² the samples'
    /// variance of w·RGB, w̄ their mean weight and c(x) = x/(1+x) (c′ = 1/(1+x)², taken as 1 for
    /// x ≤ 0, where the mapping clips). The pixel's expected squared error after n samples is
    /// this over n (the delta method applied to the ratio estimator Σw·RGB / Σw; exact in the
    /// first order for filters of constant weight). `None` below two samples.
    pub fn compressed_variance(&self, px: &Pixel, rgb: Vec3) -> Option<f64> {
        if self.moments.n < 2 || px.weight_sum == 0.0 {
            return None;
        }
        let mean_weight = px.weight_sum / self.moments.n as f64;
        let slope = |m: f32| 1.0 / (1.0 + f64::from(m.max(0.0))).powi(2);
        let slopes = DVec3::new(slope(rgb.x), slope(rgb.y), slope(rgb.z));
        let v = slopes * slopes * self.moments.variance();
        Some(v.element_sum() / (mean_weight * mean_weight))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compressed_variance_is_the_mapped_variance_of_one_sample() {
        // Samples 0 and 2 with weight 1: mean 1, variance 2; c'(1) = 1/4, so each channel
        // contributes 2/16 and the three together 3/8.
        let mut a = AdaptivePixel::default();
        let mut px = Pixel::default();
        for v in [0.0f32, 2.0] {
            a.add(&Mat3::IDENTITY, Vec3::splat(v), 1.0);
            px.weight_sum += 1.0;
        }
        let v = a.compressed_variance(&px, Vec3::ONE).unwrap();
        assert!((v - 3.0 / 8.0).abs() < 1e-12, "{v}");
        // A constant weight scales w·RGB and w̄ alike: the same.
        let mut b = AdaptivePixel::default();
        px.weight_sum = 0.0;
        for v in [0.0f32, 2.0] {
            b.add(&Mat3::IDENTITY, Vec3::splat(v), 0.5);
            px.weight_sum += 0.5;
        }
        assert!((b.compressed_variance(&px, Vec3::ONE).unwrap() - 3.0 / 8.0).abs() < 1e-12);
        assert_eq!(AdaptivePixel::default().compressed_variance(&px, Vec3::ONE), None);
    }
}
