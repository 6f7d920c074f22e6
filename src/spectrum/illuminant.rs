//! CIE standard illuminants (D65, D50, A, E, F1–F12) and the CIE daylight series, normalised
//! as pbrt-v4 normalises its named spectra: luminance Y = ∫ S ȳ / ∫ ȳ = 1.

use super::data::{DAYLIGHT_S0, DAYLIGHT_S1, DAYLIGHT_S2, ILLUM_A, ILLUM_D50, ILLUM_D65};
use super::data::{ILLUM_F11, ILLUM_F2};
use super::spd::Spectrum;

/// Names accepted by [`Spectrum::named`] (pbrt-v4 spellings).
pub const NAMED_ILLUMINANTS: [&str; 17] = [
    "stdillum-D65",
    "stdillum-D50",
    "stdillum-A",
    "stdillum-E",
    "stdillum-F1",
    "stdillum-F2",
    "stdillum-F3",
    "stdillum-F4",
    "stdillum-F5",
    "stdillum-F6",
    "stdillum-F7",
    "stdillum-F8",
    "stdillum-F9",
    "stdillum-F10",
    "stdillum-F11",
    "stdillum-F12",
    "illum-acesD60",
];

/// Tabulated (start [nm], spacing [nm], values) → piecewise-linear spectrum with Y = 1.
pub(super) fn from_table(t: &(f64, f64, &[f64])) -> Spectrum {
    let (start, step, values) = *t;
    let lambdas = (0..values.len()).map(|i| start + step * i as f64).collect();
    let s =
        Spectrum::piecewise_linear_f64(lambdas, values.to_vec()).expect("built-in illuminant tables are well formed");
    normalise_luminance(s)
}

/// Scales `s` so that its luminance Y (the ∫ȳ normalisation (see `spectrum::cie`)) is 1.
pub fn normalise_luminance(s: Spectrum) -> Spectrum {
    let y = s.to_xyz_f64().y;
    if y > 0.0 {
        s.scaled(1.0 / y)
    } else {
        s
    }
}

/// CIE daylight illuminant at correlated colour temperature `cct` [K] (CIE 015:2018 §3.1:
/// chromaticity x_D(T), y_D = −3x_D² + 2.87x_D − 0.275, S = S₀ + M₁S₁ + M₂S₂), normalised
/// to Y = 1. `None` outside the defined range 4000–25000 K.
pub fn daylight(cct: f64) -> Option<Spectrum> {
    if !(4000.0..=25000.0).contains(&cct) {
        return None;
    }
    let t = cct;
    let x = if t <= 7000.0 {
        -4.6070e9 / t.powi(3) + 2.9678e6 / t.powi(2) + 0.09911e3 / t + 0.244063
    } else {
        -2.0064e9 / t.powi(3) + 1.9018e6 / t.powi(2) + 0.24748e3 / t + 0.237040
    };
    let y = -3.0 * x * x + 2.87 * x - 0.275;
    let m = 0.0241 + 0.2562 * x - 0.7341 * y;
    let m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m;
    let m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
    let lambdas = (0..DAYLIGHT_S0.len()).map(|i| 300.0 + 5.0 * i as f64).collect();
    let values = (0..DAYLIGHT_S0.len()).map(|i| DAYLIGHT_S0[i] + m1 * DAYLIGHT_S1[i] + m2 * DAYLIGHT_S2[i]).collect();
    Spectrum::piecewise_linear_f64(lambdas, values).map(normalise_luminance)
}

/// The illuminant called `name` computed or tabulated here (D65, D50, A, E, F2, F11, ACES
/// D60; pbrt-v4's other fluorescents are `pbrt_spectra`'s).
pub fn named_illuminant(name: &str) -> Option<Spectrum> {
    Some(match name {
        "stdillum-D65" => from_table(&ILLUM_D65),
        "stdillum-D50" => from_table(&ILLUM_D50),
        "stdillum-A" => from_table(&ILLUM_A),
        "stdillum-E" => Spectrum::constant(1.0),
        "stdillum-F2" => from_table(&ILLUM_F2),
        "stdillum-F11" => from_table(&ILLUM_F11),
        // ACES white: CIE daylight at 6000 K on the pre-1968 temperature scale
        // (c₂ = 1.4380e-2 → 1.4388e-2), Academy TB-2018-001.
        "illum-acesD60" => daylight(6000.0 * 1.4388 / 1.4380)?,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_named_have_unit_luminance() {
        for n in NAMED_ILLUMINANTS {
            let y = Spectrum::named(n).unwrap().to_xyz_f64().y;
            assert!((y - 1.0).abs() < 1e-12, "{n}: {y}");
        }
        assert!(Spectrum::named("stdillum-D66").is_none());
    }

    fn xy(s: &Spectrum) -> (f64, f64) {
        let v = s.to_xyz_f64();
        let sum = v.x + v.y + v.z;
        (v.x / sum, v.y / sum)
    }

    #[test]
    fn chromaticities_match_cie_015() {
        // CIE 015:2018 Table 1/Table 8 (2° observer), four decimals as published.
        let cases = [
            ("stdillum-D65", 0.3127, 0.3290),
            ("stdillum-D50", 0.3457, 0.3585),
            ("stdillum-A", 0.4476, 0.4074),
            ("stdillum-E", 0.3333, 0.3333),
            ("illum-acesD60", 0.32168, 0.33767),
        ];
        for (n, x, y) in cases {
            let (gx, gy) = xy(&Spectrum::named(n).unwrap());
            assert!((gx - x).abs() < 1.5e-4 && (gy - y).abs() < 1.5e-4, "{n}: {gx} {gy}");
        }
        // The spiky fluorescents depend on how the 5 nm table is interpolated, so compare with
        // colour-science 0.4.7 on the same definition (linear interpolation to 1 nm, zero
        // outside, `sd_to_XYZ_integration`); the rule there is a 1 nm rectangle sum, ours is
        // exact, which differs by < 3e-5 in xy.
        for (n, x, y) in [("stdillum-F2", 0.372_084_89, 0.375_289_60), ("stdillum-F11", 0.380_517_96, 0.377_125_87)] {
            let (gx, gy) = xy(&Spectrum::named(n).unwrap());
            assert!((gx - x).abs() < 3e-5 && (gy - y).abs() < 3e-5, "{n}: {gx} {gy}");
        }
    }

    #[test]
    fn daylight_at_6504_k_is_d65() {
        let d = daylight(6500.0 * 1.4388 / 1.4380).unwrap();
        let d65 = Spectrum::named("stdillum-D65").unwrap();
        let (a, b) = (xy(&d), xy(&d65));
        assert!((a.0 - b.0).abs() < 1e-4 && (a.1 - b.1).abs() < 1e-4, "{a:?} {b:?}");
        assert!(daylight(3000.0).is_none());
    }
}
