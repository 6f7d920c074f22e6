//! `prism bench` and `prism compare`.

use super::positive;
use crate::accel::AccelKind;
use crate::bench::{self, BenchConfig};
use crate::render::SamplerKind;
use anyhow::{bail, Context, Result};
use std::path::PathBuf;

/// Arguments of `prism bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// pbrt-v4 scene, or a built-in: builtin:cornell (the default), builtin:terrain (1M triangles).
    pub scene: Option<PathBuf>,
    /// Backends, comma separated: embree, embree-watertight, obvhs.
    #[arg(long, default_value = "embree,obvhs")]
    pub accel: String,
    /// Samplers, comma separated.
    #[arg(long, default_value = "independent,sobol")]
    pub sampler: String,
    /// Sample counts, comma separated.
    #[arg(long, default_value = "1,4,16,64,256")]
    pub spp_ladder: String,
    /// Reference image (EXR); without one, a reference is rendered and cached in --out, and
    /// rendered again when the settings or any file the scene reads (includes, meshes, …) change.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Samples per pixel of a rendered reference.
    #[arg(long, default_value_t = 4096)]
    pub reference_spp: u64,
    /// Output directory for CSV, JSON and plots.
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Image size as WxH.
    #[arg(long, default_value = "256x256")]
    pub resolution: String,
    /// Maximum path depth, or -1 for no limit.
    #[arg(long, default_value_t = 8, allow_negative_numbers = true)]
    pub max_depth: i64,
    /// Target RMSEs, comma separated: bench.md and time_to_rmse.json give each curve's time to
    /// each [default: the lowest RMSE every curve reaches].
    #[arg(long)]
    pub target_rmse: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

fn list<T>(s: &str, what: &str, parse: impl Fn(&str) -> Result<T>) -> Result<Vec<T>> {
    let v: Vec<T> = s.split(',').map(|x| parse(x.trim())).collect::<Result<_>>()?;
    if v.is_empty() {
        bail!("{what} is empty");
    }
    Ok(v)
}

/// Runs `prism bench`.
pub fn run(a: &BenchArgs) -> Result<()> {
    let accels = list(&a.accel, "--accel", |s| AccelKind::parse(s).map_err(anyhow::Error::msg))?;
    let samplers = list(&a.sampler, "--sampler", |s| match s {
        "independent" => Ok(SamplerKind::Independent),
        "sobol" => Ok(SamplerKind::Sobol),
        o => bail!("unknown sampler '{o}' (valid: independent, sobol)"),
    })?;
    let ladder = list(&a.spp_ladder, "--spp-ladder", |s| {
        positive(s.parse::<u64>().with_context(|| format!("--spp-ladder: '{s}' is not a count"))?, "--spp-ladder")
    })?;
    positive(a.reference_spp, "--reference-spp")?;
    let target_rmse = match &a.target_rmse {
        None => Vec::new(),
        Some(t) => list(t, "--target-rmse", |s| match s.parse::<f64>() {
            Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
            _ => bail!("--target-rmse: '{s}' is not a positive number"),
        })?,
    };
    let pool = super::worker_pool(a.threads)?;
    let (w, h) = a
        .resolution
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| w > 0 && h > 0)
        .with_context(|| format!("--resolution '{}' is not WxH", a.resolution))?;
    let cfg = BenchConfig {
        scene: a.scene.clone(),
        accels,
        samplers,
        ladder,
        reference: a.reference.clone(),
        reference_spp: a.reference_spp,
        out: a.out.clone(),
        resolution: (w, h),
        max_depth: super::max_depth(a.max_depth)?,
        target_rmse,
    };
    pool.install(|| bench::run(&cfg))?;
    eprintln!(
        "bench: wrote bench.csv, bench.json, time_to_rmse.json, bench.md, run.json, error_vs_time.{{png,svg}}, rays_per_s.{{png,svg}} in {}",
        a.out.display()
    );
    Ok(())
}

/// Arguments of `prism compare`.
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// Test image.
    pub a: PathBuf,
    /// Reference image.
    pub b: PathBuf,
    /// Write a false-colour |A−B| image here.
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs `prism compare`.
pub fn compare(a: &CompareArgs) -> Result<()> {
    if let Some(d) = &a.diff {
        // Fail before printing any metrics, not after.
        super::render::check_output(d)?;
    }
    let ia = crate::image::read(&a.a).with_context(|| format!("reading {}", a.a.display()))?;
    let ib = crate::image::read(&a.b).with_context(|| format!("reading {}", a.b.display()))?;
    let m = crate::image::metrics::compare(&ia, &ib)
        .with_context(|| format!("comparing {} with {}", a.a.display(), a.b.display()))?;
    if a.json {
        let j = serde_json::json!({"rmse": m.rmse, "rel_mse": m.rel_mse, "mae": m.mae, "max_abs": m.max_abs});
        println!("{}", serde_json::to_string_pretty(&j)?);
    } else {
        println!("RMSE    {:.6e}\nrelMSE  {:.6e}\nMAE     {:.6e}\nmax|Δ|  {:.6e}", m.rmse, m.rel_mse, m.mae, m.max_abs);
    }
    if let Some(d) = &a.diff {
        let img = crate::image::metrics::false_colour_difference(&ia, &ib)?;
        crate::image::write(d, &img).with_context(|| format!("writing {}", d.display()))?;
    }
    Ok(())
}
