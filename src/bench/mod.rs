//! `prism bench`: how fast a scene converges, on which backend and sampler. Renders a ladder of
//! sample counts, measures time, throughput and memory, and the error of each image against a
//! converged reference; writes CSV, JSON and plots.

mod error;
mod plot;
mod run_info;
mod terrain;
mod time_to_error;

pub use error::BenchError;
pub use plot::{plot_error_vs_time, plot_rays_per_s};
pub use run_info::RunInfo;
pub use terrain::{terrain_scene, TERRAIN_TRIANGLES};
pub use time_to_error::{default_target, time_to, times_to_rmse, Reading, TimeToRmse};

use crate::accel::AccelKind;
use crate::filter::Filter;
use crate::image::{metrics, Image};
use crate::named::UnknownName;
use crate::pbrt::InputStamp;
use crate::render::{render_range, RenderSettings, SamplerKind};
use crate::scene::{Scene, SceneBuilder};
use crate::spectrum::ColorSpace;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One rendered point of the ladder.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct BenchPoint {
    /// Backend.
    pub accel: String,
    /// Sampler.
    pub sampler: String,
    /// Samples per pixel.
    pub spp: u64,
    /// Wall time of the render [s] (excluding the scene build).
    pub time_s: f64,
    /// Camera samples per second.
    pub samples_per_s: f64,
    /// Rays (camera, continuation, shadow) per second.
    pub rays_per_s: f64,
    /// Accelerator and light build time [s].
    pub build_s: f64,
    /// Resident memory added by loading and building the scene [bytes].
    pub scene_bytes: i64,
    /// Triangles stored in the scene's meshes.
    #[serde(default)]
    pub triangles: u64,
    /// Resident memory added by the accelerator (and lights) on top of the loaded meshes [bytes].
    #[serde(default)]
    pub accel_bytes: i64,
    /// Bytes the accelerator reports holding (its own count: Embree's memory monitor, obvhs'
    /// arrays), exact where the resident-set differences are page-granular and noisy. Embree's
    /// holds its BVH nodes and leaves, and copies of the vertices and indices it does not read
    /// in place from prism's meshes.
    #[serde(default)]
    pub accel_own_bytes: u64,
    /// Bytes of prism's own triangle arrays (positions, indices, normals, texture coordinates):
    /// what shading reads, and what Embree traces in place when it shares them.
    #[serde(default)]
    pub mesh_bytes: u64,
    /// Peak resident memory during the build above the level before loading [bytes]
    /// (builders need temporary memory; 0 where the kernel cannot reset the peak).
    #[serde(default)]
    pub build_peak_bytes: i64,
    /// Peak resident memory of the process so far [bytes].
    pub peak_rss_bytes: u64,
    /// Root-mean-square error against the reference (linear RGB).
    pub rmse: f64,
    /// Relative MSE against the reference.
    pub rel_mse: f64,
    /// Mean absolute error.
    pub mae: f64,
}

/// What to benchmark.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// pbrt-v4 scene, or `builtin:cornell` / `builtin:terrain` (None: the Cornell box).
    pub scene: Option<PathBuf>,
    /// Backends to compare.
    pub accels: Vec<AccelKind>,
    /// Samplers to compare.
    pub samplers: Vec<SamplerKind>,
    /// Sample counts.
    pub ladder: Vec<u64>,
    /// Reference image (None: render and cache one).
    pub reference: Option<PathBuf>,
    /// Samples per pixel of a rendered reference.
    pub reference_spp: u64,
    /// Output directory.
    pub out: PathBuf,
    /// What every render of the bench uses (image size, path depth, filter, ...), except the
    /// samples per pixel, sampler and seed each point sets.
    pub settings: RenderSettings,
    /// RMSEs to report each curve's time to (empty: [`default_target`]).
    pub target_rmse: Vec<f64>,
}

/// Resident set size (current, peak) of this process [bytes], from /proc/self/status.
pub fn rss_bytes() -> (u64, u64) {
    let text = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        text.lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<u64>().ok())
            .map_or(0, |kb| kb * 1024)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

/// Resets the process's peak resident set size (VmHWM) to the current one, so a later
/// [`rss_bytes`] gives the peak of what follows. Linux ≥ 4.0 (`/proc/self/clear_refs`, value 5);
/// returns false where that is not possible.
pub fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Names of the built-in scenes `prism bench` accepts instead of a file.
pub const BUILTIN_SCENES: [&str; 2] = ["builtin:cornell", "builtin:terrain"];

impl BenchConfig {
    /// The bench's render settings: prism's defaults with a box filter, so that each pixel's
    /// error is its own samples' (a wider filter would correlate neighbours).
    pub fn base_settings() -> RenderSettings {
        RenderSettings { filter: Filter::by_name("box").expect("built in"), ..Default::default() }
    }
}

fn load(cfg: &BenchConfig) -> Result<SceneBuilder, BenchError> {
    Ok(match cfg.scene.as_deref().and_then(|p| p.to_str()) {
        None | Some("builtin:cornell") => SceneBuilder::cornell_box(),
        Some("builtin:terrain") => terrain_scene(),
        Some(_) => {
            let path = cfg.scene.as_deref().expect("matched Some");
            let loaded = crate::pbrt::load_file(path, &Default::default())?;
            for w in &loaded.warnings {
                log::warn!("{w}");
            }
            loaded.builder
        }
    })
}

fn settings(cfg: &BenchConfig, spp: u64, sampler: SamplerKind, seed: u64) -> RenderSettings {
    RenderSettings { spp, seed, sampler, ..cfg.settings.clone() }
}

/// Renders `s` and returns the image, its render time [s] and the statistics, calling
/// `progress(samples per pixel done)` after each pass.
fn render_image(
    scene: &Scene,
    s: &RenderSettings,
    mut progress: impl FnMut(u64),
) -> Result<(Image, f64, crate::integrator::Stats), BenchError> {
    let t0 = Instant::now();
    let mut film = crate::render::new_film(s)?;
    let stats = render_range(scene, s, &mut film, 0..s.spp, &Default::default(), |_, done| {
        progress(done);
        true
    });
    Ok((film.to_image(ColorSpace::srgb())?, t0.elapsed().as_secs_f64(), stats))
}

/// The stamps (size, hash of the contents) of every file the scene reads (none for a built-in
/// scene), so that an edited scene file, or a file it includes or loads, is not rendered against
/// the old reference.
fn input_stamps(cfg: &BenchConfig) -> Result<Vec<InputStamp>, BenchError> {
    let Some(path) = cfg.scene.as_ref().filter(|p| p.exists()) else { return Ok(Vec::new()) };
    let (desc, _) = crate::pbrt::parse_file(path, &Default::default())?;
    Ok(crate::pbrt::input_stamps(&desc.input_files(), path.parent().unwrap_or(Path::new(""))))
}

/// The reference: the given image, or a cached render whose settings match, or a new render.
fn reference(cfg: &BenchConfig) -> Result<Image, BenchError> {
    if let Some(p) = &cfg.reference {
        let img = crate::image::read(p).map_err(|source| BenchError::ReadReference { path: p.clone(), source })?;
        // Checked before rendering anything: every point is compared with it pixel by pixel.
        let (w, h) = cfg.settings.resolution;
        if (img.width, img.height) != (w, h) {
            return Err(BenchError::ReferenceSize { path: p.clone(), size: (img.width, img.height), renders: (w, h) });
        }
        return Ok(img);
    }
    let path = cfg.out.join("reference.exr");
    let meta_path = cfg.out.join("reference.json");
    // The reference is reused while its render's fingerprint (every input file's contents and
    // every setting that changes the image) is the same.
    let reference_settings = settings(cfg, cfg.reference_spp, SamplerKind::Sobol, 0xfeed);
    let accel = AccelKind::default_available();
    let scene_name = cfg.scene.as_ref().map_or("builtin:cornell".into(), |p| p.display().to_string());
    let fingerprint =
        crate::fingerprint::fingerprint(&scene_name, &input_stamps(cfg)?, &reference_settings, "srgb", accel.name());
    let meta = serde_json::json!({ "fingerprint": fingerprint, "exr_samples": "f32" });
    if let (Ok(old), Ok(img)) = (std::fs::read_to_string(&meta_path), crate::image::read(&path)) {
        if serde_json::from_str::<serde_json::Value>(&old).ok().as_ref() == Some(&meta) {
            eprintln!("bench: using the cached reference {}", path.display());
            return Ok(img);
        }
    }
    eprintln!("bench: rendering a reference at {} spp (cached in {})", cfg.reference_spp, path.display());
    let scene = load(cfg)?.build(accel)?;
    let bar = crate::progress::spp_progress_bar(cfg.reference_spp);
    let (img, _, _) = render_image(&scene, &reference_settings, |done| bar.set_position(done))?;
    bar.finish_and_clear();
    // 32-bit samples: the cached reference is then exactly the one just measured against, so a
    // later run that reuses it measures the same errors.
    let exact = crate::image::WriteOptions { exr_sample: crate::image::ExrSample::Float, ..Default::default() };
    crate::image::write_with(&path, &img, &exact)?;
    crate::io::write_atomic(&meta_path, serde_json::to_string_pretty(&meta)?.as_bytes())?;
    Ok(img)
}

/// Runs the whole ladder for every backend and sampler.
pub fn run(cfg: &BenchConfig) -> Result<Vec<BenchPoint>, BenchError> {
    if let Some(name) = cfg.scene.as_ref().and_then(|p| p.to_str()).filter(|n| n.starts_with("builtin:")) {
        if !BUILTIN_SCENES.contains(&name) {
            let valid = BUILTIN_SCENES.join(", ");
            return Err(BenchError::UnknownScene(UnknownName { what: "built-in scene", name: name.into(), valid }));
        }
    }
    std::fs::create_dir_all(&cfg.out).map_err(|source| BenchError::CreateDir { path: cfg.out.clone(), source })?;
    let info = RunInfo::collect(cfg);
    let reference = reference(cfg)?;
    let mut points = Vec::new();
    for &accel in &cfg.accels {
        let (rss0, _) = rss_bytes();
        let can_reset = reset_peak_rss();
        let builder = load(cfg)?;
        let (rss_loaded, _) = rss_bytes();
        let t0 = Instant::now();
        let scene = builder.build(accel)?;
        let build_s = t0.elapsed().as_secs_f64();
        let (rss_built, peak) = rss_bytes();
        let scene_bytes = rss_built as i64 - rss0 as i64;
        let accel_bytes = rss_built as i64 - rss_loaded as i64;
        let build_peak_bytes = if can_reset { peak as i64 - rss0 as i64 } else { 0 };
        let triangles = scene.triangle_count();
        let accel_own_bytes = scene.accel().memory_bytes() as u64;
        let mesh_bytes = scene.mesh_bytes() as u64;
        for &sampler in &cfg.samplers {
            for &spp in &cfg.ladder {
                // A different seed from the reference's, so errors are not correlated with it.
                let (img, time_s, stats) = render_image(&scene, &settings(cfg, spp, sampler, 1), |_| {})?;
                let m = metrics::compare(&img, &reference)?;
                let p = BenchPoint {
                    accel: accel.name().into(),
                    sampler: sampler.name().into(),
                    spp,
                    time_s,
                    samples_per_s: stats.samples as f64 / time_s,
                    rays_per_s: stats.rays as f64 / time_s,
                    build_s,
                    scene_bytes,
                    triangles,
                    accel_bytes,
                    accel_own_bytes,
                    mesh_bytes,
                    build_peak_bytes,
                    peak_rss_bytes: rss_bytes().1,
                    rmse: m.rmse,
                    rel_mse: m.rel_mse,
                    mae: m.mae,
                };
                eprintln!(
                    "bench: {:6} {:11} {:5} spp  {:8.3} s  {:6.2} M rays/s  RMSE {:.4e}",
                    p.accel,
                    p.sampler,
                    p.spp,
                    p.time_s,
                    p.rays_per_s / 1e6,
                    p.rmse
                );
                points.push(p);
            }
        }
    }
    let targets = if cfg.target_rmse.is_empty() {
        default_target(&points).into_iter().collect()
    } else {
        cfg.target_rmse.clone()
    };
    write_outputs(&cfg.out, &points, &targets, &info)?;
    Ok(points)
}

/// The points as a Markdown table (for docs/benchmarks.md).
pub fn markdown_table(points: &[BenchPoint]) -> String {
    let mut t = String::from(
        "| accel | sampler | spp | time [s] | M samples/s | M rays/s | build [s] | scene MB | RMSE | relMSE |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for p in points {
        t += &format!(
            "| {} | {} | {} | {:.3} | {:.3} | {:.2} | {:.3} | {:.1} | {:.3e} | {:.3e} |\n",
            p.accel,
            p.sampler,
            p.spp,
            p.time_s,
            p.samples_per_s / 1e6,
            p.rays_per_s / 1e6,
            p.build_s,
            p.scene_bytes as f64 / 1e6,
            p.rmse,
            p.rel_mse
        );
    }
    t += "\n| accel | triangles | build [s] | scene B/tri | meshes B/tri | accel B/tri | accel's own count B/tri | build peak B/tri |\n|---|---|---|---|---|---|---|---|\n";
    let mut seen = Vec::new();
    for p in points.iter().filter(|p| p.triangles > 0) {
        if seen.contains(&&p.accel) {
            continue;
        }
        seen.push(&p.accel);
        let per = |b: i64| b as f64 / p.triangles as f64;
        t += &format!(
            "| {} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} |\n",
            p.accel,
            p.triangles,
            p.build_s,
            per(p.scene_bytes),
            per(p.mesh_bytes as i64),
            per(p.accel_bytes),
            per(p.accel_own_bytes as i64),
            per(p.build_peak_bytes)
        );
    }
    if !seen.is_empty() {
        t += "\nscene: resident memory added by loading and building; meshes: prism's vertex, index, normal and \
              texture-coordinate arrays (read by shading, and by Embree in place); accel: resident memory the build \
              added; accel's own count: the backend's (Embree: BVH nodes and leaves, and copies of the arrays it \
              does not read in place; obvhs: nodes and reordered triangles); build peak: the most resident during \
              the build.\n";
    }
    t
}

/// Writes bench.csv, bench.json, time_to_rmse.json (each curve's time to each of `targets`),
/// bench.md (headed by `info`), run.json and the plots into `dir`.
pub fn write_outputs(dir: &Path, points: &[BenchPoint], targets: &[f64], info: &RunInfo) -> Result<(), BenchError> {
    let mut csv = String::from(
        "accel,sampler,spp,time_s,samples_per_s,rays_per_s,build_s,scene_bytes,triangles,accel_bytes,accel_own_bytes,mesh_bytes,build_peak_bytes,peak_rss_bytes,rmse,rel_mse,mae\n",
    );
    for p in points {
        csv += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            p.accel,
            p.sampler,
            p.spp,
            p.time_s,
            p.samples_per_s,
            p.rays_per_s,
            p.build_s,
            p.scene_bytes,
            p.triangles,
            p.accel_bytes,
            p.accel_own_bytes,
            p.mesh_bytes,
            p.build_peak_bytes,
            p.peak_rss_bytes,
            p.rmse,
            p.rel_mse,
            p.mae
        );
    }
    crate::io::write_atomic(&dir.join("bench.csv"), csv.as_bytes())?;
    crate::io::write_atomic(&dir.join("bench.json"), serde_json::to_string_pretty(points)?.as_bytes())?;
    crate::io::write_atomic(&dir.join("run.json"), serde_json::to_string_pretty(info)?.as_bytes())?;
    let times = times_to_rmse(points, targets);
    for t in &times {
        let how = if t.reading == Reading::Extrapolated { " (extrapolated)" } else { "" };
        eprintln!("bench: {:6} {:11} reaches RMSE {:.3e} in {:.3} s{how}", t.accel, t.sampler, t.target_rmse, t.time_s);
    }
    crate::io::write_atomic(&dir.join("time_to_rmse.json"), serde_json::to_string_pretty(&times)?.as_bytes())?;
    let md = format!("{}\n{}\n{}", info.markdown(), markdown_table(points), time_to_error::markdown(&times));
    crate::io::write_atomic(&dir.join("bench.md"), md.as_bytes())?;
    for ext in ["png", "svg"] {
        plot_error_vs_time(points, &dir.join(format!("error_vs_time.{ext}")))?;
        plot_rays_per_s(points, &dir.join(format!("rays_per_s.{ext}")))?;
    }
    Ok(())
}
