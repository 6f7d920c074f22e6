//! RGB colour spaces defined by primaries and a white point, with
//! XYZ↔RGB matrices derived from the chromaticities (SMPTE RP 177-1993 §3.3), not pasted.

use super::illuminant::named_illuminant;
use super::jakob_hanika::{RgbToSpectrumTable, SigmoidFitter};
use super::spd::Spectrum;
use glam::{DMat3, DVec3, Mat3, Vec3};
use std::sync::OnceLock;

/// An RGB colour space: three primaries and a white, all as CIE 1931 xy chromaticities,
/// plus the spectrum of the white illuminant (used for RGB illuminants and reflectance fits).
#[derive(Debug)]
pub struct ColorSpace {
    /// Canonical name (pbrt-v4 spelling).
    pub name: &'static str,
    /// xy of the red, green and blue primaries.
    pub primaries: [[f64; 2]; 3],
    /// xy of the white point.
    pub white: [f64; 2],
    /// Spectrum of the white illuminant, normalised to luminance Y = 1.
    pub illuminant: Spectrum,
    /// Linear RGB → XYZ (columns are the primaries' XYZ, scaled so RGB (1,1,1) is the white
    /// with Y = 1).
    pub rgb_to_xyz_matrix: Mat3,
    /// XYZ → linear RGB, the inverse of `rgb_to_xyz_matrix`.
    pub xyz_to_rgb_matrix: Mat3,
    /// `rgb_to_xyz_matrix` in double precision.
    pub rgb_to_xyz_f64: DMat3,
    /// `xyz_to_rgb_matrix` in double precision.
    pub xyz_to_rgb_f64: DMat3,
    fitter: OnceLock<SigmoidFitter>,
    table: OnceLock<RgbToSpectrumTable>,
}

/// XYZ with Y = 1 of chromaticity (x, y).
fn xy_to_xyz(xy: [f64; 2]) -> DVec3 {
    DVec3::new(xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1])
}

/// RGB→XYZ from chromaticities: P = [XYZ(r) XYZ(g) XYZ(b)], S = P⁻¹ XYZ(w), M = P diag(S).
pub fn rgb_to_xyz_from_chromaticities(primaries: [[f64; 2]; 3], white: [f64; 2]) -> DMat3 {
    let p = DMat3::from_cols(xy_to_xyz(primaries[0]), xy_to_xyz(primaries[1]), xy_to_xyz(primaries[2]));
    let s = p.inverse() * xy_to_xyz(white);
    DMat3::from_cols(p.x_axis * s.x, p.y_axis * s.y, p.z_axis * s.z)
}

impl ColorSpace {
    /// A colour space from primaries, white point and white illuminant.
    pub fn new(name: &'static str, primaries: [[f64; 2]; 3], white: [f64; 2], illuminant: Spectrum) -> Self {
        let m = rgb_to_xyz_from_chromaticities(primaries, white);
        let inv = m.inverse();
        Self {
            name,
            primaries,
            white,
            illuminant,
            rgb_to_xyz_matrix: m.as_mat3(),
            xyz_to_rgb_matrix: inv.as_mat3(),
            rgb_to_xyz_f64: m,
            xyz_to_rgb_f64: inv,
            fitter: OnceLock::new(),
            table: OnceLock::new(),
        }
    }

    /// Linear RGB → XYZ.
    pub fn rgb_to_xyz(&self, rgb: Vec3) -> Vec3 {
        self.rgb_to_xyz_matrix * rgb
    }

    /// XYZ → linear RGB.
    pub fn xyz_to_rgb(&self, xyz: Vec3) -> Vec3 {
        self.xyz_to_rgb_matrix * xyz
    }

    /// The space called `name` (case-insensitive): "srgb", "rec2020", "aces2065-1", "acescg",
    /// "dci-p3" / "display-p3". As in pbrt-v4, "dci-p3" is the P3 primaries with a D65 white
    /// (i.e. Display P3), not the theatrical DCI white.
    pub fn by_name(name: &str) -> Option<&'static ColorSpace> {
        const SPELLINGS: [&[&str]; 5] = [
            &["srgb", "rec709", "rec.709", "bt709"],
            &["rec2020", "rec.2020", "bt2020"],
            &["aces2065-1", "aces", "ap0"],
            &["acescg", "ap1"],
            &["dci-p3", "display-p3", "p3", "displayp3"],
        ];
        let idx = SPELLINGS.iter().position(|s| s.iter().any(|s| s.eq_ignore_ascii_case(name)))?;
        Some(&all()[idx])
    }

    /// Linear sRGB (Rec. 709 primaries, D65).
    pub fn srgb() -> &'static ColorSpace {
        &all()[0]
    }

    /// The names [`Self::by_name`] knows (canonical spellings).
    pub fn names() -> [&'static str; 5] {
        ["srgb", "rec2020", "aces2065-1", "acescg", "dci-p3"]
    }

    /// The Gauss–Newton fitter of sigmoid polynomials for this space (built on first use).
    pub(crate) fn fitter(&self) -> &SigmoidFitter {
        self.fitter.get_or_init(|| SigmoidFitter::new(&self.illuminant, self.xyz_to_rgb_f64))
    }

    /// The Jakob–Hanika coefficient table for this space (built on first use, see
    /// docs/colour.md for the resolution and why it is not checked in).
    pub fn rgb_to_spectrum_table(&self) -> &RgbToSpectrumTable {
        self.table.get_or_init(|| RgbToSpectrumTable::build(self.fitter(), RgbToSpectrumTable::DEFAULT_RES))
    }
}

fn all() -> &'static [ColorSpace; 5] {
    static SPACES: OnceLock<[ColorSpace; 5]> = OnceLock::new();
    SPACES.get_or_init(|| {
        let d65 = || named_illuminant("stdillum-D65").expect("D65 is built in");
        let aces = || named_illuminant("illum-acesD60").expect("ACES white is built in");
        const D65: [f64; 2] = [0.3127, 0.3290];
        const ACES_WHITE: [f64; 2] = [0.32168, 0.33767];
        [
            // ITU-R BT.709-6 / IEC 61966-2-1.
            ColorSpace::new("srgb", [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], D65, d65()),
            // ITU-R BT.2020-2.
            ColorSpace::new("rec2020", [[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]], D65, d65()),
            // SMPTE ST 2065-1 (AP0).
            ColorSpace::new("aces2065-1", [[0.7347, 0.2653], [0.0, 1.0], [0.0001, -0.0770]], ACES_WHITE, aces()),
            // Academy S-2014-004 (AP1).
            ColorSpace::new("acescg", [[0.713, 0.293], [0.165, 0.830], [0.128, 0.044]], ACES_WHITE, aces()),
            // SMPTE EG 432-1 P3 primaries with D65 white (Display P3; pbrt-v4 "dci-p3").
            ColorSpace::new("dci-p3", [[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]], D65, d65()),
        ]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_matrix(m: DMat3, published: [[f64; 3]; 3], tol: f64, what: &str) {
        for (r, row) in published.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                let got = m.col(c)[r];
                assert!((got - v).abs() <= tol, "{what}[{r}][{c}] = {got}, published {v}");
            }
        }
    }

    #[test]
    fn derived_matrices_match_published() {
        // IEC 61966-2-1 (4 decimals).
        let srgb = ColorSpace::srgb();
        let m_srgb = [[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]];
        assert_matrix(srgb.rgb_to_xyz_f64, m_srgb, 5e-5, "sRGB");
        // The published inverse is the inverse of the 4-decimal forward matrix, so it
        // carries that rounding amplified by the inverse's norm (≈ 4): allow 4e-4.
        let inv = [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]];
        assert_matrix(srgb.xyz_to_rgb_f64, inv, 4e-4, "sRGB⁻¹");
        // ITU-R BT.2087-0 (6 decimals).
        let m2020 = [[0.636958, 0.144617, 0.168881], [0.262700, 0.677998, 0.059302], [0.000000, 0.028073, 1.060985]];
        assert_matrix(ColorSpace::by_name("rec2020").unwrap().rgb_to_xyz_f64, m2020, 5e-7, "2020");
        // SMPTE ST 2065-1 (10 decimals).
        let ap0 =
            [[0.9525523959, 0.0, 0.0000936786], [0.3439664498, 0.7281660966, -0.0721325464], [0.0, 0.0, 1.0088251844]];
        assert_matrix(ColorSpace::by_name("ACES2065-1").unwrap().rgb_to_xyz_f64, ap0, 5e-10, "AP0");
        // Academy S-2014-004 (10 decimals).
        let ap1 = [
            [0.6624541811, 0.1340042065, 0.1561876870],
            [0.2722287168, 0.6740817658, 0.0536895174],
            [-0.0055746495, 0.0040607335, 1.0103391003],
        ];
        assert_matrix(ColorSpace::by_name("acescg").unwrap().rgb_to_xyz_f64, ap1, 5e-10, "AP1");
        // Display P3 (Apple / colour-science, 7 decimals).
        let p3 = [[0.4865709, 0.2656677, 0.1982173], [0.2289746, 0.6917385, 0.0792869], [0.0, 0.0451134, 1.0439444]];
        assert_matrix(ColorSpace::by_name("display-p3").unwrap().rgb_to_xyz_f64, p3, 5e-8, "P3");
    }

    #[test]
    fn white_maps_to_white_and_matrices_invert() {
        for n in ColorSpace::names() {
            let cs = ColorSpace::by_name(n).unwrap();
            let w = cs.rgb_to_xyz_f64 * DVec3::ONE;
            let want = xy_to_xyz(cs.white);
            assert!((w - want).abs().max_element() < 1e-12, "{n}");
            let id = cs.rgb_to_xyz_f64 * cs.xyz_to_rgb_f64;
            assert!((id - DMat3::IDENTITY).abs_diff_eq(DMat3::ZERO, 1e-12), "{n}");
            let v = Vec3::new(0.2, 0.5, 0.9);
            assert!((cs.xyz_to_rgb(cs.rgb_to_xyz(v)) - v).abs().max_element() < 1e-6);
        }
        assert!(ColorSpace::by_name("prophoto").is_none());
        assert_eq!(ColorSpace::by_name("DCI-P3").unwrap().name, "dci-p3");
    }
}
