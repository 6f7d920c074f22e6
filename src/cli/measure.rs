//! `prism measure irradiance|radiance`: the measuring instrument on the command line.

use crate::accel::AccelKind;
use crate::pbrt::FileSettings;
use crate::render::RenderSettings;
use crate::scene::SceneBuilder;
use crate::settings;
use anyhow::{bail, Context, Result};
use glam::Vec3;
use std::path::PathBuf;

/// What to measure.
#[derive(clap::Subcommand, Debug)]
pub enum MeasureCommand {
    /// Irradiance E [W/m²] (and illuminance [lux]) at a point with a normal.
    Irradiance {
        #[command(flatten)]
        at: Instrument,
        /// Surface normal nx,ny,nz.
        #[arg(long, allow_hyphen_values = true)]
        normal: String,
    },
    /// Radiance L [W/(sr·m²)] (and luminance [cd/m²]) leaving a point toward a direction.
    Radiance {
        #[command(flatten)]
        at: Instrument,
        /// Direction dx,dy,dz the radiance travels in (e.g. from a surface toward a viewer).
        #[arg(long, allow_hyphen_values = true)]
        dir: String,
    },
}

/// Where and how to measure.
#[derive(clap::Args, Debug)]
pub struct Instrument {
    /// pbrt-v4 scene file; without one, the built-in Cornell box.
    pub scene: Option<PathBuf>,
    /// Point x,y,z.
    #[arg(long, allow_hyphen_values = true)]
    pub at: String,
    /// Number of independent estimates.
    #[arg(long, default_value_t = 100_000)]
    pub samples: u64,
    /// Seed [default: the file's, else 0, as `prism render`].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Maximum path depth, or -1 for no limit [default: the file's, else pbrt-v4's 5 for a scene
    /// file and 8 for the built-in Cornell box, as `prism render`].
    #[arg(long, allow_negative_numbers = true)]
    pub max_depth: Option<i64>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

fn parse_vec3(s: &str, what: &str) -> Result<Vec3> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("{what} '{s}' is not x,y,z"))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        bail!("{what} '{s}' is not three finite numbers x,y,z");
    }
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// Runs `prism measure`.
pub fn run(cmd: &MeasureCommand) -> Result<()> {
    let (a, (dir, dir_name)) = match cmd {
        MeasureCommand::Irradiance { at, normal } => (at, (normal, "--normal")),
        MeasureCommand::Radiance { at, dir } => (at, (dir, "--dir")),
    };
    let p = parse_vec3(&a.at, "--at")?;
    let dir = parse_vec3(dir, dir_name)?;
    if dir.length() == 0.0 {
        bail!("{dir_name} must not be zero");
    }
    if a.samples < 2 {
        bail!("--samples must be at least 2 (a standard error needs two)");
    }
    let d = RenderSettings::default();
    let max_depth = a.max_depth.map(|m| settings::max_depth(m, "--max-depth")).transpose()?;
    let (builder, file) = match &a.scene {
        None => (SceneBuilder::cornell_box(), FileSettings::default()),
        Some(path) => {
            let loaded = super::render::load_scene_file(path, false, Default::default())?;
            (loaded.builder, loaded.settings)
        }
    };
    let seed = a.seed.or(file.seed).unwrap_or(d.seed);
    let scene = builder.build(AccelKind::default_available()).context("building the scene")?;
    let integrator = super::render::integrator_for(&scene, &file, None, max_depth, None);
    // (radiometric name, estimate, unit), (photometric ...), samples, JSON.
    let ((rn, re, ru), (pn, pe, pu), samples, json) = match cmd {
        MeasureCommand::Radiance { .. } => {
            let m = crate::measure::radiance(&scene, &integrator, p, dir, a.samples, seed);
            let json = serde_json::to_string_pretty(&m)?;
            (("radiance  L", m.radiance, "W/(sr·m²)"), ("luminance Lv", m.luminance, "cd/m²"), m.samples, json)
        }
        MeasureCommand::Irradiance { .. } => {
            let m = crate::measure::irradiance(&scene, &integrator, p, dir, a.samples, seed);
            let json = serde_json::to_string_pretty(&m)?;
            (("irradiance  E", m.irradiance, "W/m²"), ("illuminance Ev", m.illuminance, "lx"), m.samples, json)
        }
    };
    let text = format!(
        "{rn} = {:.6e} ± {:.2e} {ru}  (360–830 nm, {samples} samples)\n{pn} = {:.6e} ± {:.2e} {pu}",
        re.mean, re.std_err, pe.mean, pe.std_err
    );
    super::print_stdout(&format!("{}\n", if a.json { json } else { text }))
}
