//! pbrt-v4's clouds scene end to end: it parses and renders with media. Its sky map is not in
//! the scene collection, so the test replaces the image light by a uniform sky of radiance 1.
//! The cloud scatters (σ_s = 10) and barely absorbs (σ_a = 0.01) and the file has no other
//! geometry, so the image is nearly a furnace: no pixel may be brighter than the sky, and the
//! cloud, whose optical depth is tens, darkens only by its small absorption.

use crate::common::test_settings;
use prism::accel::AccelKind;
use prism::light::{Light, UniformInfiniteLight};
use prism::pbrt::{self, parse_file, ParseOptions};
use prism::spectrum::Spectrum;
use std::path::Path;
use std::sync::Arc;

#[test]
fn pbrt_v4_clouds_scene_renders_under_a_uniform_sky() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/pbrt-v4-scenes/clouds/clouds.pbrt");
    if !path.exists() {
        eprintln!("skipped: {} is not beside the repository", path.display());
        return;
    }
    let (mut desc, mut warnings) = parse_file(&path, &ParseOptions::default()).unwrap();
    let before = desc.lights.len();
    desc.lights.retain(|l| l.kind != "infinite");
    assert_eq!(before - desc.lights.len(), 1, "the file's sky");
    let (mut b, settings) = pbrt::build(&desc, &mut warnings).unwrap();
    b.add_light(Light::UniformInfinite(UniformInfiniteLight {
        spectrum: Arc::new(Spectrum::constant(1.0)),
        scale: 1.0,
    }));
    let scene = b.build(AccelKind::default_available()).unwrap();
    assert_eq!(scene.media().len(), 1, "the cloud");
    let max_depth = settings.max_depth.unwrap();
    assert_eq!(max_depth, 50);
    let (w, h) = (32, 18);
    let (film, stats) = prism::render::render(&scene, &test_settings((w, h), 32, 7, max_depth), |_| {}).unwrap();
    assert_eq!(stats.nonfinite, 0);
    // The sky's Y, from a ray that misses the cloud.
    let y: Vec<f64> = film.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect();
    let sky = y.iter().cloned().fold(0.0, f64::max);
    assert!(sky > 0.0, "the image is black");
    let darkest = y.iter().cloned().fold(f64::INFINITY, f64::min);
    eprintln!("clouds: sky Y {sky:.4}, darkest pixel Y {darkest:.4}");
    assert!(darkest > 0.5 * sky, "darkest pixel {darkest} vs sky {sky}: a nearly white cloud cannot be dark");
    assert!(darkest < 0.995 * sky, "the cloud absorbs a little: {darkest} vs {sky}");
}
