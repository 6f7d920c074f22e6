//! `prism measure irradiance`: the measuring instrument on the command line.

use crate::accel::AccelKind;
use crate::integrator::PathIntegrator;
use crate::scene::SceneBuilder;
use anyhow::{bail, Context, Result};
use glam::Vec3;
use std::path::PathBuf;

/// What to measure.
#[derive(clap::Subcommand, Debug)]
pub enum MeasureCommand {
    /// Irradiance E [W/m²] (and illuminance [lux]) at a point with a normal.
    Irradiance(IrradianceArgs),
}

/// Arguments of `prism measure irradiance`.
#[derive(clap::Args, Debug)]
pub struct IrradianceArgs {
    /// pbrt-v4 scene file; without one, the built-in Cornell box.
    pub scene: Option<PathBuf>,
    /// Point x,y,z.
    #[arg(long, allow_hyphen_values = true)]
    pub at: String,
    /// Surface normal nx,ny,nz.
    #[arg(long, allow_hyphen_values = true)]
    pub normal: String,
    /// Number of independent estimates.
    #[arg(long, default_value_t = 100_000)]
    pub samples: u64,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Maximum path depth.
    #[arg(long, default_value_t = 8)]
    pub max_depth: u32,
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
    let MeasureCommand::Irradiance(a) = cmd;
    let p = parse_vec3(&a.at, "--at")?;
    let n = parse_vec3(&a.normal, "--normal")?;
    if n.length() == 0.0 {
        bail!("--normal must not be zero");
    }
    if a.samples < 2 {
        bail!("--samples must be at least 2 (a standard error needs two)");
    }
    let builder = match &a.scene {
        None => SceneBuilder::cornell_box(),
        Some(path) => super::render::load_scene_file(path, false)?.0,
    };
    let scene = builder.build(AccelKind::default_available()).context("building the scene")?;
    let integrator = PathIntegrator { max_depth: a.max_depth, ..Default::default() };
    let m = crate::measure::irradiance(&scene, &integrator, p, n, a.samples, a.seed);
    if a.json {
        println!("{}", serde_json::to_string_pretty(&m)?);
    } else {
        println!(
            "irradiance  E = {:.6e} ± {:.2e} W/m²  (360–830 nm, {} samples)",
            m.irradiance.mean, m.irradiance.std_err, m.samples
        );
        println!("illuminance Ev = {:.6e} ± {:.2e} lx", m.illuminance.mean, m.illuminance.std_err);
    }
    Ok(())
}
