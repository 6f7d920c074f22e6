//! Helpers shared by the end-to-end tests.

use prism::film::Film;
use prism::filter::Filter;
use prism::integrator::Integrator;
use prism::render::{RenderSettings, SamplerKind};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The settings most end-to-end renders use: `resolution` pixels, `spp` independent samples
/// per pixel from `seed`, a box filter (each pixel its own samples' estimate), paths of at most
/// `max_depth` bounces, prism's defaults otherwise.
pub fn test_settings(resolution: (u32, u32), spp: u64, seed: u64, max_depth: u32) -> RenderSettings {
    RenderSettings {
        resolution,
        spp,
        seed,
        sampler: SamplerKind::Independent,
        filter: Filter::by_name("box").unwrap(),
        integrator: Integrator { max_depth, ..Default::default() },
        ..Default::default()
    }
}

/// The `prism` binary.
pub fn prism() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prism"))
}

/// A fresh, empty directory for one test, under cargo's temporary directory for tests (in the
/// target directory, so that runs leave nothing in the system's temporary directory).
pub fn tmpdir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("prism-cli-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The exit status of `child` once it ends, or `None` (the child killed) when it has not ended
/// within `limit`.
pub fn wait_within(child: &mut std::process::Child, limit: std::time::Duration) -> Option<std::process::ExitStatus> {
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return Some(status);
        }
        if start.elapsed() > limit {
            child.kill().unwrap();
            child.wait().unwrap();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
}

/// A process's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A `.film` file (`prism render -o X.film`).
pub fn film(path: &Path) -> Film {
    prism::checkpoint::load(path).unwrap().0
}

/// Compares two films pixel by pixel on Y: the mean of the per-pixel differences, its standard
/// error (pixels are independent estimates), and the mean Y of `a`.
pub fn film_difference(a: &Film, b: &Film) -> (f64, f64, f64) {
    let y = |p: &prism::film::Pixel| p.xyz_sum.y / p.weight_sum;
    let d: Vec<f64> = a.pixels.iter().zip(&b.pixels).map(|(p, q)| y(p) - y(q)).collect();
    let n = d.len() as f64;
    let m = d.iter().sum::<f64>() / n;
    let se = (d.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0) / n).sqrt();
    (m, se, a.pixels.iter().map(y).sum::<f64>() / n)
}

/// Pixels whose Y differs from `b`'s by more than half of it (light leaks and acne show up as
/// many such pixels; noise as few).
pub fn pixels_far_off(a: &Film, b: &Film) -> usize {
    let y = |p: &prism::film::Pixel| p.xyz_sum.y / p.weight_sum;
    a.pixels.iter().zip(&b.pixels).filter(|(p, q)| (y(p) - y(q)).abs() > 0.5 * y(q).abs().max(0.05)).count()
}

/// The scene of the pbrt-v4 file `text` on `accel`, which must read without an unsupported
/// feature or an unused parameter.
pub fn pbrt_scene(text: &str, accel: prism::accel::AccelKind) -> prism::scene::Scene {
    let (desc, mut warnings) = prism::pbrt::parse_str(text, &Default::default()).unwrap();
    let (builder, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    let unsupported: Vec<_> =
        warnings.iter().filter(|w| w.strict_error().is_some() || w.message.contains("not used")).collect();
    assert!(unsupported.is_empty(), "{unsupported:?}");
    builder.build(accel).unwrap()
}

/// obvhs, and the default backend when that is another.
pub fn backends() -> Vec<prism::accel::AccelKind> {
    use prism::accel::AccelKind;
    let mut b = vec![AccelKind::Obvhs];
    if AccelKind::default_available() != AccelKind::Obvhs {
        b.push(AccelKind::default_available());
    }
    b
}

/// Renders the scene file `file` as two parts (`--part 1/2`, `2/2`) into `dir` and merges them
/// to `dir/merged.exr`; its path.
pub fn render_halves_and_merge(dir: &Path, file: &Path) -> PathBuf {
    for part in ["1/2", "2/2"] {
        let out = dir.join(format!("part{}.film", &part[..1]));
        let o = prism().arg("render").arg(file).args(["--part", part, "-o"]).arg(&out).output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let merged = dir.join("merged.exr");
    let o = prism()
        .args(["merge", "-o"])
        .arg(&merged)
        .arg(dir.join("part1.film"))
        .arg(dir.join("part2.film"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    merged
}
