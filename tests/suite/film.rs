//! What the film records: a crop of the image (pbrt-v4's "cropwindow"/"pixelbounds", prism's
//! --cropwindow/--pixelbounds) renders exactly those pixels of the full render, and the
//! "cie1931" sensor's ISO, exposure time and white balance (pbrt-v4's Film/Camera parameters).

use crate::common::{film, prism, stderr, tmpdir};
use prism::film::Film;
use prism::spectrum::ColorSpace;
use std::path::{Path, PathBuf};

/// Renders with `prism render ARGS -o DIR/NAME.film` and reads the film back.
fn render(dir: &Path, name: &str, args: &[&str]) -> Film {
    let out = dir.join(format!("{name}.film"));
    let o = prism().arg("render").args(args).args(["-o", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    film(&out)
}

fn write_scene(dir: &Path, name: &str, film_params: &str, camera_params: &str, world: &str) -> PathBuf {
    let path = dir.join(name);
    let text = format!(
        "Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 30 {film_params}\n\
         Camera \"perspective\" \"float fov\" 50 {camera_params}\nSampler \"independent\" \"integer pixelsamples\" 2\n\
         WorldBegin\n{world}\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

const BOX_WORLD: &str = r#"LightSource "point" "rgb I" [5 5 5] "point3 from" [0 1 -1]
Material "diffuse" "rgb reflectance" [0.7 0.3 0.2]
Shape "trianglemesh" "point3 P" [-2 -2 3  2 -2 3  2 2 3  -2 2 3] "integer indices" [0 1 2 0 2 3]
Material "diffuse" "rgb reflectance" [0.2 0.5 0.8]
Translate 0 0 1.5
Shape "sphere" "float radius" 0.6"#;

#[test]
fn a_crop_renders_exactly_those_pixels_of_the_full_image() {
    let d = tmpdir("crop");
    let common = ["--resolution", "40x30", "--spp", "2", "--accel", "obvhs"];
    let full = render(&d, "full", &common);
    // pbrt-v4's rounding: x ∈ [⌈40·0.25⌉, ⌈40·0.6⌉) = [10, 24), y ∈ [⌈30·0.1⌉, ⌈30·0.5⌉) = [3, 15).
    let window = render(&d, "window", &[&common[..], &["--cropwindow", "0.6,0.25,0.1,0.5"]].concat());
    let bounds = render(&d, "bounds", &[&common[..], &["--pixelbounds", "10,24,3,15"]].concat());
    let scene = write_scene(&d, "crop.pbrt", r#""float cropwindow" [0.25 0.6 0.1 0.5]"#, "", BOX_WORLD);
    let in_file = render(&d, "file", &[scene.to_str().unwrap(), "--accel", "obvhs"]);
    let file_full = render(&d, "file_full", &[scene.to_str().unwrap(), "--accel", "obvhs", "--cropwindow", "0,1,0,1"]);
    for (what, crop, whole) in
        [("--cropwindow", &window, &full), ("--pixelbounds", &bounds, &full), ("Film", &in_file, &file_full)]
    {
        assert_eq!((crop.width, crop.height), (14, 12), "{what}");
        for y in 0..12 {
            for x in 0..14 {
                let (p, q) = (&crop.pixels[(y * 14 + x) as usize], &whole.pixels[((y + 3) * 40 + x + 10) as usize]);
                assert_eq!(p, q, "{what}: pixel ({x}, {y}) of the crop differs from ({}, {})", x + 10, y + 3);
            }
        }
        assert!(crop.pixels.iter().any(|p| p.xyz_sum.y > 0.0), "{what}: black crop");
    }
    // An empty crop is a clear error, not a panic or an empty image.
    let out = d.join("empty.png");
    let o = prism().args(["render", "--cropwindow", "0.5,0.5,0,1", "-o", out.to_str().unwrap()]).output().unwrap();
    assert!(
        !o.status.success() && stderr(&o).contains("cropwindow [0.5 0.5 0 1] selects no pixels of a 256x256 image"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
}

#[test]
fn iso_and_exposure_time_scale_the_film_as_pbrt_v4s_imaging_ratio() {
    let d = tmpdir("iso");
    let base = write_scene(&d, "base.pbrt", "", "", BOX_WORLD);
    let iso = write_scene(&d, "iso.pbrt", r#""float iso" 400"#, "", BOX_WORLD);
    // exposure time × ISO / 100 = 0.5 × 200 / 100 = 1: the same film as the defaults.
    let half = write_scene(&d, "half.pbrt", r#""float iso" 200"#, r#""float shutterclose" 0.5"#, BOX_WORLD);
    let films: Vec<Film> =
        [&base, &iso, &half].iter().map(|s| render(&d, "f", &[s.to_str().unwrap(), "--accel", "obvhs"])).collect();
    assert!(films[0].pixels.iter().any(|p| p.xyz_sum.y > 0.0), "black render");
    for (a, (b, c)) in films[0].pixels.iter().zip(films[1].pixels.iter().zip(&films[2].pixels)) {
        assert_eq!(a.xyz_sum * 4.0, b.xyz_sum, "ISO 400 is exactly 4× ISO 100");
        assert_eq!(a, c, "0.5 s at ISO 200 is 1 s at ISO 100");
    }
}

#[test]
fn white_balance_makes_a_white_surface_under_that_light_neutral() {
    // A white Lambertian wall under a uniform sky of a 3200 K blackbody (daylight is undefined
    // below 4000 K, so "whitebalance" 3200 adapts from that blackbody's white, on the 1.4388 cm·K
    // scale: 3200 × 1.4388 / 1.4380 K).
    let d = tmpdir("wb");
    let world = r#"LightSource "infinite" "blackbody L" 3201.78
Material "diffuse" "spectrum reflectance" [360 1 830 1]
Shape "trianglemesh" "point3 P" [-5 -5 2  5 -5 2  5 5 2  -5 5 2] "integer indices" [0 1 2 0 2 3]"#;
    let srgb = ColorSpace::srgb();
    let mut ratios = Vec::new();
    for (name, film_params) in [("plain", ""), ("balanced", r#""float whitebalance" 3200"#)] {
        let scene = write_scene(&d, &format!("{name}.pbrt"), film_params, "", world);
        let f = render(&d, name, &[scene.to_str().unwrap(), "--accel", "obvhs", "--resolution", "16x16", "--spp", "4"]);
        // Per-pixel r/g and b/g (independent estimates): mean and standard error.
        let (mut rg, mut bg) = (Vec::new(), Vec::new());
        for y in 0..f.height {
            for x in 0..f.width {
                let rgb = srgb.xyz_to_rgb(f.xyz(x, y));
                rg.push((rgb.x / rgb.y) as f64);
                bg.push((rgb.z / rgb.y) as f64);
            }
        }
        let stat = |v: &[f64]| {
            let n = v.len() as f64;
            let m = v.iter().sum::<f64>() / n;
            (m, (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0) / n).sqrt())
        };
        ratios.push((stat(&rg), stat(&bg)));
    }
    let ((rg, _), (bg, _)) = ratios[0];
    assert!(rg > 1.3 && bg < 0.6, "a 3200 K light looks orange unbalanced: r/g {rg}, b/g {bg}");
    let ((rg, rg_se), (bg, bg_se)) = ratios[1];
    assert!((rg - 1.0).abs() <= 4.0 * rg_se + 2e-3, "balanced r/g = {rg} ± {rg_se}");
    assert!((bg - 1.0).abs() <= 4.0 * bg_se + 2e-3, "balanced b/g = {bg} ± {bg_se}");
}
