//! pbrt-v4's named spectra from pbrt-v4's own tables (`data::pbrt_v4`): the CIE illuminants,
//! metals' η and k, glasses' η, and the camera sensitivities `<sensor>_r`, `_g`, `_b`.
//! Illuminants are normalised to luminance Y = 1 as pbrt-v4 normalises them; the others are
//! the tabulated values, piecewise linear, zero outside the table (as pbrt-v4's
//! `PiecewiseLinearSpectrum`).

use super::data::{
    AG_ETA, AG_K, AL_ETA, AL_K, AU_ETA, AU_K, CAMERAS, CUZN_ETA, CUZN_K, CU_ETA, CU_K, GLASS_BAF10, GLASS_BK7,
    GLASS_F10, GLASS_F11, GLASS_F5, GLASS_FK51A, GLASS_LASF9, ILLUM_F1, ILLUM_F10, ILLUM_F12, ILLUM_F3, ILLUM_F4,
    ILLUM_F5, ILLUM_F6, ILLUM_F7, ILLUM_F8, ILLUM_F9, METAL_LAMBDA, MGO_ETA, MGO_K, TIO2_ETA, TIO2_K,
};
use super::illuminant::{from_table, named_illuminant};
use super::spd::Spectrum;

/// First wavelength [nm] of the camera tables.
pub const CAMERA_LAMBDA_START: f32 = 380.0;
/// Spacing [nm] of the camera tables.
pub const CAMERA_LAMBDA_STEP: f32 = 10.0;

/// A camera's r, g, b spectral sensitivities, tabulated from [`CAMERA_LAMBDA_START`] every
/// [`CAMERA_LAMBDA_STEP`] nm.
pub type CameraCurves = [[f32; 35]; 3];

/// A camera's sensitivities (r, g, b) at `lambda` [nm]: linear between the tabulated values,
/// zero outside the table.
#[inline]
pub fn camera_rgb_bar(curves: &CameraCurves, lambda: f32) -> glam::Vec3 {
    let x = (lambda - CAMERA_LAMBDA_START) / CAMERA_LAMBDA_STEP;
    let last = (curves[0].len() - 1) as f32;
    if !(x >= 0.0 && x <= last) {
        return glam::Vec3::ZERO;
    }
    let i = (x as usize).min(curves[0].len() - 2);
    let t = x - i as f32;
    let at = |c: &[f32; 35]| c[i] + t * (c[i + 1] - c[i]);
    glam::Vec3::new(at(&curves[0]), at(&curves[1]), at(&curves[2]))
}

/// The (r, g, b) spectral sensitivities of pbrt-v4's camera `sensor` (e.g. "canon_eos_5d"),
/// 380–720 nm at 10 nm, each peaking near 1.
pub fn camera_sensitivities(sensor: &str) -> Option<&'static CameraCurves> {
    CAMERAS.iter().find(|(n, _)| *n == sensor).map(|(_, c)| c)
}

/// The names of pbrt-v4's camera sensors.
pub fn camera_names() -> impl Iterator<Item = &'static str> {
    CAMERAS.iter().map(|(n, _)| *n)
}

/// True for a name pbrt-v4 gives a built-in spectrum: [`super::NAMED_SPECTRA`] and the camera
/// channels `<sensor>_r`, `_g`, `_b`.
pub fn is_named_spectrum(name: &str) -> bool {
    super::NAMED_SPECTRA.contains(&name) || camera_channel(name).is_some()
}

/// (sensor, channel 0–2) of a camera channel's name.
fn camera_channel(name: &str) -> Option<(&'static CameraCurves, usize)> {
    let (sensor, channel) = name.rsplit_once('_')?;
    let c = ["r", "g", "b"].iter().position(|&x| x == channel)?;
    Some((camera_sensitivities(sensor)?, c))
}

fn pairs(t: &[(f64, f64)]) -> Option<Spectrum> {
    Spectrum::piecewise_linear_f64(t.iter().map(|p| p.0).collect(), t.iter().map(|p| p.1).collect())
}

fn metal(values: &[f64; 56]) -> Option<Spectrum> {
    Spectrum::piecewise_linear_f64(METAL_LAMBDA.to_vec(), values.to_vec())
}

/// A table of evenly spaced values: (first [nm], spacing [nm], values).
fn spaced(t: &(f64, f64, &[f64])) -> Option<Spectrum> {
    let (start, step, values) = *t;
    Spectrum::piecewise_linear_f64((0..values.len()).map(|i| start + step * i as f64).collect(), values.to_vec())
}

impl Spectrum {
    /// A spectrum pbrt-v4 names: the CIE illuminants listed in
    /// [`super::NAMED_ILLUMINANTS`] (Y = 1), and pbrt-v4's tabulated metals, glasses and
    /// camera sensitivities.
    pub fn named(name: &str) -> Option<Spectrum> {
        named_illuminant(name).or_else(|| pbrt_named_spectrum(name))
    }
}

/// The spectrum pbrt-v4 calls `name`, from pbrt-v4's tables; `None` for a name it does not
/// tabulate here (the CIE A/D50/D65 illuminants and ACES D60 are [`Spectrum::named`]'s).
pub fn pbrt_named_spectrum(name: &str) -> Option<Spectrum> {
    if let Some((curves, c)) = camera_channel(name) {
        let l = (0..35).map(|i| (CAMERA_LAMBDA_START + CAMERA_LAMBDA_STEP * i as f32) as f64).collect();
        return Spectrum::piecewise_linear_f64(l, curves[c].iter().map(|&v| v as f64).collect());
    }
    let illuminant = |t| Some(from_table(t));
    match name {
        "stdillum-F1" => illuminant(&ILLUM_F1),
        "stdillum-F3" => illuminant(&ILLUM_F3),
        "stdillum-F4" => illuminant(&ILLUM_F4),
        "stdillum-F5" => illuminant(&ILLUM_F5),
        "stdillum-F6" => illuminant(&ILLUM_F6),
        "stdillum-F7" => illuminant(&ILLUM_F7),
        "stdillum-F8" => illuminant(&ILLUM_F8),
        "stdillum-F9" => illuminant(&ILLUM_F9),
        "stdillum-F10" => illuminant(&ILLUM_F10),
        "stdillum-F12" => illuminant(&ILLUM_F12),
        "metal-Ag-eta" => metal(&AG_ETA),
        "metal-Ag-k" => metal(&AG_K),
        "metal-Al-eta" => metal(&AL_ETA),
        "metal-Al-k" => metal(&AL_K),
        "metal-Au-eta" => metal(&AU_ETA),
        "metal-Au-k" => metal(&AU_K),
        "metal-Cu-eta" => metal(&CU_ETA),
        "metal-Cu-k" => metal(&CU_K),
        "metal-CuZn-eta" => spaced(&CUZN_ETA),
        "metal-CuZn-k" => spaced(&CUZN_K),
        "metal-MgO-eta" => pairs(MGO_ETA),
        "metal-MgO-k" => pairs(MGO_K),
        "metal-TiO2-eta" => pairs(TIO2_ETA),
        "metal-TiO2-k" => pairs(TIO2_K),
        "glass-BK7" => pairs(GLASS_BK7),
        "glass-BAF10" => pairs(GLASS_BAF10),
        "glass-FK51A" => pairs(GLASS_FK51A),
        "glass-LASF9" => pairs(GLASS_LASF9),
        "glass-F5" => pairs(GLASS_F5),
        "glass-F10" => pairs(GLASS_F10),
        "glass-F11" => pairs(GLASS_F11),
        _ => None,
    }
}

/// The reflectances of the 24 ColorChecker patches (BabelColor's measurements, as pbrt-v4
/// trains its camera sensors on them), 380–730 nm, zero outside, in chart order.
pub fn colorchecker_reflectances() -> Vec<Spectrum> {
    let l: Vec<f64> = (0..36).map(|i| 380.0 + 10.0 * i as f64).collect();
    super::data::COLORCHECKER.iter().filter_map(|r| Spectrum::piecewise_linear_f64(l.clone(), r.to_vec())).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(n: &str) -> Spectrum {
        Spectrum::named(n).unwrap_or_else(|| panic!("{n}"))
    }

    #[test]
    fn glasses_match_schott_catalogue_indices_at_the_helium_d_line() {
        // n_d (587.56 nm) from the Schott optical glass catalogue: N-BK7 1.51680, N-BAF10
        // 1.67003, N-FK51A 1.48656, N-LASF9 1.85025, N-SF5 1.67271, N-SF10 1.72828, N-SF11
        // 1.78472. The tables step 21–22 nm; linear interpolation there is within 2e-4.
        let cases = [
            ("glass-BK7", 1.51680),
            ("glass-BAF10", 1.67003),
            ("glass-FK51A", 1.48656),
            ("glass-LASF9", 1.85025),
            ("glass-F5", 1.67271),
            ("glass-F10", 1.72828),
            ("glass-F11", 1.78472),
        ];
        for (n, nd) in cases {
            let got = named(n).eval_f64(587.56);
            assert!((got - nd).abs() < 2e-4, "{n}: {got} vs {nd}");
        }
    }

    /// Normal-incidence reflectance of a metal of index η + ik.
    fn reflectance(metal: &str, l: f64) -> f64 {
        let (n, k) = (named(&format!("metal-{metal}-eta")).eval_f64(l), named(&format!("metal-{metal}-k")).eval_f64(l));
        ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k)
    }

    #[test]
    fn metals_are_pbrt_v4s_tables_with_their_known_optical_constants() {
        // Silver at 500 nm: n ≈ 0.13, k ≈ 2.9 (Palik's handbook, Lynch & Hunter); Johnson &
        // Christy's n ≈ 0.05 is prism's own "prism-metal-Ag-eta".
        let (n, k) = (named("metal-Ag-eta").eval_f64(500.0), named("metal-Ag-k").eval_f64(500.0));
        assert!((0.12..0.15).contains(&n) && (2.8..3.0).contains(&k), "Ag: {n} {k}");
        let jc = crate::bsdf::named_spectra::named_spectrum("prism-metal-Ag-eta").unwrap().eval_f64(500.0);
        assert!(jc < 0.07, "{jc}");
        // Aluminium at 550 nm: n ≈ 0.96, k ≈ 6.69 (Rakić 1995).
        let (n, k) = (named("metal-Al-eta").eval_f64(550.0), named("metal-Al-k").eval_f64(550.0));
        assert!((n - 0.96).abs() < 0.05 && (k - 6.69).abs() < 0.1, "Al: {n} {k}");
        // Gold and copper reflect red far better than blue (their colour); silver and
        // aluminium are bright throughout.
        for m in ["Au", "Cu"] {
            let (blue, red) = (reflectance(m, 450.0), reflectance(m, 650.0));
            assert!(red > 0.9 && blue < 0.65, "{m}: {blue} {red}");
        }
        for m in ["Ag", "Al"] {
            assert!(reflectance(m, 450.0) > 0.9 && reflectance(m, 650.0) > 0.9, "{m}");
        }
        // MgO and TiO2 are dielectrics: n ≈ 1.74 (MgO, 589 nm) and ≈ 2.9 (rutile, 600 nm),
        // k = 0 in the visible.
        assert!((named("metal-MgO-eta").eval_f64(589.0) - 1.737).abs() < 2e-3);
        assert!((named("metal-TiO2-eta").eval_f64(600.0) - 2.9).abs() < 0.05);
        assert!(named("metal-MgO-k").eval_f64(500.0) < 1e-5 && named("metal-TiO2-k").eval_f64(500.0) == 0.0);
    }

    #[test]
    fn brass_is_pbrt_v4s_table_and_reflects_as_a_yellow_metal() {
        // pbrt-v4's CuZn table at 550 nm (its 27th sample) and halfway to 560 nm.
        let (eta, k) = (named("metal-CuZn-eta"), named("metal-CuZn-k"));
        assert!((eta.eval_f64(550.0) - 0.527).abs() < 1e-6 && (k.eval_f64(550.0) - 2.765).abs() < 1e-6);
        assert!((eta.eval_f64(555.0) - 0.516).abs() < 1e-6 && (k.eval_f64(555.0) - 2.8125).abs() < 1e-6);
        assert!(eta.eval_f64(289.0) == 0.0 && k.eval_f64(891.0) == 0.0);
        // Brass reflects red like copper and gold (R > 0.85 at 650 nm) and blue poorly; it
        // reflects green better than copper (zinc moves the absorption edge towards the blue:
        // yellow, not red-orange).
        let (blue, green, red) = (reflectance("CuZn", 450.0), reflectance("CuZn", 550.0), reflectance("CuZn", 650.0));
        assert!(red > 0.85 && (0.35..0.6).contains(&blue), "{blue} {red}");
        assert!(green > reflectance("Cu", 550.0) + 0.1, "{green}");
    }

    fn xy(s: &Spectrum) -> (f64, f64) {
        let v = s.to_xyz_f64();
        (v.x / (v.x + v.y + v.z), v.y / (v.x + v.y + v.z))
    }

    #[test]
    fn fluorescent_illuminants_have_cie_chromaticities_and_mercury_lines() {
        // CIE 015:2018 Table 10 (2° observer), four decimals; the published values sum the
        // 5 nm table, ours integrate its linear interpolation: they differ by up to 1e-3 where
        // lines are narrow.
        let cases = [
            ("stdillum-F1", 0.3131, 0.3371),
            ("stdillum-F3", 0.4091, 0.3941),
            ("stdillum-F4", 0.4402, 0.4031),
            ("stdillum-F5", 0.3138, 0.3452),
            ("stdillum-F6", 0.3779, 0.3882),
            ("stdillum-F7", 0.3129, 0.3292),
            ("stdillum-F8", 0.3458, 0.3586),
            ("stdillum-F9", 0.3741, 0.3727),
            ("stdillum-F10", 0.3458, 0.3588),
            ("stdillum-F12", 0.4370, 0.4042),
        ];
        for (n, x, y) in cases {
            let (gx, gy) = xy(&named(n));
            assert!((gx - x).abs() < 1e-3 && (gy - y).abs() < 1e-3, "{n}: {gx} {gy} vs {x} {y}");
            assert!((named(n).to_xyz_f64().y - 1.0).abs() < 1e-12, "{n}");
        }
        // Every fluorescent lamp shows mercury's 404.7 and 435.8 nm lines; the tri-band lamps
        // F10–F12 peak where their phosphors emit: 435 (Hg), 545 (Tb³⁺), 610 nm (Eu³⁺).
        let peak = |s: &Spectrum, lo: f64, hi: f64| {
            (0..=((hi - lo) as usize)).map(|i| lo + i as f64).max_by(|a, b| s.eval_f64(*a).total_cmp(&s.eval_f64(*b)))
        };
        for i in 1..=12 {
            let s = named(&format!("stdillum-F{i}"));
            assert_eq!(peak(&s, 420.0, 450.0), Some(435.0), "F{i}");
            assert_eq!(peak(&s, 395.0, 415.0), Some(405.0), "F{i}");
        }
        for i in 10..=12 {
            let s = named(&format!("stdillum-F{i}"));
            assert_eq!(peak(&s, 530.0, 560.0), Some(545.0), "F{i}");
            assert_eq!(peak(&s, 595.0, 625.0), Some(610.0), "F{i}");
        }
    }

    #[test]
    fn aces_d60_is_pbrt_v4s_table() {
        // pbrt-v4's ACES_Illum_D60 (relative to 100 at 560 nm) at a few wavelengths.
        let d60 = named("illum-acesD60");
        let at = |l: f64| d60.eval_f64(l) / d60.eval_f64(560.0) * 100.0;
        for (l, v) in [(300.0, 0.02928), (445.0, 101.72045), (600.0, 91.948), (700.0, 76.4464), (830.0, 63.7793)] {
            assert!((at(l) - v).abs() < 2e-3 * v.max(1.0), "{l}: {} vs {v}", at(l));
        }
    }

    #[test]
    fn every_camera_has_named_channels_peaking_where_camera_filters_do() {
        assert_eq!(camera_names().count(), 17);
        for cam in camera_names() {
            let peak = |c: &str| {
                let s = named(&format!("{cam}_{c}"));
                (380..=720).map(f64::from).max_by(|a, b| s.eval_f64(*a).total_cmp(&s.eval_f64(*b))).unwrap()
            };
            // Bayer filters: blue peaks in 430–480 nm, green in 500–560, red in 580–620.
            let (r, g, b) = (peak("r"), peak("g"), peak("b"));
            assert!(
                (580.0..=620.0).contains(&r) && (500.0..=560.0).contains(&g) && (430.0..=480.0).contains(&b),
                "{cam}: {r} {g} {b}"
            );
            assert!(is_named_spectrum(&format!("{cam}_g")));
        }
        assert!(!is_named_spectrum("canon_eos_5d_x") && !is_named_spectrum("nikon_d1_r"));
    }
}
