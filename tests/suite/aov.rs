//! pbrt-v4's `gbuffer` film and `--aov`: every channel on a scene whose values are known in
//! closed form (planes at known depths and normals, a grey Lambertian albedo), the beauty the
//! same as without geometry buffers, and parts that merge to the single render.

use crate::common::{prism, render_halves_and_merge, stderr, tmpdir};
use std::collections::HashMap;
use std::path::Path;

/// Image size [pixels], and the plane's distance and the camera's field of view.
const N: usize = 32;
const DEPTH: f32 = 5.0;
const FOV_DEG: f32 = 30.0;

/// The channels of an OpenEXR file by name (read with the `exr` crate, not prism's reader).
fn channels(path: &Path) -> HashMap<String, Vec<f32>> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .unwrap();
    let list = image.layer_data.channel_data.list;
    list.into_iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect()
}

/// A camera at `eye` looking along +z (y up) at a grey diffuse plane z = eye.z + DEPTH (u, v
/// over x, y ∈ [−4, 4]) tilted by `slope` (z grows by `slope`·x), under a uniform sky; the
/// film's extra text. The triangles wind so that pbrt-v4's geometric normal, the cross product
/// of (p₀ − p₂) and (p₁ − p₂), faces the camera.
fn scene(eye: [f32; 3], slope: f32, film: &str) -> String {
    let [x, y, z] = eye;
    let (z0, z1) = (z + DEPTH - 4.0 * slope, z + DEPTH + 4.0 * slope);
    format!(
        "LookAt {x} {y} {z}  {x} {y} {} 0 1 0\n\
         Camera \"perspective\" \"float fov\" {FOV_DEG}\n\
         Sampler \"independent\" \"integer pixelsamples\" 16\n\
         PixelFilter \"box\"\n\
         Film \"gbuffer\" \"integer xresolution\" {N} \"integer yresolution\" {N} \"bool savefp16\" false {film}\n\
         Integrator \"path\" \"integer maxdepth\" 2\n\
         WorldBegin\n\
         LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
         Shape \"trianglemesh\" \"point3 P\" [{a} {b} {z0}  {c} {b} {z1}  {c} {d} {z1}  {a} {d} {z0}]\n\
           \"point2 uv\" [0 0 1 0 1 1 0 1] \"integer indices\" [0 2 1 0 3 2]\n",
        z + 1.0,
        a = x - 4.0,
        b = y - 4.0,
        c = x + 4.0,
        d = y + 4.0,
    )
}

/// Renders `text` to an OpenEXR in `dir` with extra arguments; its channels.
fn render(dir: &Path, name: &str, text: &str, args: &[&str]) -> HashMap<String, Vec<f32>> {
    let file = dir.join(format!("{name}.pbrt"));
    std::fs::write(&file, text).unwrap();
    let out = dir.join(format!("{name}.exr"));
    let o = prism().arg("render").arg(&file).arg("-o").arg(&out).args(args).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    channels(&out)
}

/// tan of half the field of view: the film spans [−t, t] at unit distance (square image).
fn tan_half() -> f32 {
    (FOV_DEG.to_radians() / 2.0).tan()
}

/// The camera-space direction (x, y, 1) through the centre of pixel (i, j) (x right, y up).
fn pixel_direction(i: usize, j: usize) -> (f32, f32) {
    let s = |k: usize| (2.0 * (k as f32 + 0.5) / N as f32 - 1.0) * tan_half();
    (s(i), -s(j))
}

#[test]
fn gbuffer_channels_are_the_planes_closed_form_values() {
    let dir = tmpdir("aov-closed-form");
    let c = render(&dir, "front", &scene([0.0; 3], 0.0, ""), &[]);
    let names = ["R", "G", "B", "Albedo.R", "P.X", "P.Z", "dzdx", "dzdy", "N.Z", "Ns.Z", "u", "v", "Variance.G"];
    for n in names.iter().chain(&["RelativeVariance.B"]) {
        assert_eq!(c[*n].len(), N * N, "channel {n}");
    }
    assert!(c["G"].iter().sum::<f32>() > 0.01 * (N * N) as f32, "the beauty is black");
    let at = |name: &str, i: usize, j: usize| c[name][j * N + i];
    for j in 0..N {
        for i in 0..N {
            // The box filter averages the pixel's area: on a plane, P is the centre's point.
            let (dx, dy) = pixel_direction(i, j);
            let want = [DEPTH * dx, DEPTH * dy, DEPTH];
            let got = [at("P.X", i, j), at("P.Y", i, j), at("P.Z", i, j)];
            for k in 0..3 {
                // Samples are uniform over the pixel (a box of one pixel, 2·DEPTH·tan/N wide):
                // the mean of 16 has standard error pixel/√(12·16) per coordinate. Over the
                // 2·N² comparisons a 5σ bound is passed by chance with probability ~10⁻³.
                let pixel = 2.0 * DEPTH * tan_half() / N as f32;
                let sigma = pixel / (12.0f32 * 16.0).sqrt();
                assert!((got[k] - want[k]).abs() < 5.0 * sigma, "P at ({i},{j}): {got:?} vs {want:?}");
            }
            // Facing the camera: both normals −z, no depth change across the pixel.
            for (name, want) in
                [("N.X", 0.0), ("N.Y", 0.0), ("N.Z", -1.0), ("Ns.X", 0.0), ("Ns.Y", 0.0), ("Ns.Z", -1.0)]
            {
                assert!((at(name, i, j) - want).abs() < 1e-5, "{name} at ({i},{j}): {}", at(name, i, j));
            }
            assert!(at("dzdx", i, j).abs() < 1e-5 && at("dzdy", i, j).abs() < 1e-5);
            // u, v follow x, y over [−4, 4].
            assert!((at("u", i, j) - (got[0] + 4.0) / 8.0).abs() < 1e-4);
            assert!((at("v", i, j) - (got[1] + 4.0) / 8.0).abs() < 1e-4);
            let (var, rel, mean) = (at("Variance.G", i, j), at("RelativeVariance.G", i, j), at("G", i, j));
            assert!(var >= 0.0 && rel >= 0.0 && mean > 0.0);
        }
    }
    // A grey reflectance of 0.5 lit by the output space's white: 0.5 in every channel, as the
    // mean of per-sample estimates from four wavelengths each; within 4 standard errors.
    for ch in ["Albedo.R", "Albedo.G", "Albedo.B"] {
        let v = &c[ch];
        let n = v.len() as f32;
        let mean = v.iter().sum::<f32>() / n;
        let se = (v.iter().map(|x| (x - mean).powi(2)).sum::<f32>() / (n - 1.0) / n).sqrt();
        assert!((mean - 0.5).abs() < 4.0 * se + 1e-4, "{ch}: {mean} ± {se}");
        // No pixel is an outlier (a NaN or a sample lost): each lies within 5 measured pixel
        // standard deviations (the four-wavelength estimate of Z spreads more than Y's).
        let sd = se * n.sqrt();
        assert!(v.iter().all(|x| (x - 0.5).abs() < 5.0 * sd), "{ch}: sd {sd}");
    }
    // The sky's light reaches the plane through a noisy estimate: some variance is recorded.
    assert!(c["Variance.G"].iter().any(|&v| v > 0.0));
}

#[test]
fn depth_slopes_world_coordinates_and_misses_are_as_pbrt_v4_writes_them() {
    let dir = tmpdir("aov-slopes");
    // A plane tilted so z grows by `a` per unit x: at the image centre one pixel's step along x
    // moves the hit by δ = 2 tan(fov/2)/N in direction, so z by DEPTH·a·δ/(1 − a·δ), scaled by
    // 1/√spp = 1/4 as pbrt-v4 scales ray differentials; none along y.
    let a = 0.5;
    let c = render(&dir, "tilted", &scene([0.0; 3], a, ""), &[]);
    let delta = 2.0 * tan_half() / N as f32;
    let want = 0.25 * DEPTH * a * delta / (1.0 - a * delta);
    let (i, j) = (N / 2, N / 2);
    let (got_x, got_y) = (c["dzdx"][j * N + i], c["dzdy"][j * N + i]);
    assert!((got_x - want).abs() < 0.05 * want, "dzdx {got_x} vs {want}");
    assert!(got_y.abs() < 0.02 * want, "dzdy {got_y}");
    // The normal leans towards −x: (a, 0, −1)/|…| in camera space.
    let n = glam::Vec3::new(a, 0.0, -1.0).normalize();
    assert!((c["N.X"][j * N + i] - n.x).abs() < 1e-5 && (c["N.Z"][j * N + i] - n.z).abs() < 1e-5);

    // World coordinates: the same view from (1, 2, 3) puts the plane at z = 3 + DEPTH.
    let w = render(&dir, "world", &scene([1.0, 2.0, 3.0], 0.0, "\"string coordinatesystem\" \"world\""), &[]);
    let camera = render(&dir, "camera", &scene([1.0, 2.0, 3.0], 0.0, ""), &[]);
    for k in 0..N * N {
        assert!((w["P.Z"][k] - (3.0 + DEPTH)).abs() < 1e-4, "world z {}", w["P.Z"][k]);
        assert!((w["P.X"][k] - 1.0 - camera["P.X"][k]).abs() < 1e-4);
        assert!((camera["P.Z"][k] - DEPTH).abs() < 1e-4);
    }
    // Pixels that see only the sky (the plane's edge is inside a wide view) hold zeros.
    let wide = scene([0.0; 3], 0.0, "").replace(&format!("\"float fov\" {FOV_DEG}"), "\"float fov\" 120");
    let c = render(&dir, "wide", &wide, &[]);
    let corner = 0;
    assert!(c["G"][corner] > 0.0, "the sky is seen");
    for ch in ["P.Z", "N.Z", "Albedo.G", "u", "Variance.G"] {
        assert_eq!(c[ch][corner], 0.0, "{ch} of a pixel that sees no surface");
    }
    // The geometric normal is the winding's, not turned to the viewer (pbrt-v4's `n`): the
    // other winding faces away.
    let away = scene([0.0; 3], 0.0, "").replace("[0 2 1 0 3 2]", "[0 1 2 0 2 3]");
    let c = render(&dir, "away", &away, &[]);
    assert!((c["N.Z"][(N / 2) * N + N / 2] - 1.0).abs() < 1e-5, "{}", c["N.Z"][(N / 2) * N + N / 2]);
}

#[test]
fn geometry_buffers_leave_the_beauty_as_it_is_and_parts_merge_to_the_whole() {
    let dir = tmpdir("aov-beauty");
    let gbuffer = scene([0.0; 3], 0.3, "");
    let rgb = gbuffer.replace("Film \"gbuffer\"", "Film \"rgb\"");
    let with = render(&dir, "gbuffer", &gbuffer, &[]);
    let without = render(&dir, "rgb", &rgb, &[]);
    assert_eq!(without.len(), 3, "an rgb film writes R, G, B only");
    for ch in ["R", "G", "B"] {
        assert_eq!(with[ch], without[ch], "{ch} changed by recording the geometry buffers");
    }
    // `--aov` on the rgb film writes the same file as the gbuffer film.
    let flag = render(&dir, "flag", &rgb, &["--aov"]);
    assert_eq!(flag, with);

    // Two parts merged: the same sums up to rounding (the variance is merged pairwise).
    let file = dir.join("gbuffer.pbrt");
    let merged = render_halves_and_merge(&dir, &file);
    let merged = channels(&merged);
    for (name, values) in &with {
        for (k, (a, b)) in values.iter().zip(&merged[name]).enumerate() {
            assert!((a - b).abs() <= 1e-4 * a.abs().max(1.0), "{name}[{k}]: {a} vs {b}");
        }
    }
}

#[test]
fn aov_output_must_be_openexr() {
    let dir = tmpdir("aov-png");
    let file = dir.join("s.pbrt");
    std::fs::write(&file, scene([0.0; 3], 0.0, "")).unwrap();
    let o = prism().arg("render").arg(&file).args(["--aov", "-o"]).arg(dir.join("x.png")).output().unwrap();
    assert!(!o.status.success());
    assert!(stderr(&o).contains("OpenEXR") && stderr(&o).lines().count() == 1, "{}", stderr(&o));
    // The file's gbuffer film with a PNG output: R, G, B with a warning.
    let o = prism().arg("render").arg(&file).arg("-o").arg(dir.join("y.png")).output().unwrap();
    assert!(o.status.success() && stderr(&o).contains("R, G, B only"), "{}", stderr(&o));
}
