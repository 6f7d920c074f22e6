//! The cheap form of `prism compat`'s rule, for each family prism renders as pbrt-v4 does: the
//! scene (tests/data/compat/) rendered at its own resolution with few samples has pbrt-v4's
//! channel means (REFERENCES*.json, measured on pbrt-v4's 1024-spp images) within the rule's 2%
//! plus four standard errors, with no unsupported-feature warning.

use crate::common::{prism, stderr, tmpdir};
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compat")
}

/// pbrt-v4's channel means and spp of its reference image of `scene` (e.g. "envmap.pbrt").
fn pbrt_v4_means(scene: &str) -> ([f64; 3], f64) {
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir().join(f)).unwrap()).unwrap()
    };
    let (a, b) = (read("REFERENCES.json"), read("REFERENCES-geometry.json"));
    let r = a["scenes"][scene]["references"]
        .as_array()
        .and_then(|refs| refs.iter().find(|r| r["seed"] == 1).cloned())
        .or_else(|| b["scenes"].as_array()?.iter().find(|s| s["scene"] == scene).map(|s| s["reference"].clone()))
        .unwrap_or_else(|| panic!("no pbrt-v4 reference for {scene}"));
    let m = r["mean_rgb"].as_array().unwrap();
    ([0, 1, 2].map(|k| m[k].as_f64().unwrap()), r["spp"].as_f64().unwrap())
}

/// Renders `scene` twice (seeds 1 and 2, `spp` independent samples each) and returns the
/// channel means of the two together, their standard errors (from the pixel-by-pixel
/// differences of the seeds: pixels are independent estimates), and the log of the first.
fn render_means(scene: &str, spp: u32) -> ([f64; 3], [f64; 3], String) {
    let d = tmpdir(&format!("compat-{scene}"));
    let mut images = Vec::new();
    let mut log = String::new();
    for seed in [1, 2] {
        let out = d.join(format!("{seed}.exr"));
        let o = prism()
            .arg("render")
            .arg(dir().join(scene))
            .args(["--spp", &spp.to_string(), "--sampler", "independent", "--seed", &seed.to_string(), "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{scene}: {}", stderr(&o));
        if seed == 1 {
            log = stderr(&o);
        }
        images.push(prism::image::read(&out).unwrap());
    }
    let (a, b) = (&images[0], &images[1]);
    let c = a.channels as usize;
    let n = (a.data.len() / c) as f64;
    let (mut sum, mut d2) = ([0.0f64; 3], [0.0f64; 3]);
    for (pa, pb) in a.data.chunks_exact(c).zip(b.data.chunks_exact(c)) {
        for k in 0..3 {
            let (x, y) = (f64::from(pa[k]), f64::from(pb[k]));
            sum[k] += x + y;
            d2[k] += (x - y) * (x - y);
        }
    }
    // Var(pixel) ≈ (x − y)²/2, so the mean of 2N pixel estimates has variance Σ(x − y)²/(4N²).
    let means = sum.map(|s| s / (2.0 * n));
    let se = d2.map(|s| s.sqrt() / (2.0 * n));
    std::fs::remove_dir_all(&d).ok();
    (means, se, log)
}

/// The check: no unsupported feature, and each channel mean within 2% of pbrt-v4's plus 4σ
/// (prism's standard error with that of pbrt-v4's own mean at its spp added).
fn assert_matches_pbrt_v4(scene: &str, spp: u32) {
    let (want, ref_spp) = pbrt_v4_means(scene);
    let (got, se, log) = render_means(scene, spp);
    let unsupported: Vec<&str> =
        log.lines().filter(|l| l.contains("unsupported feature") || l.contains("was not used")).collect();
    assert!(unsupported.is_empty(), "{scene}: {unsupported:#?}");
    for k in 0..3 {
        assert!(got[k] > 0.01 * want[k].max(1e-3), "{scene}: channel {k} is black ({got:?})");
        let se_ref = se[k] * (2.0 * f64::from(spp) / ref_spp).sqrt();
        let tol = 0.02 * want[k] + 4.0 * (se[k] * se[k] + se_ref * se_ref).sqrt();
        assert!(
            (got[k] - want[k]).abs() <= tol,
            "{scene}: channel {k} mean {:.5} ± {:.5} vs pbrt-v4's {:.5} (tolerance {tol:.5}); all {got:?} vs {want:?}",
            got[k],
            se[k],
            want[k]
        );
    }
}

#[test]
fn perspective_depth_of_field_has_pbrt_v4s_means() {
    assert_matches_pbrt_v4("cameras-dof.pbrt", 16);
}

#[test]
fn realistic_double_gauss_camera_has_pbrt_v4s_means() {
    // The lens's ray weights (cos⁴θ · pupil area / rear distance²) with the film's ISO set the
    // brightness; a pinhole in its place is an order of magnitude too bright.
    assert_matches_pbrt_v4("cameras-realistic.pbrt", 16);
}

#[test]
fn orthographic_and_spherical_cameras_have_pbrt_v4s_means() {
    for scene in ["cameras-ortho.pbrt", "cameras-spherical.pbrt", "cameras-equirect.pbrt"] {
        assert_matches_pbrt_v4(scene, 16);
    }
}

#[test]
fn equal_area_environment_map_has_pbrt_v4s_means() {
    assert_matches_pbrt_v4("envmap.pbrt", 16);
}

#[test]
fn point_spot_goniometric_projection_and_distant_lights_have_pbrt_v4s_means() {
    assert_matches_pbrt_v4("lights.pbrt", 16);
}

#[test]
fn two_sided_powered_textured_and_a_hundred_small_area_lights_have_pbrt_v4s_means() {
    assert_matches_pbrt_v4("lights-area.pbrt", 16);
}

#[test]
fn every_texture_type_and_mapping_has_pbrt_v4s_means() {
    assert_matches_pbrt_v4("textures.pbrt", 16);
}

#[test]
fn bump_normal_map_and_alpha_shading_has_pbrt_v4s_means() {
    assert_matches_pbrt_v4("shading.pbrt", 16);
}

#[test]
fn coated_conductor_and_diffuse_mix_dielectric_and_interface_materials_have_pbrt_v4s_means() {
    assert_matches_pbrt_v4("materials.pbrt", 16);
}

#[test]
fn partial_quadrics_bilinear_patches_and_a_subdivided_mesh_have_pbrt_v4s_means() {
    assert_matches_pbrt_v4("shapes.pbrt", 16);
}

#[test]
fn film_response_clamp_and_a_tiny_sphere_light_have_pbrt_v4s_means() {
    // The brightest feature is a sphere light 1.5 cm across: the clamp scales down each sample
    // over `maxcomponentvalue`, so the means hold only when the sphere is sampled by its cone.
    assert_matches_pbrt_v4("film.pbrt", 16);
}

#[test]
fn translating_rotating_and_scaling_shapes_blur_with_pbrt_v4s_means() {
    // A rotation interpolated by matrix blending would shrink the box halfway (a shear), and a
    // shape left at its start transform moves its colour's share of the image.
    assert_matches_pbrt_v4("motion.pbrt", 16);
}

/// pbrt-v4's own killeroo scene (where it is available beside the repository: its licence keeps
/// it out of the project): in a crop of the glossy red killeroo at pbrt-v4's reference
/// resolution and spp (350×350, 128), prism's x/(1+x) RMSE against pbrt-v4's 512-spp image is
/// at most 3× pbrt-v4's own 128-spp error there. Measured: the Loop subdivision surface 2.0×, its
/// control mesh 7.3× (facets break the coat's highlight into sparkles); the excess that is left
/// is the sphere light's sampling noise, which the floor shows as well.
#[test]
fn killeroo_subdivision_surface_has_pbrt_v4s_highlight() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/pbrt-v4-scenes");
    let scene = shared.join("killeroos/killeroo-simple.pbrt");
    let (reference, second) = (
        shared.join("ref/killeroo-simple-350.pbrt-v4.exr"),
        shared.join("ref/killeroo-simple-350.pbrt-v4.seed2-128.exr"),
    );
    if !scene.exists() || !reference.exists() || !second.exists() {
        eprintln!("skipped: pbrt-v4's killeroo scene and references are not available");
        return;
    }
    let (x0, x1, y0, y1) = (210u32, 300u32, 160u32, 230u32);
    let d = tmpdir("compat-killeroo");
    let out = d.join("crop.exr");
    let bounds = format!("{x0},{x1},{y0},{y1}");
    let o = prism()
        .arg("render")
        .arg(&scene)
        .args(["--resolution", "350x350", "--spp", "128", "--seed", "1", "--pixelbounds", &bounds, "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // Nothing but the note that its "halton" sampler is drawn as prism's Sobol.
    let e = stderr(&o);
    assert!(e.lines().filter(|l| l.starts_with("prism: warning: ")).all(|l| l.contains("sampler \"halton\"")), "{e}");
    let crop = |img: &prism::image::Image| {
        let c = img.channels as usize;
        let mut data = Vec::new();
        for y in y0..y1 {
            let row = (y * img.width) as usize;
            data.extend_from_slice(&img.data[(row + x0 as usize) * c..(row + x1 as usize) * c]);
        }
        prism::image::Image { width: x1 - x0, height: y1 - y0, channels: img.channels, data }
    };
    let got = prism::image::read(&out).unwrap();
    assert_eq!((got.width, got.height), (x1 - x0, y1 - y0));
    let reference = crop(&prism::image::read(&reference).unwrap());
    let own =
        prism::image::metrics::compressed_rgb_rmse(&crop(&prism::image::read(&second).unwrap()), &reference).unwrap();
    let error = prism::image::metrics::compressed_rgb_rmse(&got, &reference).unwrap();
    let mean = prism::image::metrics::channel_means(&got);
    assert!(mean.iter().all(|&m| m > 0.01), "black crop: {mean:?}");
    std::fs::remove_dir_all(&d).ok();
    assert!(error <= 3.0 * own, "error {error:.5} vs pbrt-v4's own {own:.5} ({:.2}×)", error / own);
}

#[test]
fn homogeneous_media_in_spheres_and_filling_the_scene_have_pbrt_v4s_means() {
    for scene in ["media.pbrt", "media-fog.pbrt"] {
        assert_matches_pbrt_v4(scene, 16);
    }
}

#[test]
fn density_grid_rgb_grid_and_cloud_media_have_pbrt_v4s_means() {
    assert_matches_pbrt_v4("media-grid.pbrt", 16);
}

#[test]
fn cylinder_ribbon_and_flat_curves_with_hair_have_pbrt_v4s_means() {
    // Cylinder curves shade through pbrt-v4's normal turned across the width, and the hair
    // BSDF reads the offset across the fibre as h = 2v − 1.
    assert_matches_pbrt_v4("curves.pbrt", 16);
}
