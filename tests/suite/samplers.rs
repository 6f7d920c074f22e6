//! pbrt-v4's samplers in whole renders: each estimates the same image as prism's Sobol sampler,
//! and renders are bit-identical for any thread count and when split into sample ranges.

use crate::common::test_settings;
use prism::accel::AccelKind;
use prism::film::Film;
use prism::render::{render, render_range, RenderSettings, SamplerKind};
use prism::sampling::Randomize;
use prism::scene::{Scene, SceneBuilder};
use std::sync::atomic::AtomicBool;

fn kinds() -> Vec<SamplerKind> {
    vec![
        SamplerKind::ZSobol(Randomize::FastOwen),
        SamplerKind::ZSobol(Randomize::Owen),
        SamplerKind::GlobalSobol(Randomize::FastOwen),
        SamplerKind::GlobalSobol(Randomize::None),
        SamplerKind::PaddedSobol(Randomize::PermuteDigits),
        SamplerKind::Halton(Randomize::PermuteDigits),
        SamplerKind::Halton(Randomize::Owen),
        SamplerKind::Pmj02bn,
        SamplerKind::Stratified { x: 4, y: 4, jitter: true },
        SamplerKind::Independent,
    ]
}

fn cornell() -> Scene {
    SceneBuilder::cornell_box().build(AccelKind::Obvhs).unwrap()
}

/// The image's mean Y.
fn mean_y(film: &Film) -> f64 {
    let n = (film.width * film.height) as f64;
    (0..film.height)
        .flat_map(|y| (0..film.width).map(move |x| (x, y)))
        .map(|(x, y)| film.xyz(x, y).y as f64)
        .sum::<f64>()
        / n
}

/// Mean and standard error of the image mean over renders with seeds 1..=`seeds`.
fn mean_over_seeds(scene: &Scene, kind: SamplerKind, seeds: u64) -> (f64, f64) {
    let means: Vec<f64> = (1..=seeds)
        .map(|seed| {
            let s = RenderSettings { sampler: kind, ..test_settings((24, 24), 16, seed, 5) };
            mean_y(&render(scene, &s, |_| {}).unwrap().0)
        })
        .collect();
    let n = means.len() as f64;
    let m = means.iter().sum::<f64>() / n;
    let var = means.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

#[test]
fn every_sampler_estimates_the_image_prisms_sobol_does() {
    // 12 renders of 24×24 pixels at 16 samples per sampler; the means of the image means must
    // agree within 4 combined standard errors (measured over the seeds).
    let scene = cornell();
    let (reference, ref_se) = mean_over_seeds(&scene, SamplerKind::Sobol, 12);
    assert!(reference > 0.0 && ref_se > 0.0 && ref_se < 0.02 * reference, "{reference} ± {ref_se}");
    for kind in kinds() {
        let (m, se) = mean_over_seeds(&scene, kind, 12);
        let tolerance = 4.0 * (se * se + ref_se * ref_se).sqrt();
        assert!((m - reference).abs() < tolerance, "{kind:?}: {m} ± {se} vs Sobol {reference} ± {ref_se}");
    }
}

#[test]
fn renders_split_into_sample_ranges_or_threads_add_up_to_the_whole() {
    let scene = cornell();
    for kind in kinds() {
        let s = RenderSettings { sampler: kind, ..test_settings((16, 12), 8, 3, 4) };
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let (whole, _) = one.install(|| render(&scene, &s, |_| {}).unwrap());
        let (again, _) = two.install(|| render(&scene, &s, |_| {}).unwrap());
        assert!(whole.pixels == again.pixels, "{kind:?}: thread count changed the image");
        let never = AtomicBool::new(false);
        let (mut a, mut b) = (Film::new(16, 12), Film::new(16, 12));
        render_range(&scene, &s, &mut a, 0..3, &never, |_, _| true);
        render_range(&scene, &s, &mut b, 3..8, &never, |_, _| true);
        a.merge(&b);
        for (p, q) in a.pixels.iter().zip(&whole.pixels) {
            assert_eq!(p.samples, q.samples);
            let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1e-30);
            assert!(close(p.xyz_sum.y, q.xyz_sum.y) && close(p.weight_sum, q.weight_sum), "{kind:?}");
        }
    }
}
