//! Area lights showing an image (pbrt-v4 `AreaLightSource "diffuse" "string filename"`): seen
//! directly, each texel's colour at its (u, v); as next-event estimation sees it, the irradiance
//! the image's radiance gives by the view-factor integral.

use crate::common::{pbrt_scene, test_settings, tmpdir};
use glam::Vec3;
use prism::accel::AccelKind;
use prism::image::Image;
use prism::integrator::{DirectStrategy, Integrator};
use prism::measure::irradiance;
use prism::render::render;
use std::path::Path;

/// Writes a `width` × 1 image of the given linear RGB texels as OpenEXR (exact floats).
fn write_row(dir: &Path, name: &str, texels: &[[f32; 3]]) -> String {
    let mut img = Image::new(texels.len() as u32, 1, 3);
    img.data = texels.iter().flatten().copied().collect();
    let path = dir.join(name);
    prism::image::write(&path, &img).unwrap();
    path.display().to_string()
}

#[test]
fn a_textured_emitter_seen_directly_shows_its_texels() {
    let dir = tmpdir("area-image-direct");
    let file = write_row(&dir, "rg.exr", &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    // A square orthographic view of exactly the quad x, y ∈ [−1, 1]; u runs with x (left to
    // right).
    let scene = pbrt_scene(
        &format!(
            r#"LookAt 0 0 -3  0 0 0  0 1 0
Camera "orthographic"
WorldBegin
AreaLightSource "diffuse" "string filename" "{file}" "bool twosided" true "float scale" 2
Material "diffuse" "rgb reflectance" [0 0 0]
Shape "bilinearmesh" "point3 P" [-1 -1 0  1 -1 0  -1 1 0  1 1 0] "point2 uv" [0 0  1 0  0 1  1 1]
"#
        ),
        AccelKind::Obvhs,
    );
    let (w, h) = (32u32, 32u32);
    let settings = test_settings((w, h), 64, 7, 1);
    let (film, _) = render(&scene, &settings, |_| {}).unwrap();
    // Columns of u < ¼ see only the red texel (its centre is at u = ¼, clamped beyond), of
    // u > ¾ only the green one.
    let region = |cols: std::ops::Range<u32>| {
        let ys: Vec<f64> = (0..h)
            .flat_map(|y| cols.clone().map(move |x| (x, y)))
            .map(|(x, y)| {
                let p = &film.pixels[(y * w + x) as usize];
                p.xyz_sum.y / p.weight_sum
            })
            .collect();
        let n = ys.len() as f64;
        let m = ys.iter().sum::<f64>() / n;
        let se = (ys.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0) / n).sqrt();
        (m, se)
    };
    let (red, se_r) = region(0..w / 4);
    let (green, se_g) = region(3 * w / 4..w);
    assert!(red > 0.0 && green > 0.0, "black: red {red}, green {green}");
    // sRGB luminance of the primaries (ITU-R BT.709): Y = 0.2126 R + 0.7152 G + 0.0722 B.
    let want = 0.2126 / 0.7152;
    let ratio = red / green;
    let se = ratio * ((se_r / red).powi(2) + (se_g / green).powi(2)).sqrt();
    // 4σ, plus 1 % for the spectral fit of a saturated primary (its Y is the RGB's to ~0.1 %).
    assert!((ratio - want).abs() <= 4.0 * se + 0.01 * want, "Y ratio {ratio:.4} ± {se:.4} vs {want:.4}");
    std::fs::remove_dir_all(&dir).ok();
}

/// ∫ L(u) cos θ cos θ' / r² dA over the quad x ∈ [−1, 1], y ∈ [−½, ½] at height 1 above
/// `p` (a receiver facing +z), by the midpoint rule on a 400 × 200 grid; u = (x + 1)/2.
fn view_integral(p: Vec3, l: impl Fn(f64) -> f64) -> f64 {
    let (nx, ny) = (400, 200);
    let (dx, dy) = (2.0 / nx as f64, 1.0 / ny as f64);
    let mut sum = 0.0;
    for i in 0..nx {
        for j in 0..ny {
            let (x, y) = (-1.0 + (i as f64 + 0.5) * dx, -0.5 + (j as f64 + 0.5) * dy);
            let d = [x - p.x as f64, y - p.y as f64, 1.0 - p.z as f64];
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let cos = d[2] / r2.sqrt();
            sum += l((x + 1.0) / 2.0) * cos * cos / r2 * dx * dy;
        }
    }
    sum
}

#[test]
fn next_event_estimation_under_a_textured_emitter_sees_the_image() {
    let dir = tmpdir("area-image-nee");
    // Grey texels: their spectra are the white times the value, so the radiance is linear in
    // them and a plain emitter of value 1 gives the kernel of the view-factor integral.
    let file = write_row(&dir, "grey.exr", &[[2.0; 3], [0.5; 3]]);
    let quad = r#"Material "diffuse" "rgb reflectance" [0 0 0]
Shape "bilinearmesh" "point3 P" [-1 -0.5 1  1 -0.5 1  -1 0.5 1  1 0.5 1] "point2 uv" [0 0  1 0  0 1  1 1]"#;
    let scene = |light: &str| {
        pbrt_scene(
            &format!("LookAt 0 0 -3  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n{light}\n{quad}\n"),
            AccelKind::Obvhs,
        )
    };
    let textured = scene(&format!(r#"AreaLightSource "diffuse" "string filename" "{file}" "bool twosided" true"#));
    let plain = scene(r#"AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" true"#);
    // The bilinear image: 2 left of the first texel's centre (u = ¼), ½ right of the second's.
    let image = |u: f64| 2.0 + (0.5 - 2.0) * ((u - 0.25) / 0.5).clamp(0.0, 1.0);
    for strategy in [DirectStrategy::LightOnly, DirectStrategy::BsdfOnly] {
        let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
        for p in [Vec3::new(-0.5, 0.0, 0.0), Vec3::ZERO, Vec3::new(0.6, 0.1, 0.0)] {
            let t = irradiance(&textured, &integ, p, Vec3::Z, 200_000, 11).irradiance;
            let u = irradiance(&plain, &integ, p, Vec3::Z, 200_000, 12).irradiance;
            assert!(t.mean > 0.0, "{strategy:?} at {p}: black");
            let k = view_integral(p, image) / view_integral(p, |_| 1.0);
            let want = u.mean * k;
            let se = (t.std_err.powi(2) + (k * u.std_err).powi(2)).sqrt();
            assert!(
                (t.mean - want).abs() <= 4.0 * se,
                "{strategy:?} at {p}: E {:.5} ± {:.5} vs {want:.5} (mean radiance {k:.4} × {:.5})",
                t.mean,
                t.std_err,
                u.mean
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_emitter_given_both_l_and_an_image_or_a_missing_image_is_an_error() {
    let dir = tmpdir("area-image-errors");
    let file = write_row(&dir, "one.exr", &[[1.0; 3]]);
    let missing = dir.join("missing.exr").display().to_string();
    for (light, what) in [
        (format!(r#""string filename" "{file}" "rgb L" [1 1 1]"#), "\"L\""),
        (format!(r#""string filename" "{missing}""#), "cannot read"),
    ] {
        let text = format!(
            "LookAt 0 0 -3  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nAreaLightSource \"diffuse\" {light}\n\
             Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2]\n"
        );
        let (desc, mut warnings) = prism::pbrt::parse_str(&text, &Default::default()).unwrap();
        let err = prism::pbrt::build(&desc, &mut warnings).err().map(|e| e.to_string());
        assert!(err.as_deref().is_some_and(|e| e.contains(what)), "{light}: {err:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
