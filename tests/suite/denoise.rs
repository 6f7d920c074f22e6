//! `--denoise`: Intel Open Image Denoise over a render and its geometry buffers. A denoised
//! noisy render is much closer to a converged one than the raw render is; the raw output is
//! the same with and without `--denoise`; a missing library is one line, before any render.
//! Tests that need the library skip, saying so, when it is not installed
//! (`scripts/install-oidn.sh`).

use crate::common::{prism, stderr, test_settings, tmpdir};
use prism::accel::AccelKind;
use prism::denoise::{DenoiseInputs, Denoiser};
use prism::film::{AovSettings, AovSpace};
use prism::image::metrics::compressed_rgb_rmse;
use prism::image::Image;
use prism::scene::SceneBuilder;
use prism::spectrum::ColorSpace;

/// The library, or `None` after printing why the calling test skips (to the real stderr, past
/// the test harness's capture, so that `cargo test` shows it).
fn denoiser(test: &str) -> Option<Denoiser> {
    use std::io::Write;
    match Denoiser::load() {
        Ok(d) => Some(d),
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "{test}: skipped: {e}");
            None
        }
    }
}

/// The Cornell box at `n`×`n`, `spp` samples per pixel from `seed`, with its geometry buffers.
fn cornell(n: u32, spp: u64, seed: u64) -> prism::film::Film {
    let scene = SceneBuilder::cornell_box().build(AccelKind::Obvhs).unwrap();
    let space = ColorSpace::by_name("srgb").unwrap();
    let mut settings = test_settings((n, n), spp, seed, 8);
    settings.film.aov = Some(AovSettings { coordinates: AovSpace::Camera, space });
    prism::render::render(&scene, &settings, |_| {}).unwrap().0
}

/// The standard deviation of an image's samples.
fn spread(img: &Image) -> f64 {
    let n = img.data.len() as f64;
    let mean = img.data.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
    (img.data.iter().map(|&v| (f64::from(v) - mean).powi(2)).sum::<f64>() / n).sqrt()
}

#[test]
fn denoising_a_noisy_render_brings_it_much_closer_to_a_converged_one() {
    let Some(denoiser) = denoiser("denoising_a_noisy_render_brings_it_much_closer_to_a_converged_one") else {
        return;
    };
    let space = ColorSpace::by_name("srgb").unwrap();
    let n = 64;
    // The converged image from other samples (another seed): 128 × the noisy render's.
    let reference = cornell(n, 512, 2).to_image(space).unwrap();
    let noisy = cornell(n, 4, 1);
    let raw = noisy.to_image(space).unwrap();
    let inputs = DenoiseInputs::from_film(&noisy, space).unwrap();
    assert_eq!(inputs.color, raw.data, "the denoiser's beauty is the raw image");
    let denoised = denoiser.denoise(&inputs).unwrap();
    assert_eq!((denoised.width, denoised.height, denoised.channels), (n, n, 3));
    assert!(denoised.data.iter().all(|v| v.is_finite()));
    let (e_raw, e_denoised) =
        (compressed_rgb_rmse(&raw, &reference).unwrap(), compressed_rgb_rmse(&denoised, &reference).unwrap());
    eprintln!("64x64 Cornell box at 4 spp: error {e_raw:.4} raw, {e_denoised:.4} denoised");
    assert!(e_denoised < 0.5 * e_raw, "denoised error {e_denoised} is not below half the raw {e_raw}");
    // Not a blur into a constant, and the same brightness: the image's structure (walls, light,
    // boxes) keeps most of the reference's spread.
    let (s_ref, s_den) = (spread(&reference), spread(&denoised));
    assert!(s_den > 0.5 * s_ref && s_den < 1.5 * s_ref, "spread {s_den} vs the reference's {s_ref}");
    let mean = |img: &Image| img.data.iter().map(|&v| f64::from(v)).sum::<f64>() / img.data.len() as f64;
    let (m_ref, m_den) = (mean(&reference), mean(&denoised));
    assert!((m_den / m_ref - 1.0).abs() < 0.1, "mean {m_den} vs the reference's {m_ref}");
}

/// Renders the Cornell box with `args` to `out`; panics with stderr on failure.
fn render(out: &std::path::Path, args: &[&str]) {
    let o = prism()
        .args(["render", "--resolution", "40x40", "--spp", "4", "--seed", "3", "--accel", "obvhs", "--threads", "2"])
        .args(args)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn the_raw_output_is_the_same_with_and_without_denoise() {
    if denoiser("the_raw_output_is_the_same_with_and_without_denoise").is_none() {
        return;
    }
    let dir = tmpdir("denoise-raw");
    // PNG has no render time in it: the files must be equal byte for byte.
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    render(&a, &[]);
    render(&b, &["--denoise"]);
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert!(!dir.join("a.denoised.png").exists());
    let denoised = prism::image::read(&dir.join("b.denoised.png")).unwrap();
    assert_eq!((denoised.width, denoised.height), (40, 40));
    // OpenEXR: the same pixels and only R, G, B (the geometry buffers recorded for the
    // denoiser are not written); the denoised image beside it differs from it.
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    render(&a, &[]);
    render(&b, &["--denoise"]);
    let (ia, ib) = (prism::image::read(&a).unwrap(), prism::image::read(&b).unwrap());
    assert_eq!((ib.channels, &ib.data), (3, &ia.data));
    let id = prism::image::read(&dir.join("b.denoised.exr")).unwrap();
    assert_eq!((id.width, id.height, id.channels), (40, 40, 3));
    assert_ne!(id.data, ia.data);
}

#[test]
fn parts_are_denoised_after_their_merge() {
    if denoiser("parts_are_denoised_after_their_merge").is_none() {
        return;
    }
    let dir = tmpdir("denoise-merge");
    let part = |i: u32| dir.join(format!("p{i}.film"));
    let o = prism().args(["render", "--part", "1/2", "--denoise", "-o"]).arg(part(1)).output().unwrap();
    let e = stderr(&o);
    assert!(!o.status.success() && e.lines().count() == 1 && e.contains("prism merge --denoise"), "{e}");
    for i in [1, 2] {
        render(&part(i), &["--part", &format!("{i}/2"), "--aov"]);
    }
    let out = dir.join("m.exr");
    let o = prism()
        .args(["merge", "--denoise", "--threads", "1"])
        .arg(part(1))
        .arg(part(2))
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let id = prism::image::read(&dir.join("m.denoised.exr")).unwrap();
    assert_eq!((id.width, id.height, id.channels), (40, 40, 3));
}

#[test]
fn a_missing_library_is_one_line_before_any_render() {
    let dir = tmpdir("denoise-missing");
    let out = dir.join("x.png");
    let o = prism()
        .args(["render", "--resolution", "8x8", "--spp", "1", "--denoise", "-o"])
        .arg(&out)
        .env("PRISM_OIDN_LIB", dir.join("libOpenImageDenoise.so.2"))
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(!o.status.success());
    assert_eq!(e.lines().count(), 1, "{e}");
    if cfg!(feature = "oidn") {
        assert!(e.contains("scripts/install-oidn.sh") && e.contains("PRISM_OIDN_LIB"), "{e}");
    } else {
        assert!(e.contains("`oidn` feature"), "{e}");
    }
    assert!(!out.exists(), "nothing is rendered without the library");
}
