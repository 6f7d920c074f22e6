//! Planck's law for blackbody emission.

/// Speed of light in vacuum [m/s] (exact, SI 2019).
const C: f64 = 299_792_458.0;
/// Planck constant [J s] (exact, SI 2019).
const H: f64 = 6.626_070_15e-34;
/// Boltzmann constant [J/K] (exact, SI 2019).
const KB: f64 = 1.380_649e-23;
/// Wien's displacement constant b [m K]: λ_peak = b / T (CODATA 2018).
const WIEN_B: f64 = 2.897_771_955e-3;

/// Spectral radiance of a blackbody, B(λ, T) = 2hc² / λ⁵ / (exp(hc / (λ k T)) − 1),
/// in W sr⁻¹ m⁻² nm⁻¹, for `lambda_nm` [nm] and `kelvin` [K]. 0 for non-positive or infinite inputs.
pub fn blackbody_radiance(lambda_nm: f64, kelvin: f64) -> f64 {
    // Infinite λ or T would give 0/0 or ∞/∞: there is no emission to speak of at λ = ∞, and
    // T = ∞ is not a temperature.
    if !(lambda_nm > 0.0 && kelvin > 0.0 && lambda_nm.is_finite() && kelvin.is_finite()) {
        return 0.0;
    }
    let l = lambda_nm * 1e-9;
    let per_m = 2.0 * H * C * C / l.powi(5) / ((H * C / (l * KB * kelvin)).exp_m1());
    per_m * 1e-9
}

/// B(λ_peak, T) with λ_peak from Wien's displacement law [W sr⁻¹ m⁻² nm⁻¹].
pub fn blackbody_peak_radiance(kelvin: f64) -> f64 {
    blackbody_radiance(WIEN_B / kelvin * 1e9, kelvin)
}

/// B(λ, T) · `inv_peak`, i.e. Planck normalised to a maximum of 1.
pub(crate) fn blackbody_normalised(lambda_nm: f64, kelvin: f64, inv_peak: f64) -> f64 {
    blackbody_radiance(lambda_nm, kelvin) * inv_peak
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_is_the_maximum() {
        for t in [1000.0, 2700.0, 6500.0, 10000.0] {
            let peak = blackbody_peak_radiance(t);
            let lp = WIEN_B / t * 1e9;
            for d in [-1.0, -0.1, 0.1, 1.0] {
                assert!(blackbody_radiance(lp + d, t) < peak);
            }
        }
    }

    #[test]
    fn stefan_boltzmann_law() {
        // π ∫ B dλ = σ T⁴ (σ = 5.670374419e-8 W m⁻² K⁻⁴); integrate 10 nm … 1 mm by a
        // log-spaced trapezoid rule fine enough for 1e-6 relative.
        let t = 5000.0;
        let n = 200_000;
        let (a, b) = (10f64.ln(), 1e6f64.ln());
        let mut sum = 0.0;
        for i in 0..=n {
            let u = a + (b - a) * i as f64 / n as f64;
            let l = u.exp();
            let w = if i == 0 || i == n { 0.5 } else { 1.0 };
            sum += w * blackbody_radiance(l, t) * l;
        }
        sum *= (b - a) / n as f64;
        let want = 5.670_374_419e-8 * t.powi(4);
        assert!((std::f64::consts::PI * sum / want - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bad_input_is_zero() {
        assert_eq!(blackbody_radiance(-1.0, 5000.0), 0.0);
        assert_eq!(blackbody_radiance(500.0, 0.0), 0.0);
        assert_eq!(blackbody_radiance(f64::NAN, 5000.0), 0.0);
    }
}
