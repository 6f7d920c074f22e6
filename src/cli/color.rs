//! `prism color ...`: command-line checks of the colour pipeline. Each subcommand
//! is a function returning its text so that tests can call it; `run` prints.

use crate::spectrum::projection::{project, Basis, Fit};
use crate::spectrum::roundtrip::reflectance_rgb;
use crate::spectrum::smits::{smits_spectrum, SmitsKind};
use crate::spectrum::{ColorSpace, RgbKind, Spectrum};
use anyhow::{bail, Result};
use glam::DVec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// RGB → spectrum method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Smits 1999 basis spectra (B. Smits, JGT 4(4)).
    Smits,
    /// Jakob & Hanika 2019 sigmoid polynomials (the default).
    Jakob,
}

/// What the RGB triplet means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Kind {
    /// Reflectance, each component in [0, 1].
    Albedo,
    /// Any non-negative quantity.
    Unbounded,
    /// Emission: scaled by the colour space's white illuminant.
    Illuminant,
}

/// Basis for `project`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BasisArg {
    /// Boxes.
    Constant,
    /// Hats.
    Linear,
}

/// Fit for `project`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FitArg {
    /// L² optimum (solve A β = b).
    Exact,
    /// Box averages of F around each node (no linear solve).
    Average,
}

/// `prism color` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum ColorCommand {
    /// Print X Y Z of an SPD file (X = ∫ S x̄ / ∫ ȳ, exact integration).
    Xyz {
        /// Two-column SPD file: wavelength [nm], value; `#` comments.
        #[arg(long)]
        spd: PathBuf,
    },
    /// Print the spectrum (360–830 nm, 5 nm) for an RGB triplet, and its round-trip RGB.
    Rgb2spec {
        /// Upsampling method.
        #[arg(long, value_enum, default_value = "jakob")]
        method: Method,
        /// Colour space: srgb, rec2020, aces2065-1, acescg, dci-p3.
        #[arg(long, default_value = "srgb")]
        space: String,
        /// How to read the triplet.
        #[arg(long, value_enum, default_value = "albedo")]
        kind: Kind,
        /// Linear R G B.
        #[arg(num_args = 3, value_names = ["R", "G", "B"], allow_negative_numbers = true)]
        rgb: Vec<f32>,
    },
    /// Project an SPD onto N box or hat functions over 360–830 nm; print the coefficients
    /// and the L² error.
    Project {
        /// Basis functions.
        #[arg(long, value_enum)]
        basis: BasisArg,
        /// How to find the coefficients.
        #[arg(long, value_enum, default_value = "exact")]
        fit: FitArg,
        /// Number of basis functions.
        #[arg(long)]
        bins: usize,
        /// Two-column SPD file.
        #[arg(long)]
        spd: PathBuf,
    },
    /// Print docs/colour.md (prose and the tables, recomputed).
    Report,
}

/// Runs a subcommand, printing its output to stdout.
pub fn run(cmd: ColorCommand) -> Result<()> {
    let text = match cmd {
        ColorCommand::Xyz { spd } => xyz_text(&spd)?,
        ColorCommand::Rgb2spec { method, space, kind, rgb } => rgb2spec_text(method, &space, kind, &rgb)?,
        ColorCommand::Project { basis, fit, bins, spd } => project_text(basis, fit, bins, &spd)?,
        ColorCommand::Report => super::color_report::report_markdown(),
    };
    super::print_stdout(&text)
}

fn load_spd(path: &Path) -> Result<Spectrum> {
    Ok(Spectrum::from_spd_file(path)?)
}

/// `prism color xyz`: "X Y Z" of the SPD file, in the ∫ȳ normalisation (see `spectrum::cie`).
pub fn xyz_text(spd: &Path) -> Result<String> {
    let xyz = load_spd(spd)?.to_xyz_f64();
    Ok(format!("{:.9} {:.9} {:.9}\n", xyz.x, xyz.y, xyz.z))
}

/// `prism color rgb2spec`: the spectrum at 360, 365, …, 830 nm and the round-trip RGB.
pub fn rgb2spec_text(method: Method, space: &str, kind: Kind, rgb: &[f32]) -> Result<String> {
    let Some(cs) = ColorSpace::by_name(space) else {
        bail!("unknown colour space '{space}' (known: {})", ColorSpace::names().join(", "));
    };
    let [r, g, b] = rgb else {
        bail!("expected 3 values R G B, got {}", rgb.len());
    };
    let rgb = [*r, *g, *b];
    for (name, v) in ["R", "G", "B"].iter().zip(rgb) {
        if !v.is_finite() {
            bail!("{name} = {v} is not a finite number");
        }
        if v < 0.0 {
            bail!("{name} = {v} is negative; RGB components must be ≥ 0");
        }
        if kind == Kind::Albedo && v > 1.0 {
            bail!("{name} = {v} exceeds 1, which an albedo cannot (use --kind unbounded)");
        }
    }
    let rgb64 = rgb.map(|v| v as f64);
    let s = match (method, kind) {
        (Method::Jakob, Kind::Albedo) => Spectrum::from_rgb(rgb, RgbKind::Albedo, cs),
        (Method::Jakob, Kind::Unbounded) => Spectrum::from_rgb(rgb, RgbKind::Unbounded, cs),
        (Method::Jakob, Kind::Illuminant) => Spectrum::from_rgb(rgb, RgbKind::Illuminant, cs),
        (Method::Smits, Kind::Albedo | Kind::Unbounded) => smits_spectrum(rgb64, SmitsKind::Reflectance, cs),
        (Method::Smits, Kind::Illuminant) => smits_spectrum(rgb64, SmitsKind::Illumination, cs),
    };
    // Reflectances are seen under the space's white; emitters are seen directly.
    let back = match kind {
        Kind::Illuminant => cs.xyz_to_rgb_f64 * s.to_xyz_f64(),
        _ => reflectance_rgb(&s, cs),
    };
    let err = (back - DVec3::from_array(rgb64)).abs().max_element();
    let mut out = String::new();
    let _ = writeln!(out, "# method {method:?}, space {}, kind {kind:?}, rgb {r} {g} {b}", cs.name);
    let _ = writeln!(out, "# lambda_nm value");
    for l in (360..=830).step_by(5) {
        let _ = writeln!(out, "{l} {:.6}", s.eval_f64(l as f64));
    }
    let _ = writeln!(out, "# round-trip rgb {:.6} {:.6} {:.6} (max abs error {:.2e})", back.x, back.y, back.z, err);
    Ok(out)
}

/// `prism color project`: coefficients and L² error of the projection.
pub fn project_text(basis: BasisArg, fit: FitArg, bins: usize, spd: &Path) -> Result<String> {
    let f = load_spd(spd)?;
    let basis = match basis {
        BasisArg::Constant => Basis::Constant,
        BasisArg::Linear => Basis::Linear,
    };
    let fit = match fit {
        FitArg::Exact => Fit::Exact,
        FitArg::Average => Fit::Average,
    };
    let p = project(&f, basis, fit, bins, (360.0, 830.0))?;
    let h = p.spacing();
    let mut out = String::new();
    let _ = writeln!(out, "# basis {basis:?}, fit {fit:?}, {bins} functions over 360-830 nm, spacing {h:.4} nm");
    let _ = writeln!(out, "# index centre_nm coefficient");
    for (i, c) in p.coeffs.iter().enumerate() {
        let centre = match basis {
            Basis::Constant => 360.0 + h * (i as f64 + 0.5),
            Basis::Linear => 360.0 + h * i as f64,
        };
        let _ = writeln!(out, "{i} {centre:.4} {c:.9}");
    }
    let _ = writeln!(out, "# L2 error {:.6e} (relative {:.6e})", p.l2_error, p.relative_error);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::{Cli, Command};
    use clap::Parser;

    /// A file of `text` in the temporary directory (the caller removes it).
    fn write_tmp(name: &str, text: &str) -> PathBuf {
        let p = std::env::temp_dir().join(format!("prism-color-{}-{name}", std::process::id()));
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn clap_parses_the_issue_lines() {
        let cli = Cli::try_parse_from([
            "prism",
            "color",
            "rgb2spec",
            "--method",
            "smits",
            "--space",
            "srgb",
            "--kind",
            "illuminant",
            "0.6",
            "0.2",
            "0.5",
        ])
        .unwrap();
        let Command::Color(ColorCommand::Rgb2spec { method, rgb, kind, .. }) = cli.command else {
            panic!("wrong subcommand")
        };
        assert_eq!((method, kind, rgb), (Method::Smits, Kind::Illuminant, vec![0.6, 0.2, 0.5]));
        let cli = Cli::try_parse_from([
            "prism", "color", "project", "--basis", "linear", "--fit", "average", "--bins", "12", "--spd", "a.spd",
        ])
        .unwrap();
        assert!(matches!(cli.command, Command::Color(ColorCommand::Project { bins: 12, .. })));
        assert!(Cli::try_parse_from(["prism", "color", "rgb2spec", "0.1", "0.2"]).is_err());
        assert!(Cli::try_parse_from(["prism", "color", "xyz"]).is_err());
    }

    #[test]
    fn xyz_of_a_file() {
        // Flat 1 over 300–900 nm covers the CMFs: Y = 1 exactly.
        let p = write_tmp("flat.spd", "# flat\n300 1\n900 1\n");
        let t = xyz_text(&p).unwrap();
        let v: Vec<f64> = t.split_whitespace().map(|x| x.parse().unwrap()).collect();
        assert!((v[1] - 1.0).abs() < 1e-9, "{t}");
        let bad = write_tmp("bad.spd", "400 1\n400 2\n");
        let e = format!("{:#}", xyz_text(&bad).unwrap_err());
        assert!(e.contains("line 2") && e.contains("bad.spd"), "{e}");
        for f in [p, bad] {
            std::fs::remove_file(f).unwrap();
        }
    }

    #[test]
    fn rgb2spec_prints_spectrum_and_roundtrip() {
        let t = rgb2spec_text(Method::Jakob, "srgb", Kind::Albedo, &[0.6, 0.2, 0.5]).unwrap();
        assert_eq!(t.lines().filter(|l| !l.starts_with('#')).count(), 95);
        let last = t.lines().last().unwrap();
        let err: f64 = last.rsplit(' ').next().unwrap().trim_end_matches(')').parse().unwrap();
        assert!(err < 1e-3, "{last}");
        let t = rgb2spec_text(Method::Smits, "srgb", Kind::Illuminant, &[1.0, 1.0, 1.0]).unwrap();
        assert!(t.contains("round-trip"));
        assert!(rgb2spec_text(Method::Jakob, "srgb", Kind::Albedo, &[1.5, 0.2, 0.1]).is_err());
        assert!(rgb2spec_text(Method::Jakob, "srgb", Kind::Unbounded, &[-1.0, 0.2, 0.1]).is_err());
        assert!(rgb2spec_text(Method::Jakob, "srgb", Kind::Unbounded, &[f32::NAN, 0.2, 0.1]).is_err());
        assert!(rgb2spec_text(Method::Jakob, "cmyk", Kind::Albedo, &[0.1, 0.2, 0.1]).is_err());
    }

    #[test]
    fn project_prints_coefficients_and_error() {
        let p = write_tmp("tri.spd", "360 0\n595 2\n830 0\n");
        // A hat on 3 nodes (360, 595, 830) is in the span: exact fit, zero error.
        let t = project_text(BasisArg::Linear, FitArg::Exact, 3, &p).unwrap();
        assert!(t.contains("1 595.0000 2.000000000"), "{t}");
        let err: f64 = t.lines().last().unwrap().split_whitespace().nth(3).unwrap().parse().unwrap();
        assert!(err < 1e-9, "{t}");
        assert!(project_text(BasisArg::Linear, FitArg::Exact, 1, &p).is_err());
        std::fs::remove_file(p).unwrap();
    }
}
