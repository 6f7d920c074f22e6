//! Fresnel reflectance of smooth interfaces (unpolarised light: the mean of the s and p
//! amplitudes squared; Born & Wolf, Principles of Optics, §1.5; pbrt-v4 §9.3).

use crate::spectrum::SampledSpectrum;

/// Reflectance of a dielectric interface for light arriving at `cos_theta_i` (negative: from
/// the inside), relative IOR `eta` = η_inside/η_outside. 1 under total internal reflection.
pub fn fr_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let (mut cos_i, mut eta) = (cos_theta_i.clamp(-1.0, 1.0), eta);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

/// A complex number, only as much as the conductor Fresnel equations need.
#[derive(Clone, Copy, Debug)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    fn add(self, o: Self) -> Self {
        Self { re: self.re + o.re, im: self.im + o.im }
    }
    fn sub(self, o: Self) -> Self {
        Self { re: self.re - o.re, im: self.im - o.im }
    }
    fn mul(self, o: Self) -> Self {
        Self { re: self.re * o.re - self.im * o.im, im: self.re * o.im + self.im * o.re }
    }
    fn norm(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    fn div(self, o: Self) -> Self {
        let d = o.norm();
        Self { re: (self.re * o.re + self.im * o.im) / d, im: (self.im * o.re - self.re * o.im) / d }
    }
    /// Principal square root.
    fn sqrt(self) -> Self {
        let n = self.norm().sqrt();
        if n == 0.0 {
            return Self { re: 0.0, im: 0.0 };
        }
        let t1 = (0.5 * (n + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            Self { re: t1, im: t2 }
        } else {
            Self { re: t2.abs(), im: t1.copysign(self.im) }
        }
    }
}

/// Reflectance of a conductor with complex IOR η + ik for light at `cos_theta_i` ∈ [0, 1]
/// (exact, from the complex form of Snell's law and the Fresnel amplitudes).
pub fn fr_complex(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let eta_c = Complex { re: eta, im: k };
    let ci = Complex { re: cos_i, im: 0.0 };
    let sin2_i = Complex { re: 1.0 - cos_i * cos_i, im: 0.0 };
    let sin2_t = sin2_i.div(eta_c.mul(eta_c));
    let cos_t = Complex { re: 1.0, im: 0.0 }.sub(sin2_t).sqrt();
    let eci = eta_c.mul(ci);
    let r_parl = eci.sub(cos_t).div(eci.add(cos_t));
    let ect = eta_c.mul(cos_t);
    let r_perp = ci.sub(ect).div(ci.add(ect));
    (r_parl.norm() + r_perp.norm()).clamp(0.0, 2.0) * 0.5
}

/// [`fr_complex`] at each of the four wavelengths.
pub fn fr_complex_spectrum(cos_theta_i: f32, eta: SampledSpectrum, k: SampledSpectrum) -> SampledSpectrum {
    let mut out = SampledSpectrum::zero();
    for i in 0..4 {
        out[i] = fr_complex(cos_theta_i, eta[i], k[i]);
    }
    out
}

/// Hemispherical-average reflectance 2∫₀¹ F(μ) μ dμ of a dielectric for light from the
/// outside (`eta` = η_inside/η_outside > 0), by 16-point Gauss–Legendre quadrature.
/// Light from the inside follows by reciprocity: 1 − (1 − F̄_out)/η².
pub fn fr_dielectric_average(eta: f32) -> f32 {
    // Gauss–Legendre nodes/weights on [−1, 1] (Abramowitz & Stegun Table 25.4), positive half.
    const X: [f32; 8] =
        [0.095_012_5, 0.281_603_6, 0.458_016_8, 0.617_876_2, 0.755_404_4, 0.865_631_2, 0.944_575, 0.989_400_9];
    const W: [f32; 8] =
        [0.189_450_6, 0.182_603_4, 0.169_156_5, 0.149_596, 0.124_629, 0.095_158_5, 0.062_253_5, 0.027_152_5];
    let mut sum = 0.0;
    for (x, w) in X.iter().zip(W) {
        for mu in [0.5 * (1.0 - x), 0.5 * (1.0 + x)] {
            sum += 0.5 * w * 2.0 * mu * fr_dielectric(mu, eta);
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_normal_incidence_and_tir() {
        // ((η−1)/(η+1))² at normal incidence; 1 beyond the critical angle from inside.
        assert!((fr_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fr_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        let crit = (1.0f32 - 1.0 / 2.25).sqrt(); // cos of the critical angle inside
        assert_eq!(fr_dielectric(-(crit - 0.01), 1.5), 1.0);
        assert!((fr_dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
        assert!(fr_dielectric(0.3, 1.0) < 1e-6);
    }

    #[test]
    fn complex_reduces_to_dielectric_when_k_is_zero() {
        for i in 0..=20 {
            let c = i as f32 / 20.0;
            assert!((fr_complex(c, 1.5, 0.0) - fr_dielectric(c, 1.5)).abs() < 1e-5, "{c}");
        }
        // Normal incidence: ((n−1)² + k²)/((n+1)² + k²). Gold-like n = 0.2, k = 3.
        let want = (0.64 + 9.0) / (1.44 + 9.0);
        assert!((fr_complex(1.0, 0.2, 3.0) - want).abs() < 1e-5);
    }

    #[test]
    fn average_reflectance_of_glass() {
        // Known value for η = 1.5: F̄ ≈ 0.0918 (e.g. d'Eon & Irving 2011, Table 1).
        let f = fr_dielectric_average(1.5);
        assert!((f - 0.0918).abs() < 1e-3, "{f}");
    }
}
