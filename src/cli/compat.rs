//! `prism compat`: render every scene that has a pbrt-v4 reference image beside it and measure
//! prism against pbrt-v4 — channel means, error against pbrt-v4's high-spp image next to
//! pbrt-v4's own error at the same spp, warnings, time — and write the report
//! (docs/compatibility.md) with side-by-side images.
//!
//! A directory holds `NAME.pbrt` scenes (at any depth) and `ref/NAME.pbrt-v4.exr` (pbrt-v4, high
//! spp, seed 1) with `ref/NAME.pbrt-v4.seed2-SPP.exr` (pbrt-v4, SPP samples, seed 2). A
//! reference named `NAME-N` belongs to scene `NAME` rendered at N×N. `ref/REFERENCES*.json`, when
//! present, give pbrt-v4's wall times.

pub use super::compat_case::CompatCase;
use super::compat_report::{self, SceneReport};
use crate::image::{self, compose, metrics, Image};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Arguments of `prism compat`.
#[derive(clap::Args, Debug)]
pub struct CompatArgs {
    /// Directories of scenes with pbrt-v4 references in `ref/`.
    #[arg(default_values = ["../shared/scenes/compat", "../shared/scenes/pbrt-v4-scenes"])]
    pub dirs: Vec<PathBuf>,
    /// Only the scenes with these names (comma separated, e.g. envmap,textures).
    #[arg(long)]
    pub only: Option<String>,
    /// Samples per pixel [default: the spp of pbrt-v4's second-seed image].
    #[arg(long)]
    pub spp: Option<u64>,
    /// Worker threads of each render (pbrt-v4's references used 2).
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Intersection backend passed to `prism render`.
    #[arg(long)]
    pub accel: Option<String>,
    /// Light sampler passed to `prism render` (bvh, power, uniform).
    #[arg(long)]
    pub light_sampler: Option<String>,
    /// Quadrics passed to `prism render` (analytic, tessellated).
    #[arg(long)]
    pub quadrics: Option<String>,
    /// Renders of each scene; its wall time is their median (the image of every run is the same:
    /// the seed is fixed), which steadies the time on a machine shared with other work.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeat: u32,
    /// Directory for prism's renders and logs.
    #[arg(long, default_value = "target/compat")]
    pub out: PathBuf,
    /// Write the report here (side-by-side images go to `images/compat/` beside it).
    #[arg(long)]
    pub doc: Option<PathBuf>,
}

/// Finds the cases of `dir`: every `ref/*.pbrt-v4.exr` whose scene exists.
pub fn discover(dir: &Path) -> Result<Vec<CompatCase>> {
    let refs = dir.join("ref");
    let entries = std::fs::read_dir(&refs).with_context(|| format!("reading {}", refs.display()))?;
    let mut files: Vec<String> =
        entries.filter_map(|e| e.ok()).map(|e| e.file_name().to_string_lossy().into_owned()).collect();
    files.sort();
    let times = reference_times(&refs);
    let mut cases = Vec::new();
    for f in &files {
        let Some(name) = f.strip_suffix(".pbrt-v4.exr") else { continue };
        let Some(scene) = find_scene(dir, name) else {
            log::warn!("{}: no scene for reference {f}", dir.display());
            continue;
        };
        let prefix = format!("{name}.pbrt-v4.seed2-");
        let second = files.iter().find_map(|g| {
            let spp = g.strip_prefix(&prefix)?.strip_suffix(".exr")?.parse().ok()?;
            Some((refs.join(g), spp))
        });
        let pbrt_wall_s = second.as_ref().and_then(|(p, _)| times.get(&*p.file_name()?.to_string_lossy()).copied());
        cases.push(CompatCase { name: name.to_string(), scene, reference: refs.join(f), second, pbrt_wall_s });
    }
    Ok(cases)
}

/// The scene of reference stem `name`: `name.pbrt` anywhere under `dir` (not in `ref/`), else,
/// for a stem `base-N`, `base.pbrt`.
fn find_scene(dir: &Path, name: &str) -> Option<PathBuf> {
    fn walk(dir: &Path, file: &str, depth: u32) -> Option<PathBuf> {
        let direct = dir.join(file);
        if direct.is_file() {
            return Some(direct);
        }
        if depth == 0 {
            return None;
        }
        let mut subdirs: Vec<PathBuf> = std::fs::read_dir(dir)
            .ok()?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_dir() && p.file_name().is_some_and(|n| n != "ref"))
            .collect();
        subdirs.sort();
        subdirs.iter().find_map(|d| walk(d, file, depth - 1))
    }
    walk(dir, &format!("{name}.pbrt"), 2).or_else(|| {
        let (base, n) = name.rsplit_once('-')?;
        n.parse::<u32>().ok()?;
        walk(dir, &format!("{base}.pbrt"), 2)
    })
}

/// Wall times [s] by image file name from `REFERENCES*.json` in `refs`: both the list form
/// (`scenes: [{reference: {...}, seed2: {...}}]`) and the map form (`scenes: {NAME: {references:
/// [...]}}`) are read; anything else is ignored.
fn reference_times(refs: &Path) -> std::collections::HashMap<String, f64> {
    let mut times = std::collections::HashMap::new();
    let mut add = |v: &serde_json::Value| {
        if let (Some(f), Some(t)) = (v["file"].as_str(), v["wall_s"].as_f64()) {
            times.insert(f.to_string(), t);
        }
    };
    let Ok(dir) = std::fs::read_dir(refs) else { return times };
    for e in dir.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().into_owned();
        if !(name.starts_with("REFERENCES") && name.ends_with(".json")) {
            continue;
        }
        let Ok(json) = std::fs::read_to_string(e.path()) else { continue };
        let Ok(v) = serde_json::from_str::<serde_json::Value>(&json) else { continue };
        match &v["scenes"] {
            serde_json::Value::Array(list) => {
                list.iter().flat_map(|s| [&s["reference"], &s["seed2"]]).for_each(&mut add)
            }
            serde_json::Value::Object(map) => {
                map.values().filter_map(|s| s["references"].as_array()).flatten().for_each(&mut add)
            }
            _ => {}
        }
    }
    times
}

/// Runs `prism compat`.
pub fn run(a: &CompatArgs) -> Result<()> {
    let only: Option<Vec<&str>> = a.only.as_deref().map(|s| s.split(',').map(str::trim).collect());
    let mut cases = Vec::new();
    for d in &a.dirs {
        cases.extend(discover(d)?);
    }
    if let Some(only) = &only {
        cases.retain(|c| only.contains(&c.name.as_str()));
    }
    if cases.is_empty() {
        bail!("no scene with a pbrt-v4 reference found");
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let image_dir = a.doc.as_ref().map(|d| d.parent().unwrap_or(Path::new("")).join("images/compat"));
    if let Some(d) = &image_dir {
        std::fs::create_dir_all(d).with_context(|| format!("creating {}", d.display()))?;
    }
    let mut reports = Vec::new();
    for case in &cases {
        eprintln!("compat: {} ...", case.name);
        let r = run_case(case, a, image_dir.as_deref())?;
        eprintln!("compat: {}", compat_report::one_line(&r));
        reports.push(r);
    }
    if let Some(doc) = &a.doc {
        let command = compat_command(a);
        // The per-feature status (what is exact, what differs and why) is written by people,
        // beside the report, and spliced in.
        let notes_path = doc.with_file_name("compatibility-notes.md");
        let notes = std::fs::read_to_string(&notes_path).ok();
        let text = compat_report::markdown(&reports, &command, notes.as_deref());
        crate::io::write_atomic(doc, text.as_bytes()).with_context(|| format!("writing {}", doc.display()))?;
        eprintln!("compat: wrote {}", doc.display());
    }
    Ok(())
}

/// The command line that regenerates the report, for its header.
fn compat_command(a: &CompatArgs) -> String {
    let mut c = String::from("prism compat");
    for d in &a.dirs {
        c += &format!(" {}", d.display());
    }
    if a.repeat > 1 {
        c += &format!(" --repeat {}", a.repeat);
    }
    if let Some(d) = &a.doc {
        c += &format!(" --doc {}", d.display());
    }
    c
}

/// Renders one case with `prism render` in a child process (so a scene that fails or crashes
/// is reported, not fatal) and measures it against pbrt-v4's images.
fn run_case(case: &CompatCase, a: &CompatArgs, image_dir: Option<&Path>) -> Result<SceneReport> {
    let reference = read(&case.reference)?;
    let second = case.second.as_ref().map(|(p, spp)| read(p).map(|i| (i, *spp))).transpose()?;
    let spp = a.spp.or(second.as_ref().map(|s| s.1)).unwrap_or(256);
    let output = a.out.join(format!("{}.exr", case.name));
    let stats = a.out.join(format!("{}.json", case.name));
    let _ = std::fs::remove_file(&output);
    let mut cmd = Command::new(std::env::current_exe().context("locating the prism executable")?);
    cmd.arg("render").arg(&case.scene);
    cmd.args(["--spp", &spp.to_string(), "--threads", &a.threads.to_string(), "--seed", "1"]);
    cmd.args(["--resolution", &format!("{}x{}", reference.width, reference.height)]);
    if let Some(accel) = &a.accel {
        cmd.args(["--accel", accel]);
    }
    if let Some(kind) = &a.light_sampler {
        cmd.args(["--light-sampler", kind]);
    }
    if let Some(mode) = &a.quadrics {
        cmd.args(["--quadrics", mode]);
    }
    cmd.arg("-o").arg(&output).arg("--stats-json").arg(&stats);
    let mut walls = Vec::new();
    let out = loop {
        let t0 = Instant::now();
        let out = cmd.output().with_context(|| format!("running prism render on {}", case.scene.display()))?;
        walls.push(t0.elapsed().as_secs_f64());
        if !out.status.success() || walls.len() == a.repeat as usize {
            break out;
        }
    };
    walls.sort_by(f64::total_cmp);
    let wall_s = walls[walls.len() / 2];
    let log = String::from_utf8_lossy(&out.stderr).into_owned();
    std::fs::write(a.out.join(format!("{}.log", case.name)), &log).ok();
    let mut r = SceneReport::new(case, spp, out.status.code(), &log, wall_s);
    r.ref_means = metrics::channel_means(&reference);
    if let Some((img, spp2)) = &second {
        r.pbrt_error = Some((metrics::compressed_rgb_rmse(img, &reference)?, *spp2));
    }
    if !out.status.success() {
        return Ok(r);
    }
    let prism = read(&output)?;
    r.prism_means = Some(metrics::channel_means(&prism));
    r.prism_error = Some(metrics::compressed_rgb_rmse(&prism, &reference).context(case.name.clone())?);
    r.render_s = std::fs::read_to_string(&stats)
        .ok()
        .and_then(|s| serde_json::from_str::<serde_json::Value>(&s).ok())
        .and_then(|v| v["elapsed_s"].as_f64());
    if let Some(dir) = image_dir {
        let diff = metrics::false_colour_difference(&prism, &reference)?;
        let panels = compose::side_by_side(&[&reference, &prism, &diff], 4)?;
        let png = dir.join(format!("{}.png", case.name));
        image::write(&png, &panels).with_context(|| format!("writing {}", png.display()))?;
        r.panels = Some(png);
    }
    Ok(r)
}

fn read(p: &Path) -> Result<Image> {
    image::read(p).with_context(|| format!("reading {}", p.display()))
}
