//! The estimators that start paths at the lights (`lightpath`, `bdpt`, `mlt`) against the path
//! tracer: the same scene must converge to the same image. Each image is cut into blocks; per
//! block, and over the whole image, the mean over independent renders (seeds) and its standard
//! error are measured, and the two estimators must agree within 4 standard errors of their
//! difference.

use crate::common::test_settings;
use prism::accel::AccelKind;
use prism::film::Film;
use prism::integrator::{Integrator, IntegratorKind, Mlt, StrategyImageKind};
use prism::render::render;
use prism::scene::{Scene, SceneBuilder};

/// Side of the square image [pixels] and of the blocks compared [pixels].
const SIZE: u32 = 32;
const BLOCK: u32 = 8;

/// Per block of the image, the mean luminance Y over `seeds` renders of `scene` by `kind`
/// (`spp` samples per pixel, paths of at most `max_depth` bounces) and its standard error.
pub(super) fn block_means(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u64,
    max_depth: u32,
    seeds: u64,
) -> Vec<(f64, f64)> {
    let blocks = (SIZE / BLOCK) as usize;
    // The blocks, then the whole image (whose smaller error catches a scale error).
    let mut per_seed = vec![Vec::new(); blocks * blocks + 1];
    for seed in 0..seeds {
        let mut settings = test_settings((SIZE, SIZE), spp, 1000 + seed, max_depth);
        // (mlt: fewer chains than pbrt-v4's default, for a small image.)
        let mlt = Mlt { chains: 64, ..Default::default() };
        settings.integrator = Integrator { kind, max_depth, mlt, ..Default::default() }.for_scene(scene);
        assert_eq!(settings.integrator.kind, kind, "the scene falls back to another estimator");
        let (film, stats) = render(scene, &settings, |_| {}).unwrap();
        assert_eq!(stats.nonfinite, 0);
        let mut sums = vec![0.0f64; blocks * blocks];
        for y in 0..SIZE {
            for x in 0..SIZE {
                sums[(y / BLOCK) as usize * blocks + (x / BLOCK) as usize] += film.xyz(x, y).y as f64;
            }
        }
        for (b, s) in sums.iter().enumerate() {
            per_seed[b].push(s / (BLOCK * BLOCK) as f64);
        }
        per_seed[blocks * blocks].push(sums.iter().sum::<f64>() / (SIZE * SIZE) as f64);
    }
    per_seed
        .iter()
        .map(|v| {
            let n = v.len() as f64;
            let mean = v.iter().sum::<f64>() / n;
            let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
            (mean, (var / n).sqrt())
        })
        .collect()
}

/// Asserts that `kind` and the path tracer render `scene` alike, block by block.
fn agrees_with_path(scene: &Scene, kind: IntegratorKind, spp: (u64, u64), max_depth: u32) {
    let reference = block_means(scene, IntegratorKind::Path, spp.0, max_depth, 8);
    let tested = block_means(scene, kind, spp.1, max_depth, 8);
    for (b, ((m0, s0), (m1, s1))) in reference.iter().zip(&tested).enumerate() {
        let sigma = (s0 * s0 + s1 * s1).sqrt();
        assert!(
            (m0 - m1).abs() <= 4.0 * sigma + 1e-6 * m0.abs(),
            "{kind:?}, block {b}: {m1:.5} ± {s1:.5} vs path {m0:.5} ± {s0:.5} ({:.1}σ)",
            (m0 - m1).abs() / sigma
        );
    }
}

fn cornell() -> Scene {
    SceneBuilder::cornell_box().build(AccelKind::Obvhs).unwrap()
}

#[test]
fn light_tracing_renders_the_cornell_box_as_path_tracing_does() {
    agrees_with_path(&cornell(), IntegratorKind::LightPath, (16, 16), 5);
}

#[test]
fn bidirectional_path_tracing_renders_the_cornell_box_as_path_tracing_does() {
    agrees_with_path(&cornell(), IntegratorKind::Bdpt, (16, 8), 5);
}

#[test]
fn metropolis_light_transport_renders_the_cornell_box_as_path_tracing_does() {
    // 16 mutations per pixel; the seeds' images differ in their bootstrap (b) as well as in
    // their chains, so the measured standard error covers both.
    agrees_with_path(&cornell(), IntegratorKind::Mlt, (16, 16), 5);
}

/// pbrt-v4's mlt parameters read from the file: a render of 6×6 pixels × 4 mutations with 8
/// chains, bit-identical with 1 and 2 threads.
#[test]
fn metropolis_light_transport_is_the_same_image_for_any_thread_count() {
    let dir = crate::common::tmpdir("mlt-threads");
    let scene = small_mlt_scene(&dir);
    let render = |threads: &str| {
        let out = dir.join(format!("t{threads}.exr"));
        let o = crate::common::prism()
            .args(["render", scene.to_str().unwrap(), "--threads", threads, "-o", out.to_str().unwrap()])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{stderr}");
        assert!(stderr.contains("24x24 4 spp"), "{stderr}");
        prism::image::read(&out).unwrap().data
    };
    let one = render("1");
    assert!(one.iter().any(|&v| v > 0.0));
    assert!(one == render("2"), "the image depends on the thread count");
}

/// [`GLOSSY`] for pbrt-v4's mlt, written to `dir`: 24×24 pixels, paths of up to 3 bounces,
/// 2000 bootstrap paths per depth, 8 chains, 4 mutations per pixel.
fn small_mlt_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let scene = dir.join("mlt.pbrt");
    let text = GLOSSY.replace(
        "WorldBegin",
        "Integrator \"mlt\" \"integer maxdepth\" [3] \"integer bootstrapsamples\" [2000] \"integer chains\" [8]\n\
         \"integer mutationsperpixel\" [4] \"float sigma\" [0.02]\nFilm \"rgb\" \"integer xresolution\" [24] \
         \"integer yresolution\" [24] \"bool savefp16\" false\nWorldBegin",
    );
    std::fs::write(&scene, text).unwrap();
    scene
}

/// The bootstrap reports its progress before the chains' first: in a log (stderr not a
/// terminal) a line when it starts and one when all 2000 × 4 depths' paths are made.
#[test]
fn metropolis_light_transport_reports_its_bootstrap_progress() {
    let dir = crate::common::tmpdir("mlt-bootstrap-progress");
    let scene = small_mlt_scene(&dir);
    let out = dir.join("out.exr");
    let o =
        crate::common::prism().args(["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{stderr}");
    let start = stderr.find("mlt bootstrap 0/8000 paths").expect(&stderr);
    let end = stderr.find("mlt bootstrap 8000/8000 paths").expect(&stderr);
    let render = stderr.find("24x24 4 spp").expect(&stderr);
    assert!(start < end && end < render, "{stderr}");
}

/// A rough gold sphere and a diffuse one on a diffuse floor under a small quad light: glossy
/// reflections of the light and of the lit floor, which the strategies sample very
/// differently.
const GLOSSY: &str = r#"
LookAt 0 1.2 -4  0 0.6 0  0 1 0
Camera "perspective" "float fov" [40]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "spectrum L" [300 30 900 30]
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
      "point3 P" [-0.3 3 -0.3  0.3 3 -0.3  0.3 3 0.3  -0.3 3 0.3]
AttributeEnd
Material "diffuse" "spectrum reflectance" [300 0.6 900 0.6]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-5 0 -5  -5 0 5  5 0 5  5 0 -5]
AttributeBegin
  Material "conductor" "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k" "float roughness" [0.15]
  Translate -0.55 0.5 0
  Shape "sphere" "float radius" [0.5]
AttributeEnd
AttributeBegin
  Material "diffuse" "spectrum reflectance" [300 0.3 900 0.3]
  Translate 0.6 0.4 0.2
  Shape "sphere" "float radius" [0.4]
AttributeEnd
"#;

#[test]
fn bidirectional_path_tracing_renders_glossy_reflections_as_path_tracing_does() {
    let scene = crate::common::pbrt_scene(GLOSSY, AccelKind::Obvhs);
    agrees_with_path(&scene, IntegratorKind::Bdpt, (32, 16), 4);
}

/// A two-sided quad light between a floor and a ceiling: each side lights one of them, so a
/// strategy that loses the back side (a light point drawn with a direction at the horizon)
/// renders the ceiling dark.
const TWO_SIDED: &str = r#"
LookAt 0 1 -3.5  0 1 0  0 1 0
Camera "perspective" "float fov" [50]
WorldBegin
Material "diffuse" "rgb reflectance" [0.6 0.6 0.6]
Shape "trianglemesh" "point3 P" [-2 0 -2  2 0 -2  2 0 2  -2 0 2] "integer indices" [0 1 2 0 2 3]
Shape "trianglemesh" "point3 P" [-2 2 -2  2 2 -2  2 2 2  -2 2 2] "integer indices" [0 2 1 0 3 2]
Shape "trianglemesh" "point3 P" [-2 0 2  2 0 2  2 2 2  -2 2 2] "integer indices" [0 1 2 0 2 3]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4] "bool twosided" true
  Translate 0 1 0.5
  Shape "trianglemesh" "point3 P" [-0.3 0 -0.3  0.3 0 -0.3  0.3 0 0.3  -0.3 0 0.3] "integer indices" [0 1 2 0 2 3]
AttributeEnd
"#;

#[test]
fn bidirectional_path_tracing_sees_both_sides_of_a_two_sided_light() {
    let scene = crate::common::pbrt_scene(TWO_SIDED, AccelKind::Obvhs);
    agrees_with_path(&scene, IntegratorKind::Bdpt, (16, 8), 3);
}

/// A diffuse plane of reflectance ρ = 0.5 at z = 0 lit by a point light of constant intensity
/// I at height h = 1, seen from above: the radiance it reflects at horizontal distance r from
/// below the light is L = (ρ/π) I h / (r² + h²)^{3/2}, in closed form. Light tracing (t = 1)
/// and light sampling (s = 1) both find it.
const LIT_PLANE: &str = r#"
LookAt 0 0 3  0 0 0  0 1 0
Camera "perspective" "float fov" [60]
WorldBegin
LightSource "point" "point3 from" [0 0 1] "spectrum I" [300 1 900 1]
Material "diffuse" "spectrum reflectance" [300 0.5 900 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-100 -100 0  100 -100 0  100 100 0  -100 100 0]
"#;

/// The same camera seeing an emitter of radiance 1 (the same constant spectrum): the
/// luminance a radiance of 1 gives.
const UNIT_EMITTER: &str = r#"
LookAt 0 0 3  0 0 0  0 1 0
Camera "perspective" "float fov" [60]
WorldBegin
AreaLightSource "diffuse" "spectrum L" [300 1 900 1]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-100 -100 0  100 -100 0  100 100 0  -100 100 0]
"#;

/// The mean over six seeds of the image's luminance from `scene` by `kind` (16 spp, paths of
/// at most `max_depth` bounces) in units of `y_unit`, with its standard error.
fn image_mean(scene: &Scene, kind: IntegratorKind, max_depth: u32, y_unit: f64) -> (f64, f64) {
    let size = 16u32;
    let means: Vec<f64> = (0..6)
        .map(|seed| {
            let mut settings = test_settings((size, size), 16, seed, max_depth);
            settings.integrator = Integrator { kind, max_depth, ..Default::default() }.for_scene(scene);
            assert_eq!(settings.integrator.kind, kind, "the scene falls back to another estimator");
            let (film, stats) = render(scene, &settings, |_| {}).unwrap();
            assert_eq!(stats.nonfinite, 0);
            let mut sum = 0.0;
            for y in 0..size {
                for x in 0..size {
                    sum += film.xyz(x, y).y as f64;
                }
            }
            sum / (size * size) as f64 / y_unit
        })
        .collect();
    let n = means.len() as f64;
    let mean = means.iter().sum::<f64>() / n;
    (mean, (means.iter().map(|m| (m - mean) * (m - mean)).sum::<f64>() / (n - 1.0) / n).sqrt())
}

/// The luminance of radiance 1 seen by [`UNIT_EMITTER`]'s camera.
fn unit_luminance() -> f64 {
    let unit = crate::common::pbrt_scene(UNIT_EMITTER, AccelKind::Obvhs);
    let (film, _) = render(&unit, &test_settings((16, 16), 16, 1, 1), |_| {}).unwrap();
    film.xyz(8, 8).y as f64
}

/// Asserts that each of `kinds` renders `scene` with the image mean `expected` (in units of
/// radiance 1) within 4 standard errors.
fn matches_closed_form(scene: &Scene, kinds: &[IntegratorKind], max_depth: u32, expected: f64) {
    let y_unit = unit_luminance();
    for &kind in kinds {
        let (mean, se) = image_mean(scene, kind, max_depth, y_unit);
        assert!(
            (mean - expected).abs() <= 4.0 * se + 2e-3 * expected,
            "{kind:?}: {mean:.6} ± {se:.6} vs the closed form {expected:.6} ({:.1}σ)",
            (mean - expected).abs() / se
        );
    }
}

#[test]
fn light_paths_reproduce_the_closed_form_radiance_of_a_plane_under_a_point_light() {
    let lit = crate::common::pbrt_scene(LIT_PLANE, AccelKind::Obvhs);
    let size = 16u32;
    // The expected image mean of L / (radiance 1): each pixel's radiance averaged over 8×8
    // points of it, from where its rays meet the plane (the camera at height 3 looking down,
    // tan(30°) across half the image).
    let half = (30f64).to_radians().tan();
    let mut expected = 0.0;
    for py in 0..size * 8 {
        for px in 0..size * 8 {
            let sx = ((px as f64 + 0.5) / (size * 8) as f64 * 2.0 - 1.0) * half;
            let sy = ((py as f64 + 0.5) / (size * 8) as f64 * 2.0 - 1.0) * half;
            let r2 = 9.0 * (sx * sx + sy * sy);
            expected += 0.5 / std::f64::consts::PI / (r2 + 1.0).powf(1.5);
        }
    }
    expected /= (size * size * 64) as f64;
    matches_closed_form(&lit, &[IntegratorKind::Bdpt, IntegratorKind::LightPath], 1, expected);
}

/// A diffuse square of reflectance ρ = 0.5 filling the view, lit by light from infinity (the
/// `LightSource` line is `{light}`). Nothing but the sky is above it, so it never sees itself:
/// every path has one bounce, and each bidirectional strategy can make every one of them.
fn open_plane(light: &str) -> Scene {
    let text = format!(
        r#"
LookAt 0 0 3  0 0 0  0 1 0
Camera "perspective" "float fov" [60]
WorldBegin
{light}
Material "diffuse" "spectrum reflectance" [300 0.5 900 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-2 -2 0  2 -2 0  2 2 0  -2 2 0]
"#
    );
    crate::common::pbrt_scene(&text, AccelKind::Obvhs)
}

const ALL: [IntegratorKind; 3] = [IntegratorKind::Path, IntegratorKind::Bdpt, IntegratorKind::LightPath];

#[test]
fn under_a_uniform_sky_an_open_diffuse_plane_reflects_albedo_times_the_sky() {
    // E = π L from the whole upper hemisphere, so L_o = (ρ/π) E = ρ L.
    let scene = open_plane(r#"LightSource "infinite" "spectrum L" [300 1 900 1]"#);
    matches_closed_form(&scene, &ALL, 3, 0.5);
}

#[test]
fn under_a_distant_light_an_open_diffuse_plane_reflects_its_irradiance_times_the_cosine() {
    // E = 1 arriving at 60° from the normal: L_o = (ρ/π) E cos θ.
    let scene = open_plane(
        r#"LightSource "distant" "point3 from" [0 1.7320508 1] "point3 to" [0 0 0] "spectrum L" [300 1 900 1]"#,
    );
    matches_closed_form(&scene, &ALL, 3, 0.5 / std::f64::consts::PI * 0.5);
}

/// A diffuse floor and two spheres, one diffuse, one rough metal, under an image sky (the
/// committed latitude–longitude map with its bright sun), seen from above so that the camera
/// sees no sky (light tracing does not show lights at infinity).
const IMAGE_SKY: &str = r#"
LookAt 0 4 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
WorldBegin
AttributeBegin
  Rotate -90 1 0 0
  LightSource "infinite" "string filename" "textures/sky.exr" "float scale" [0.5]
AttributeEnd
Material "diffuse" "spectrum reflectance" [300 0.6 900 0.6]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-6 0 -6  -6 0 6  6 0 6  6 0 -6]
AttributeBegin
  Material "conductor" "spectrum eta" "metal-Cu-eta" "spectrum k" "metal-Cu-k" "float roughness" [0.2]
  Translate -0.6 0.5 0
  Shape "sphere" "float radius" [0.5]
AttributeEnd
AttributeBegin
  Material "diffuse" "spectrum reflectance" [300 0.4 900 0.4]
  Translate 0.6 0.4 0.3
  Shape "sphere" "float radius" [0.4]
AttributeEnd
"#;

#[test]
fn under_an_image_sky_light_paths_render_as_path_tracing_does() {
    let opts = prism::pbrt::ParseOptions {
        base_dir: Some(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")),
        ..Default::default()
    };
    let (desc, mut warnings) = prism::pbrt::parse_str(IMAGE_SKY, &opts).unwrap();
    let (builder, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    let scene = builder.build(AccelKind::Obvhs).unwrap();
    agrees_with_path(&scene, IntegratorKind::Bdpt, (16, 8), 4);
    agrees_with_path(&scene, IntegratorKind::LightPath, (16, 16), 4);
}

/// A strategy (depth, s, t) and its image.
type StrategyFilm = ((usize, usize, usize), Film);

/// bdpt's strategy images (`visualizeweights`, `visualizestrategies`) of the open plane under a
/// uniform sky at depths 0 … 2, rendered with `seed`: the main film and each strategy's.
fn strategy_films(kind: StrategyImageKind, seed: u64) -> (Film, Vec<StrategyFilm>) {
    let scene = open_plane(r#"LightSource "infinite" "spectrum L" [300 1 900 1]"#);
    let mut settings = test_settings((16, 16), 16, seed, 2);
    settings.integrator =
        Integrator { kind: IntegratorKind::Bdpt, max_depth: 2, strategy_images: kind, ..Default::default() };
    let (film, _) = render(&scene, &settings, |_| {}).unwrap();
    let images = film.strategies.as_ref().expect("strategy images").strategies().collect::<Vec<_>>();
    let films = images.into_iter().map(|(d, s, t)| ((d, s, t), film.strategy_film(s, t).unwrap())).collect();
    (film, films)
}

#[test]
fn weighted_strategy_images_of_a_depth_sum_to_the_light_of_that_depth() {
    // The camera sees only the plane and the plane never sees itself: all the image's light
    // has depth 1, so the weighted depth-1 images sum to the image (rounding apart: each
    // contribution is recorded on its own) and the others are black.
    let (film, strategies) = strategy_films(StrategyImageKind::Weighted, 5);
    assert_eq!(strategies.iter().filter(|((d, _, _), _)| *d == 1).count(), 3);
    for y in 0..16 {
        for x in 0..16 {
            let main = film.xyz(x, y).y as f64;
            let mut depth1 = 0.0;
            for ((depth, s, t), f) in &strategies {
                let v = f.xyz(x, y).y as f64;
                if *depth == 1 {
                    depth1 += v;
                } else {
                    assert_eq!(v, 0.0, "depth {depth}, ({s}, {t}) at ({x}, {y})");
                }
            }
            assert!((depth1 - main).abs() <= 1e-5 * main, "({x}, {y}): Σ strategies {depth1} vs the image {main}");
        }
    }
}

#[test]
fn each_unweighted_strategy_image_alone_estimates_the_light_of_its_depth() {
    // s = 0 (the camera path finds the sky), s = 1 (light sampling) and s = 2, t = 1 (light
    // tracing) each see the whole of ρ L = 0.5 without their weights.
    let y_unit = unit_luminance();
    let runs: Vec<_> = (0..6).map(|seed| strategy_films(StrategyImageKind::Unweighted, 20 + seed).1).collect();
    for (k, ((depth, s, t), _)) in runs[0].iter().enumerate().filter(|(_, ((d, _, _), _))| *d == 1) {
        let means: Vec<f64> = runs
            .iter()
            .map(|films| {
                let f = &films[k].1;
                (0..16).flat_map(|y| (0..16).map(move |x| (x, y))).map(|(x, y)| f.xyz(x, y).y as f64).sum::<f64>()
                    / 256.0
                    / y_unit
            })
            .collect();
        let n = means.len() as f64;
        let mean = means.iter().sum::<f64>() / n;
        let se = (means.iter().map(|m| (m - mean) * (m - mean)).sum::<f64>() / (n - 1.0) / n).sqrt();
        assert!(
            (mean - 0.5).abs() <= 4.0 * se + 1e-3,
            "depth {depth}, ({s}, {t}): {mean:.5} ± {se:.5} vs ρ L = 0.5 ({:.1}σ)",
            (mean - 0.5).abs() / se
        );
    }
}

#[test]
fn splatting_estimators_give_one_image_for_any_thread_count_and_for_merged_parts() {
    // Light-tracing splats land on any pixel: the image must not depend on which thread or
    // which part rendered a sample, and `prism merge` of two parts is the whole render.
    use crate::common::{prism, stderr, tmpdir};
    let d = tmpdir("splat-parts");
    let scene = d.join("s.pbrt");
    std::fs::write(
        &scene,
        "LookAt 0 1 4  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\nWorldBegin\n\
         AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4 4 4]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [-0.4 2 -0.4  0.4 2 -0.4  0.4 2 0.4  -0.4 2 0.4]\n\
         AttributeEnd\nMaterial \"diffuse\" \"rgb reflectance\" [0.6 0.5 0.4]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point3 P\" [-3 0 -3  -3 0 3  3 0 3  3 0 -3]\n\
         Shape \"sphere\" \"float radius\" 0.5\n",
    )
    .unwrap();
    let run = |args: &[&str]| {
        let o = prism().arg("render").arg(&scene).args(args).output().unwrap();
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    };
    for integrator in ["bdpt", "lightpath"] {
        let path = |name: &str| d.join(format!("{integrator}-{name}")).to_str().unwrap().to_string();
        let common = ["--integrator", integrator, "--spp", "4", "--resolution", "24x16", "--accel", "obvhs"];
        for threads in ["1", "2"] {
            run(&[&common[..], &["--threads", threads, "-o", &path(&format!("t{threads}.exr"))]].concat());
        }
        let (one, two) = (path("t1.exr"), path("t2.exr"));
        let (a, b) = (prism::image::read(one.as_ref()).unwrap(), prism::image::read(two.as_ref()).unwrap());
        assert!(a.data.iter().any(|&v| v > 0.01), "{integrator}: black image");
        assert_eq!(a.data, b.data, "{integrator}: one and two threads differ");
        for i in 1..=2 {
            run(&[&common[..], &["--part", &format!("{i}/2"), "-o", &path(&format!("p{i}.film"))]].concat());
        }
        let merged = path("merged.exr");
        let o = prism().arg("merge").args([path("p1.film"), path("p2.film")]).args(["-o", &merged]).output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        let m = prism::image::read(merged.as_ref()).unwrap();
        // The same samples summed in another grouping, stored as half floats.
        for (x, y) in a.data.iter().zip(&m.data) {
            assert!((x - y).abs() <= 1e-3 * x.abs().max(1e-2), "{integrator}: whole {x} vs merged parts {y}");
        }
    }
}
