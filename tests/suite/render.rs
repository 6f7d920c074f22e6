//! End-to-end renders of small scenes: analytic answers, determinism, no non-finite samples.

use crate::common::{film_difference, test_settings};
use glam::Vec3;
use prism::accel::AccelKind;
use prism::camera::Camera;
use prism::film::Film;
use prism::geometry::shapes::icosphere;
use prism::integrator::Stats;
use prism::material::Material;
use prism::render::{render, RenderSettings, SamplerKind};
use prism::scene::{Emission, Scene, SceneBuilder};
use prism::spectrum::Spectrum;

fn settings(res: u32, spp: u64, max_depth: u32) -> RenderSettings {
    test_settings((res, res), spp, 1, max_depth)
}

fn accels() -> Vec<AccelKind> {
    let mut v = vec![AccelKind::Obvhs];
    if cfg!(embree) {
        v.push(AccelKind::Embree);
    }
    v
}

/// Mean and standard error of the pixels' Y (each pixel an independent estimate).
fn mean_y(film: &Film) -> (f64, f64) {
    let ys: Vec<f64> = (0..film.height)
        .flat_map(|y| (0..film.width).map(move |x| (x, y)))
        .map(|(x, y)| film.xyz(x, y).y as f64)
        .collect();
    let n = ys.len() as f64;
    let m = ys.iter().sum::<f64>() / n;
    let var = ys.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// A camera inside a closed sphere whose surface reflects ρ and emits L: every ray sees
/// L (1 + ρ + ρ² + …) = L / (1 − ρ) (the rendered furnace test).
#[test]
fn rendered_furnace_matches_geometric_series() {
    for accel in accels() {
        for (rho, le) in [(0.5f32, 1.0f32), (0.8, 0.25)] {
            let mut b = SceneBuilder::new();
            let m = b.add_material(Material::diffuse(Spectrum::constant(rho)));
            let em = Emission { spectrum: Spectrum::constant(1.0), scale: le, two_sided: true };
            b.add_mesh(icosphere(Vec3::ZERO, 1.0, 3), m, Some(em));
            b.set_camera(Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y), 60.0);
            let scene = b.build(accel).unwrap();
            let (film, stats) = render(&scene, &settings(32, 16, 200), |_| {}).unwrap();
            assert_eq!(stats.nonfinite, 0);
            let (m, se) = mean_y(&film);
            let expected = le as f64 / (1.0 - rho as f64);
            assert!(se > 0.0 && se < 0.05 * expected, "{accel:?} ρ={rho}: SE {se} (test would be weak)");
            assert!((m - expected).abs() < 4.0 * se, "{accel:?} ρ={rho}: {m} ± {se} vs {expected}");
        }
    }
}

fn cornell(accel: AccelKind) -> Scene {
    SceneBuilder::cornell_box().build(accel).unwrap()
}

fn render_with_threads(scene: &Scene, s: &RenderSettings, threads: usize) -> (Film, Stats) {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| render(scene, s, |_| {}).unwrap())
}

#[test]
fn renders_are_bit_identical_for_any_thread_count() {
    let scene = cornell(AccelKind::Obvhs);
    let mut s = settings(24, 5, 5);
    s.sampler = SamplerKind::Sobol;
    let (a, _) = render_with_threads(&scene, &s, 1);
    let (b, _) = render_with_threads(&scene, &s, 2);
    let (c, _) = render_with_threads(&scene, &s, 3);
    assert!(a.pixels == b.pixels && b.pixels == c.pixels);
    assert!(a.pixels.iter().any(|p| p.xyz_sum.y > 0.0));
}

#[test]
fn an_image_without_pixels_renders_to_an_empty_film() {
    // The library takes any size; the CLI rejects 0, but nothing below it may panic on one.
    let scene = cornell(AccelKind::Obvhs);
    for res in [(0, 0), (0, 8), (8, 0)] {
        let s = RenderSettings { resolution: res, ..settings(8, 2, 3) };
        let (film, stats) = render(&scene, &s, |_| {}).unwrap();
        assert!(film.pixels.is_empty() && stats.samples == 0, "{res:?}");
    }
}

#[test]
fn cornell_box_has_red_left_green_right_and_no_nans() {
    for accel in accels() {
        let scene = cornell(accel);
        let s = settings(32, 16, 5);
        let (film, stats) = render(&scene, &s, |_| {}).unwrap();
        assert_eq!(stats.nonfinite, 0, "{accel:?}");
        let space = prism::spectrum::ColorSpace::srgb();
        let avg = |x0: u32, x1: u32| {
            let mut acc = Vec3::ZERO;
            for y in 10..22 {
                for x in x0..x1 {
                    acc += space.xyz_to_rgb(film.xyz(x, y));
                }
            }
            acc / ((x1 - x0) * 12) as f32
        };
        let left = avg(0, 3);
        let right = avg(29, 32);
        assert!(left.x > 1.5 * left.y && left.x > 1.5 * left.z, "{accel:?} left wall not red: {left}");
        assert!(right.y > 1.2 * right.x && right.y > 1.2 * right.z, "{accel:?} right wall not green: {right}");
        let (m, _) = mean_y(&film);
        assert!(m > 0.1, "{accel:?}: image too dark ({m})");
    }
}

#[test]
fn embree_and_obvhs_render_the_same_image_within_noise() {
    if !cfg!(embree) {
        return;
    }
    let s = settings(16, 64, 5);
    let (a, sa) = render(&cornell(AccelKind::Embree), &s, |_| {}).unwrap();
    let (b, sb) = render(&cornell(AccelKind::Obvhs), &s, |_| {}).unwrap();
    assert_eq!((sa.nonfinite, sb.nonfinite), (0, 0));
    // Same seeds: pixels differ only where the two triangle tests round differently and a path
    // diverges. The per-pixel differences must average to zero within their standard error.
    let (m, se, mean) = film_difference(&a, &b);
    // A black image would pass the comparison: the box must be lit.
    assert!(mean > 0.1, "black image (mean Y {mean})");
    assert!(m.abs() <= 4.0 * se + 1e-6 * mean, "mean difference {m} ± {se}");
}

#[test]
fn cornell_box_pbrt_file_renders_like_the_built_in_scene() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.pbrt");
    let (desc, mut warnings) = prism::pbrt::parse_file(&path, &Default::default()).unwrap();
    let (builder, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let s = settings(24, 16, 5);
    let (a, sa) = render(&builder.build(AccelKind::Obvhs).unwrap(), &s, |_| {}).unwrap();
    let (b, sb) = render(&cornell(AccelKind::Obvhs), &s, |_| {}).unwrap();
    assert_eq!((sa.nonfinite, sb.nonfinite), (0, 0));
    let (m, se, mean) = film_difference(&a, &b);
    assert!(mean > 0.1, "black image");
    assert!(m.abs() <= 4.0 * se + 1e-5 * mean, "mean difference {m} ± {se}");
}
