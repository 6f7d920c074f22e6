//! `prism bench` and `prism compare`.

use crate::accel::AccelKind;
use crate::bench::{self, BenchConfig};
use crate::integrator::Integrator;
use crate::render::RenderSettings;
use crate::settings::{self, parse_list};
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
    /// Image size as WxH [default: prism render's, 256x256].
    #[arg(long)]
    pub resolution: Option<String>,
    /// Maximum path depth, or -1 for no limit [default: prism render's, 8].
    #[arg(long, allow_negative_numbers = true)]
    pub max_depth: Option<i64>,
    /// Target RMSEs, comma separated: bench.md and time_to_rmse.json give each curve's time to
    /// each [default: the lowest RMSE every curve reaches].
    #[arg(long)]
    pub target_rmse: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Runs `prism bench`.
pub fn run(a: &BenchArgs) -> Result<()> {
    let accels = parse_list(&a.accel, "--accel", |s| AccelKind::parse(s).map_err(anyhow::Error::from))?;
    let samplers = parse_list(&a.sampler, "--sampler", settings::parse_sampler)?;
    let ladder = parse_list(&a.spp_ladder, "--spp-ladder", |s| settings::parse_count(s, "--spp-ladder"))?;
    settings::count(a.reference_spp.min(i64::MAX as u64) as i64, "--reference-spp")?;
    let target_rmse = match &a.target_rmse {
        None => Vec::new(),
        Some(t) => parse_list(t, "--target-rmse", |s| match s.parse::<f64>() {
            Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
            _ => bail!("--target-rmse: '{s}' is not a positive number"),
        })?,
    };
    let pool = super::worker_pool(a.threads)?;
    let base = BenchConfig::base_settings();
    let resolution = a.resolution.as_deref().map(settings::parse_resolution).transpose()?;
    let max_depth = a.max_depth.map(|d| settings::max_depth(d, "--max-depth")).transpose()?;
    // The file's integrator, as `prism render` takes it (the built-in scenes have none).
    let file = match a.scene.as_deref().filter(|p| !p.to_string_lossy().starts_with("builtin:")) {
        // Its warnings are printed when the bench loads it.
        Some(path) => crate::pbrt::load_file(path, &Default::default())?.settings,
        None => Default::default(),
    };
    let from_file = Integrator::from_file(&file);
    let settings = RenderSettings {
        resolution: resolution.unwrap_or(base.resolution),
        integrator: Integrator { max_depth: max_depth.unwrap_or(from_file.max_depth), ..from_file },
        ..base
    };
    let cfg = BenchConfig {
        scene: a.scene.clone(),
        accels,
        samplers,
        ladder,
        reference: a.reference.clone(),
        reference_spp: a.reference_spp,
        out: a.out.clone(),
        settings,
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
    // The error `prism compat` and `--target-error` use, where the images have colour.
    let mapped = (ia.channels >= 3).then(|| crate::image::metrics::compressed_rgb_rmse(&ia, &ib)).transpose()?;
    if a.json {
        let j = serde_json::json!({"rmse": m.rmse, "rel_mse": m.rel_mse, "mae": m.mae, "max_abs": m.max_abs,
            "mapped_rgb_rmse": mapped});
        super::print_stdout(&format!("{}\n", serde_json::to_string_pretty(&j)?))?;
    } else {
        let mapped = mapped.map_or(String::new(), |e| format!("RMSE of x/(1+x) RGB  {e:.6e}\n"));
        super::print_stdout(&format!(
            "RMSE    {:.6e}\nrelMSE  {:.6e}\nMAE     {:.6e}\nmax|Δ|  {:.6e}\n{mapped}",
            m.rmse, m.rel_mse, m.mae, m.max_abs
        ))?;
    }
    if let Some(d) = &a.diff {
        let img = crate::image::metrics::false_colour_difference(&ia, &ib)?;
        crate::image::write(d, &img).with_context(|| format!("writing {}", d.display()))?;
    }
    Ok(())
}
