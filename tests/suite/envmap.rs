//! The environment-map light: χ² test of its importance sampling (smooth maps and a sharp bright
//! spot), E = πL from a constant map under every direct-lighting strategy, pbrt's "illuminance"
//! on an upward patch, and the example scene `scenes/envmap.pbrt` with its committed map.

use crate::common::test_settings;
use glam::{Mat3, Vec3};
use prism::accel::AccelKind;
use prism::image::Image;
use prism::integrator::{DirectStrategy, Integrator};
use prism::light::photometry::lumens_per_unit_y;
use prism::light::{EnvMapLight, Light};
use prism::math::PI;
use prism::measure::irradiance;
use prism::pbrt::{parse_file, parse_str};
use prism::sampling::chi2::{Chi2Test, Domain};
use prism::scene::{Scene, SceneBuilder};
use prism::spectrum::ColorSpace;
use std::path::{Path, PathBuf};

fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [f32; 3]) -> Image {
    let mut img = Image::new(w, h, 3);
    for y in 0..h {
        for x in 0..w {
            let o = ((y * w + x) * 3) as usize;
            img.data[o..o + 3].copy_from_slice(&f(x, y));
        }
    }
    img
}

/// The example sky: a blue-to-white gradient above the horizon, brown ground below, and a small
/// warm sun of 2×2 texels 30° above the horizon.
fn sky(w: u32, h: u32) -> Image {
    image(w, h, |x, y| {
        let theta = PI * (y as f32 + 0.5) / h as f32;
        if (w / 8..w / 8 + 2).contains(&x) && (h / 3 - 1..h / 3 + 1).contains(&y) {
            return [400.0, 350.0, 260.0];
        }
        if theta < PI / 2.0 {
            let t = theta / (PI / 2.0);
            [0.25 + 0.6 * t, 0.45 + 0.45 * t, 1.0]
        } else {
            [0.12, 0.09, 0.06]
        }
    })
}

fn chi2(light: &EnvMapLight, what: &str, tests: usize) {
    let t = Chi2Test { sample_count: 300_000, test_count: tests, domain: Domain::SPHERE, ..Chi2Test::default() };
    let r = t.run(|_, u| light.sample_direction(u).map(|(d, _)| d), |d| light.pdf_li(d));
    assert!(r.passed, "{what}: {r}");
}

#[test]
fn importance_sampling_matches_its_density_chi2() {
    let srgb = ColorSpace::srgb();
    let rot = Mat3::from_rotation_x(0.7) * Mat3::from_rotation_z(0.3);
    let gradient = image(32, 16, |x, y| [1.0 + x as f32 * 0.1, 0.5 + y as f32, 0.2]);
    // A dark map with one texel 10⁴ times brighter near the horizon and one at the pole. (At 10⁶
    // a dark texel's probability, ~10⁻⁸, is below the 2⁻²⁴ step of an f32 sample u, so light
    // sampling never picks it and χ² would count 0 against a tiny expectation; the CDF is f64 and
    // exact, and BSDF sampling with MIS still reaches those directions.) The
    // maps with sharp features have 160 × 80 texels, one per χ² cell, so the cells' expected
    // counts need no quadrature across a 10⁶ step (the harness integrates with adaptive Simpson).
    let spot =
        image(160, 80, |x, y| if (x, y) == (100, 42) || (x, y) == (5, 0) { [100.0, 200.0, 50.0] } else { [0.01; 3] });
    let cases = [
        ("gradient", EnvMapLight::new(&gradient, Mat3::IDENTITY, 1.0, srgb)),
        ("gradient rotated", EnvMapLight::new(&gradient, rot, 1.0, srgb)),
        ("bright spot", EnvMapLight::new(&spot, Mat3::IDENTITY, 1.0, srgb)),
        ("sky", EnvMapLight::new(&sky(160, 80), Mat3::IDENTITY, 1.0, srgb)),
    ];
    for (what, light) in &cases {
        chi2(light, what, cases.len());
    }
}

#[test]
fn importance_sampling_puts_the_samples_on_the_bright_spot() {
    // The sampler must concentrate on the spot: with one texel of 10⁶× the rest carrying ~99.9 %
    // of the importance, nearly every sample lands in its solid angle.
    let spot = image(64, 32, |x, y| if (x, y) == (40, 17) { [1e4; 3] } else { [0.01; 3] });
    let light = EnvMapLight::new(&spot, Mat3::IDENTITY, 1.0, ColorSpace::srgb());
    let mut rng = prism::sampling::Rng::new(3, 0);
    let n = 10_000;
    let hits = (0..n)
        .filter_map(|_| light.sample_direction(glam::Vec2::new(rng.uniform(), rng.uniform())))
        .filter(|(d, _)| {
            let theta = d.z.acos();
            let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
            ((phi / (2.0 * PI) * 64.0) as u32, (theta / PI * 32.0) as u32) == (40, 17)
        })
        .count();
    assert!(hits as f64 > 0.99 * n as f64, "{hits} of {n} samples on the spot");
}

fn builder_with(light: Light) -> Scene {
    let mut b = SceneBuilder::new();
    b.set_camera(prism::camera::Camera::look_at(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y), 45.0);
    b.add_light(light);
    b.build(AccelKind::Obvhs).unwrap()
}

#[test]
fn constant_map_gives_e_equal_pi_l_with_every_strategy() {
    // RGB (0.5, 0.5, 0.5) is the space's white at luminance Y = 0.5, so the illuminance on any
    // unoccluded patch is E_v = π · 0.5 · K_m ∫ȳ dλ [lux], in either layout: equirectangular
    // (16 × 8) and equal-area (16 × 16).
    let expected = (PI * 0.5 * lumens_per_unit_y()) as f64;
    for grey in [image(16, 8, |_, _| [0.5; 3]), crate::equal_area_envmap::equal_area_map(16, |_, _, _| [0.5; 3])] {
        let light = EnvMapLight::new(&grey, Mat3::from_rotation_y(0.4), 1.0, ColorSpace::srgb());
        let layout = light.layout();
        let scene = builder_with(Light::EnvMap(light));
        for strategy in [DirectStrategy::Mis, DirectStrategy::LightOnly, DirectStrategy::BsdfOnly] {
            let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
            for n in [Vec3::Z, Vec3::new(0.3, -0.8, 0.2)] {
                let m = irradiance(&scene, &integ, Vec3::ZERO, n, 20_000, 11);
                let e = m.illuminance;
                assert!(
                    (e.mean - expected).abs() <= 3.0 * e.std_err + 1e-4 * expected,
                    "{layout:?} {strategy:?} n={n}: {} ± {} lux vs πL = {expected}",
                    e.mean,
                    e.std_err
                );
            }
        }
    }
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn load(text: &str) -> Scene {
    let opts = prism::pbrt::ParseOptions { base_dir: Some(scenes()), ..Default::default() };
    let (desc, mut warnings) = parse_str(text, &opts).unwrap();
    let (b, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    b.build(AccelKind::Obvhs).unwrap()
}

#[test]
fn illuminance_and_lux_set_the_upward_patch_as_pbrt_v4_and_si_say() {
    // On an equirectangular map (prism's layout; pbrt-v4's square maps get twice, see
    // equal_area_envmap.rs) "illuminance" q scales the light so that a patch facing +z (the
    // map's zenith) reads Y = q on its film, whatever the map holds (K_m ∫ȳ dλ · q lux);
    // prism's "lux" q gives it q lux.
    for (param, lux) in [("illuminance", 1500.0 * lumens_per_unit_y() as f64), ("lux", 1500.0)] {
        let scene = load(&format!(
            r#"Camera "perspective" WorldBegin
            LightSource "infinite" "string filename" "textures/sky.exr" "float {param}" 1500"#
        ));
        let integ = Integrator { max_depth: 1, ..Default::default() };
        let e = irradiance(&scene, &integ, Vec3::ZERO, Vec3::Z, 40_000, 2).illuminance;
        assert!((e.mean - lux).abs() <= 3.0 * e.std_err, "{param}: {} ± {} lux vs {lux}", e.mean, e.std_err);
    }
}

#[test]
fn committed_sky_map_is_the_generated_one() {
    // Rewrite with PRISM_REGEN_MESHES=1 (same switch as the example meshes).
    let path = scenes().join("textures/sky.exr");
    let sky = sky(64, 32);
    if std::env::var_os("PRISM_REGEN_MESHES").is_some() {
        prism::image::write(&path, &sky).unwrap();
    }
    let read = prism::image::read(&path).unwrap();
    assert_eq!((read.width, read.height), (sky.width, sky.height));
    let worst = read.data.iter().zip(&sky.data).map(|(a, b)| (a - b).abs() / b.abs().max(1e-3)).fold(0.0, f32::max);
    assert!(worst < 1e-3, "committed map differs from the generator by {worst}");
}

#[test]
fn envmap_scene_renders_without_nans_and_shows_the_sky() {
    let path = scenes().join("envmap.pbrt");
    let (desc, mut warnings) = parse_file(&path, &Default::default()).unwrap();
    let (b, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let scene = b.build(AccelKind::Obvhs).unwrap();
    let s = test_settings((48, 32), 8, 1, 3);
    let (film, stats) = prism::render::render(&scene, &s, |_| {}).unwrap();
    assert_eq!(stats.nonfinite, 0);
    // The top row sees the sky (bluish: Z > Y... in XYZ a blue sky has z/y > 1), the bottom row
    // the lit floor.
    let top = film.xyz(24, 0);
    assert!(top.y > 0.2 && top.z > top.y, "sky pixel {top}");
    let bottom = film.xyz(24, 31);
    assert!(bottom.y > 0.01, "floor pixel {bottom}");
}
