//! `prism sss-report`: renders the report's three scenes × three media with both subsurface
//! methods at a small resolution, measures time and RMSE against a converged random-walk
//! reference, estimates each method's remaining error at convergence, and writes the table into
//! docs/subsurface.md (between marker comments), CSV/JSON, an error-vs-time plot per scene, and
//! PNGs of the references and of the diffusion renders.

use super::sss_scenes::{build, MEDIA, SHAPES};
use crate::accel::AccelKind;
use crate::bench::{plot_error_vs_time, BenchPoint};
use crate::checkpoint::{self, FilmHeader};
use crate::film::Film;
use crate::filter::Filter;
use crate::image::{metrics, Image};
use crate::integrator::{Integrator, SubsurfaceMethod};
use crate::render::{render, render_range, RenderSettings, SamplerKind};
use crate::settings::{self, parse_list};
use crate::spectrum::ColorSpace;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `prism sss-report`.
#[derive(clap::Args, Debug, Clone)]
pub struct SssReportArgs {
    /// Directory holding subsurface.md; figures go to OUT/subsurface/.
    #[arg(long, default_value = "docs")]
    pub out: PathBuf,
    /// Image side [pixels].
    #[arg(long, default_value_t = 64)]
    pub size: u32,
    /// Samples per pixel of the random-walk reference.
    #[arg(long, default_value_t = 8192)]
    pub reference_spp: u64,
    /// Samples per pixel of the diffusion render whose error against the reference is the
    /// model's remaining error (at most the reference's).
    #[arg(long, default_value_t = 1024)]
    pub convergence_spp: u64,
    /// Sample counts rendered with each method (comma-separated, increasing).
    #[arg(long, default_value = "4,16,64")]
    pub ladder: String,
    /// Directory where references are kept as film files, extended and reused by later runs
    /// with the same scene, medium and size (delete it after changing the random walk).
    #[arg(long, default_value = "target/sss-reference")]
    pub cache: PathBuf,
}

/// One row of the report.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SssRow {
    /// Scene.
    pub scene: String,
    /// Medium.
    pub medium: String,
    /// Method.
    pub method: String,
    /// Time of the reference render [s], summed over the runs that built it.
    pub reference_s: f64,
    /// (spp, time [s], RMSE) along the ladder.
    pub ladder: Vec<(u64, f64, f64)>,
    /// RMSE remaining at convergence: diffusion at the reference's spp against the reference;
    /// for the walk, the reference's own noise (estimated).
    pub bias: f64,
    /// Diffusion: the model's bias alone, √(bias² − σ_D² − σ_R²), with the noise σ_D of the
    /// diffusion image (half the squared RMSE between two seeds) and σ_R of the reference
    /// removed. None for the walk (unbiased).
    pub model_bias: Option<f64>,
    /// Diffusion: the render time [s] after which the walk's expected RMSE, RMSE@last × √(t_last/t),
    /// falls below the diffusion's model bias: beyond it the unbiased method is the better buy.
    pub walk_wins_after_s: Option<f64>,
}

/// The report's renders: prism's defaults with a `size`² image, a box filter (each pixel's error
/// its own samples') and depth 16 (subsurface paths bounce more than the default allows).
fn settings(size: u32, spp: u64, seed: u64, sss: SubsurfaceMethod) -> RenderSettings {
    let d = RenderSettings::default();
    RenderSettings {
        resolution: (size, size),
        spp,
        seed,
        sampler: SamplerKind::Sobol,
        filter: Filter::by_name("box").expect("box filter"),
        integrator: Integrator { max_depth: 16, sss, ..d.integrator },
        ..d
    }
}

/// Runs the report.
pub fn run(a: &SssReportArgs) -> Result<()> {
    let ladder = parse_list(&a.ladder, "--ladder", |s| settings::parse_count(s, "--ladder"))?;
    settings::count(a.size.into(), "--size")?;
    for (n, what) in [(a.reference_spp, "--reference-spp"), (a.convergence_spp, "--convergence-spp")] {
        settings::count(n.min(i64::MAX as u64) as i64, what)?;
    }
    if ladder.len() < 2 || ladder.windows(2).any(|w| w[0] >= w[1]) {
        bail!("--ladder needs at least two increasing sample counts");
    }
    let fig = a.out.join("subsurface");
    std::fs::create_dir_all(&fig).with_context(|| format!("creating {}", fig.display()))?;
    let space = ColorSpace::srgb();
    let mut rows = Vec::new();
    let mut points = Vec::new();
    for shape in SHAPES {
        let mut shape_points = Vec::new();
        for medium in &MEDIA {
            let scene = build(shape, medium).build(AccelKind::default_available()).context("building the scene")?;
            let name = format!("{}-{}", shape.name(), medium.name);
            let fingerprint = format!(
                "sss-report {} samples v{} {name} {medium:?} {}",
                env!("CARGO_PKG_VERSION"),
                crate::render::SAMPLE_STREAM_VERSION,
                a.size
            );
            let (film, reference_s) = reference(&scene, a, &name, &fingerprint)?;
            let reference = film.to_image(space)?;
            save_png(&fig.join(format!("{name}-reference.png")), &reference)?;
            let mut diffusion_noise2 = 0.0;
            for method in [SubsurfaceMethod::Diffusion, SubsurfaceMethod::RandomWalk] {
                // Untimed: builds the diffusion table (a once-per-material cost, not a render's).
                render(&scene, &settings(a.size, 1, 0, method), |_| {})?;
                let mut rungs = Vec::new();
                for &spp in &ladder {
                    let t0 = Instant::now();
                    let (film, _) = render(&scene, &settings(a.size, spp, 1, method), |_| {})?;
                    let time_s = t0.elapsed().as_secs_f64();
                    let img = film.to_image(space)?;
                    let m = metrics::compare(&img, &reference)?;
                    rungs.push((spp, time_s, m.rmse));
                    let p = BenchPoint {
                        accel: medium.name.to_string(),
                        sampler: method.name().to_string(),
                        spp,
                        time_s,
                        rmse: m.rmse,
                        rel_mse: m.rel_mse,
                        mae: m.mae,
                        ..Default::default()
                    };
                    shape_points.push(p.clone());
                    points.push((shape.name(), p));
                    if spp == *ladder.last().unwrap() {
                        save_png(&fig.join(format!("{name}-{}.png", method.name())), &img)?;
                    }
                }
                // The error left at convergence: diffusion rendered at many samples against the
                // reference; the walk is unbiased, so its value is the reference's own noise,
                // extrapolated from the last rung as 1/√spp.
                let bias = match method {
                    SubsurfaceMethod::Diffusion => {
                        let spp = a.convergence_spp.min(a.reference_spp);
                        let render_seed = |seed| {
                            let (film, _) = render(&scene, &settings(a.size, spp, seed, method), |_| {})?;
                            film.to_image(space)
                        };
                        let (d, d2) = (render_seed(2)?, render_seed(3)?);
                        diffusion_noise2 = metrics::compare(&d, &d2)?.rmse.powi(2) / 2.0;
                        metrics::compare(&d, &reference)?.rmse
                    }
                    SubsurfaceMethod::RandomWalk => {
                        let (n, _, e) = *rungs.last().unwrap();
                        e * (n as f64 / a.reference_spp as f64).sqrt()
                    }
                };
                eprintln!("{name} {}: {rungs:?}, at convergence {bias:.4}", method.name());
                rows.push(SssRow {
                    scene: shape.name().into(),
                    medium: medium.name.into(),
                    method: method.name().into(),
                    reference_s,
                    ladder: rungs,
                    bias,
                    model_bias: None,
                    walk_wins_after_s: None,
                });
            }
            // Rows: [.., diffusion, walk]; the walk's value is the reference's noise.
            let n = rows.len();
            let (reference_noise, d) = (rows[n - 1].bias, rows[n - 2].bias);
            let model_bias = (d * d - diffusion_noise2 - reference_noise * reference_noise).max(0.0).sqrt();
            let &(_, t, e) = rows[n - 1].ladder.last().unwrap();
            rows[n - 2].model_bias = Some(model_bias);
            rows[n - 2].walk_wins_after_s = (model_bias > 0.0).then(|| t * (e / model_bias).powi(2));
        }
        plot_error_vs_time(&shape_points, &fig.join(format!("{}-error.png", shape.name())))?;
    }
    let json = serde_json::to_string_pretty(&rows)?;
    crate::io::write_atomic(&fig.join("report.json"), json.as_bytes())?;
    let table = markdown(&rows, a, &ladder);
    let doc = a.out.join("subsurface.md");
    let text = std::fs::read_to_string(&doc).unwrap_or_default();
    crate::io::write_atomic(&doc, splice(&text, &table).as_bytes())?;
    eprintln!("wrote {} and {}", doc.display(), fig.display());
    Ok(())
}

/// The random-walk reference of one scene and medium at `a.reference_spp`, and the time spent
/// rendering it [s]. Sobol samples depend only on their index, so the film kept in the cache is
/// extended by the missing sample range (saved after every pass) and equals a render in one go.
fn reference(scene: &crate::scene::Scene, a: &SssReportArgs, name: &str, fingerprint: &str) -> Result<(Film, f64)> {
    std::fs::create_dir_all(&a.cache).with_context(|| format!("creating {}", a.cache.display()))?;
    let path = a.cache.join(format!("{name}-{}.film", a.size));
    let time_path = path.with_extension("seconds");
    // A cache holding more samples than asked for is left alone (and not used).
    let (mut cached, mut keep) = (None, true);
    if let Ok((film, h)) = checkpoint::load(&path) {
        if h.fingerprint == fingerprint && h.samples.start == 0 {
            let seconds = std::fs::read_to_string(&time_path).ok().and_then(|s| s.trim().parse::<f64>().ok());
            match seconds {
                Some(s) if h.samples.end <= a.reference_spp => cached = Some((film, h.samples.end, s)),
                Some(_) => keep = false,
                None => {}
            }
        }
    }
    let (mut film, done, before_s) = match cached {
        Some(c) => c,
        None => (Film::try_new(a.size, a.size)?, 0, 0.0),
    };
    let settings = settings(a.size, a.reference_spp, 1000, SubsurfaceMethod::RandomWalk);
    let t0 = Instant::now();
    let mut saved = Ok(());
    let stats = render_range(scene, &settings, &mut film, done..a.reference_spp, &Default::default(), |film, end| {
        if !keep {
            return true;
        }
        let header = FilmHeader {
            width: a.size,
            height: a.size,
            samples: 0..end,
            spp_total: a.reference_spp,
            fingerprint: fingerprint.to_string(),
            window: None,
            color_space: None,
            exr_float: false,
            aov: false,
            spectral: None,
            splat_paths: None,
        };
        let seconds = before_s + t0.elapsed().as_secs_f64();
        saved = checkpoint::save(&path, film, &header)
            .map_err(anyhow::Error::from)
            .and_then(|()| Ok(crate::io::write_atomic(&time_path, seconds.to_string().as_bytes())?));
        saved.is_ok()
    });
    saved.with_context(|| format!("caching the reference in {}", path.display()))?;
    let seconds = before_s + t0.elapsed().as_secs_f64();
    eprintln!(
        "{name}: reference {} spp ({done} cached), {seconds:.1} s ({} non-finite)",
        a.reference_spp, stats.nonfinite
    );
    Ok((film, seconds))
}

fn markdown(rows: &[SssRow], a: &SssReportArgs, ladder: &[u64]) -> String {
    let mut s = format!(
        "Generated by `prism sss-report --out {} --size {} --reference-spp {} --convergence-spp {} --ladder {}` \
         ({}×{} px, random-walk reference at {} spp, Sobol sampler, box filter). RMSE in linear sRGB.\n\n",
        a.out.display(),
        a.size,
        a.reference_spp,
        a.convergence_spp,
        a.ladder,
        a.size,
        a.size,
        a.reference_spp
    );
    s += "| scene | medium | method | reference [s] |";
    for n in ladder {
        s += &format!(" time @{n} [s] | RMSE @{n} |");
    }
    s += " RMSE at convergence¹ | model bias² | walk better after [s]³ |\n|---|---|---|---|";
    s += &"---|---|".repeat(ladder.len());
    s += "---|---|---|\n";
    for r in rows {
        s += &format!("| {} | {} | {} | {:.1} |", r.scene, r.medium, r.method, r.reference_s);
        for (_, t, e) in &r.ladder {
            s += &format!(" {t:.2} | {e:.4} |");
        }
        let model = r.model_bias.map_or("–".to_string(), |b| format!("{b:.4}"));
        let after = r.walk_wins_after_s.map_or("–".to_string(), |t| format!("{t:.1}"));
        s += &format!(" {:.4} | {model} | {after} |\n", r.bias);
    }
    let last = ladder[ladder.len() - 1];
    s += &format!(
        "\n¹ diffusion: rendered at {} spp against the reference (the model's bias plus both \
         images' noise); random walk: unbiased, so this is the reference's own noise, \
         estimated as RMSE@{last} × √({last}/{}).\n\n\
         ² the diffusion's bias with both images' noise removed: √(RMSE² − σ_D² − σ_R²), where σ_D² is \
         half the squared RMSE between two diffusion renders (seeds 2, 3) and σ_R the walk's row.\n\n\
         ³ the render time from which the random walk's expected RMSE, RMSE@{last} × √(t@{last} / t), \
         is below the diffusion's model bias: the unbiased method is then the better buy.\n",
        a.convergence_spp.min(a.reference_spp),
        a.reference_spp
    );
    s
}

const BEGIN: &str = "<!-- sss-report:begin -->";
const END: &str = "<!-- sss-report:end -->";

/// Replaces the text between the markers (or appends a marked section).
fn splice(doc: &str, table: &str) -> String {
    match (doc.find(BEGIN), doc.find(END)) {
        (Some(b), Some(e)) if b < e => format!("{}{BEGIN}\n{table}{}", &doc[..b], &doc[e..]),
        _ => format!("{doc}\n{BEGIN}\n{table}{END}\n"),
    }
}

fn save_png(path: &Path, img: &Image) -> Result<()> {
    crate::image::write(path, img).with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cached_reference_is_extended_to_exactly_the_render_in_one_go() {
        let dir = std::env::temp_dir().join(format!("prism-sss-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let args = |spp: u64, cache: &str| SssReportArgs {
            out: dir.clone(),
            size: 6,
            reference_spp: spp,
            convergence_spp: spp,
            ladder: "1,2".into(),
            cache: dir.join(cache),
        };
        let scene = build(SHAPES[0], &MEDIA[0]).build(AccelKind::default_available()).unwrap();
        let (half, _) = reference(&scene, &args(4, "a"), "t", "fp").unwrap();
        let (extended, _) = reference(&scene, &args(8, "a"), "t", "fp").unwrap();
        let (direct, _) = reference(&scene, &args(8, "b"), "t", "fp").unwrap();
        assert_eq!(half.total_samples(), 36 * 4);
        assert_eq!(extended.pixels, direct.pixels);
        assert!(extended.pixels.iter().any(|p| p.xyz_sum.y > 0.0), "the reference is black");
        // Fewer samples than cached: rendered afresh, the cache kept.
        let (fewer, _) = reference(&scene, &args(4, "a"), "t", "fp").unwrap();
        assert_eq!(fewer.pixels, half.pixels);
        assert_eq!(checkpoint::load(&dir.join("a").join("t-6.film")).unwrap().1.samples, 0..8);
        // Another fingerprint (another medium or code version) starts over.
        let (other, _) = reference(&scene, &args(4, "a"), "t", "other").unwrap();
        assert_eq!(other.pixels, half.pixels);
        let (_, h) = checkpoint::load(&dir.join("a").join("t-6.film")).unwrap();
        assert_eq!((h.samples, h.fingerprint.as_str()), (0..4, "other"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn report_table_is_spliced_between_its_markers() {
        assert_eq!(
            splice("a\n<!-- sss-report:begin -->\nold\n<!-- sss-report:end -->\nz", "new\n"),
            "a\n<!-- sss-report:begin -->\nnew\n<!-- sss-report:end -->\nz"
        );
    }
}
