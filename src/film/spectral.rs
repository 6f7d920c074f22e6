//! Spectral radiance in wavelength buckets beside the image, as pbrt-v4's `SpectralFilm`
//! records it: [λmin, λmax] cut into `buckets` equal intervals, each pixel holding per bucket
//! the filter-weighted mean of the radiance values of the sampled wavelengths that fell in it.
//! Written as OpenEXR channels `S0.<centre>nm` in the layout of Fichet, Pacanowski and Wilkie,
//! "An OpenEXR Layout for Spectral Images", JCGT 10(3), 2021.

use crate::spectrum::{SampledSpectrum, SampledWavelengths, CIE_Y_INTEGRAL, N_SPECTRUM_SAMPLES};

/// The buckets (pbrt-v4's `nbuckets`, `lambdamin`, `lambdamax`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpectralSettings {
    /// Number of equal wavelength intervals (pbrt-v4's default 16).
    pub buckets: u32,
    /// Lower end of the first [nm] (default 360).
    pub lambda_min: f32,
    /// Upper end of the last [nm] (default 830).
    pub lambda_max: f32,
}

impl Default for SpectralSettings {
    /// pbrt-v4's defaults: 16 buckets over [360, 830] nm.
    fn default() -> Self {
        Self { buckets: 16, lambda_min: 360.0, lambda_max: 830.0 }
    }
}

impl SpectralSettings {
    /// f64 sums per pixel: per bucket Σ w·L, then per bucket Σ w.
    pub fn stride(&self) -> usize {
        2 * self.buckets as usize
    }

    /// The bucket of wavelength `lambda` [nm] (clamped to the first or last, as pbrt-v4's
    /// `LambdaToBucket`).
    #[inline]
    pub fn bucket(&self, lambda: f32) -> usize {
        let n = self.buckets as f32;
        let b = (n * (lambda - self.lambda_min) / (self.lambda_max - self.lambda_min)) as i64;
        b.clamp(0, self.buckets as i64 - 1) as usize
    }

    /// The wavelengths a camera sample carries: uniform over [λmin, λmax] (pbrt-v4's
    /// `SpectralFilm::SampleWavelengths`). With equal buckets and a uniform density, the
    /// weighted mean of the values that land in a bucket estimates the bucket's mean radiance
    /// without dividing by the density. The RGB image then integrates over [λmin, λmax] only.
    #[inline]
    pub fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        SampledWavelengths::sample_uniform_range(u, self.lambda_min, self.lambda_max)
    }

    /// Adds one sample's radiance `l` [W·m⁻²·sr⁻¹·nm⁻¹] at `lambdas` with filter weight `w` to
    /// a pixel's sums `sums` ([`Self::stride`] long). A sample whose largest value exceeds
    /// `max_component` in pbrt-v4's units (radiance ÷ ∫ȳ: pbrt-v4 normalises a light's spectrum
    /// to ∫ȳ S dλ = 1, prism to a luminance of 1) is scaled down to it, as pbrt-v4 clamps it.
    /// A wavelength whose density is 0 (a secondary wavelength terminated at a dispersive
    /// interface) adds nothing: its value did not follow its own path.
    #[inline]
    pub fn add(&self, sums: &mut [f64], l: &SampledSpectrum, lambdas: &SampledWavelengths, w: f32, max_component: f32) {
        let peak = l.max_value() / CIE_Y_INTEGRAL;
        let scale = if peak > max_component { max_component / peak } else { 1.0 };
        let n = self.buckets as usize;
        for i in 0..N_SPECTRUM_SAMPLES {
            if lambdas.pdf[i] == 0.0 {
                continue;
            }
            let b = self.bucket(lambdas.lambda[i]);
            sums[b] += (w * scale * l.0[i]) as f64;
            sums[n + b] += w as f64;
        }
    }

    /// The bucket means of a pixel's sums (0 for a bucket no wavelength fell in).
    pub fn means<'a>(&self, sums: &'a [f64]) -> impl Iterator<Item = f32> + 'a {
        let (l, w) = sums.split_at(self.buckets as usize);
        l.iter().zip(w).map(|(&l, &w)| if w > 0.0 { (l / w) as f32 } else { 0.0 })
    }

    /// The centre of bucket `i` [nm], in single precision as pbrt-v4 computes it.
    pub fn centre(&self, i: u32) -> f32 {
        let t = (i as f32 + 0.5) / self.buckets as f32;
        (1.0 - t) * self.lambda_min + t * self.lambda_max
    }

    /// The OpenEXR channel names of the buckets: `S0.` and the centre with three decimals and
    /// a comma for the decimal point (a '.' separates OpenEXR layers), then `nm`: 16 buckets
    /// over [360, 830] begin with `S0.374,688nm`.
    pub fn channel_names(&self) -> Vec<String> {
        (0..self.buckets)
            .map(|i| format!("S0.{}nm", format!("{:.3}", self.centre(i) as f64).replace('.', ",")))
            .collect()
    }

    /// Whether pbrt-v4 accepts these settings; the reason when not.
    pub fn check(&self) -> Result<(), String> {
        use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN};
        if self.buckets == 0 {
            return Err("\"nbuckets\" must be at least 1".into());
        }
        if !(self.lambda_min >= LAMBDA_MIN && self.lambda_max <= LAMBDA_MAX) {
            return Err(format!(
                "[\"lambdamin\", \"lambdamax\"] = [{}, {}] must lie within [{LAMBDA_MIN}, {LAMBDA_MAX}] nm",
                self.lambda_min, self.lambda_max
            ));
        }
        if self.lambda_min >= self.lambda_max {
            return Err(format!("\"lambdamin\" {} must be below \"lambdamax\" {}", self.lambda_min, self.lambda_max));
        }
        Ok(())
    }
}

/// The buckets of every pixel of a film.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralSums {
    /// The buckets.
    pub settings: SpectralSettings,
    /// Row-major, [`SpectralSettings::stride`] sums per pixel.
    pub sums: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_names_are_pbrt_v4s() {
        let s = SpectralSettings::default();
        let names = s.channel_names();
        assert_eq!(names.len(), 16);
        // Width 470/16 = 29.375 nm: centres 360 + 29.375 (i + ½).
        assert_eq!(names[0], "S0.374,688nm");
        assert_eq!(names[1], "S0.404,062nm"); // 404.0625: the tie goes to the even digit
        assert_eq!(names[15], "S0.815,312nm");
        let t = SpectralSettings { buckets: 3, lambda_min: 400.0, lambda_max: 700.0 };
        assert_eq!(t.channel_names(), ["S0.450,000nm", "S0.550,000nm", "S0.650,000nm"]);
    }

    #[test]
    fn wavelengths_fall_in_their_interval() {
        let s = SpectralSettings { buckets: 4, lambda_min: 400.0, lambda_max: 800.0 };
        assert_eq!(s.bucket(400.0), 0);
        assert_eq!(s.bucket(499.9), 0);
        assert_eq!(s.bucket(500.0), 1);
        assert_eq!(s.bucket(799.9), 3);
        assert_eq!(s.bucket(800.0), 3);
        assert_eq!(s.bucket(300.0), 0);
    }

    #[test]
    fn sums_give_the_weighted_mean_per_bucket() {
        let s = SpectralSettings { buckets: 4, lambda_min: 400.0, lambda_max: 800.0 };
        let mut sums = vec![0.0; s.stride()];
        let lambdas = SampledWavelengths { lambda: [450.0, 550.0, 650.0, 750.0], pdf: [1.0 / 400.0; 4] };
        s.add(&mut sums, &SampledSpectrum::new([1.0, 2.0, 3.0, 4.0]), &lambdas, 1.0, f32::INFINITY);
        s.add(&mut sums, &SampledSpectrum::new([3.0, 2.0, 3.0, 4.0]), &lambdas, 3.0, f32::INFINITY);
        assert_eq!(s.means(&sums).collect::<Vec<_>>(), [2.5, 2.0, 3.0, 4.0]);
        // A terminated secondary adds nothing; a bucket nothing fell in reads 0.
        let mut sums = vec![0.0; s.stride()];
        let lambdas = SampledWavelengths { lambda: [450.0, 550.0, 650.0, 750.0], pdf: [1.0 / 1600.0, 0.0, 0.0, 0.0] };
        s.add(&mut sums, &SampledSpectrum::new([1.0, 2.0, 3.0, 4.0]), &lambdas, 1.0, f32::INFINITY);
        assert_eq!(s.means(&sums).collect::<Vec<_>>(), [1.0, 0.0, 0.0, 0.0]);
        // The clamp acts on radiance ÷ ∫ȳ.
        let mut sums = vec![0.0; s.stride()];
        let l = SampledSpectrum::new([CIE_Y_INTEGRAL * 4.0, CIE_Y_INTEGRAL, 0.0, 0.0]);
        let lambdas = SampledWavelengths { lambda: [450.0, 550.0, 650.0, 750.0], pdf: [1.0 / 400.0; 4] };
        s.add(&mut sums, &l, &lambdas, 1.0, 2.0);
        let m: Vec<f32> = s.means(&sums).collect();
        assert!((m[0] / CIE_Y_INTEGRAL - 2.0).abs() < 1e-5 && (m[1] / CIE_Y_INTEGRAL - 0.5).abs() < 1e-5, "{m:?}");
    }

    #[test]
    fn pbrt_v4_rejects_what_it_cannot_render() {
        assert!(SpectralSettings::default().check().is_ok());
        assert!(SpectralSettings { buckets: 0, ..Default::default() }.check().is_err());
        assert!(SpectralSettings { lambda_min: 300.0, ..Default::default() }.check().is_err());
        assert!(SpectralSettings { lambda_max: 900.0, ..Default::default() }.check().is_err());
        assert!(SpectralSettings { lambda_min: 600.0, lambda_max: 500.0, ..Default::default() }.check().is_err());
    }
}
