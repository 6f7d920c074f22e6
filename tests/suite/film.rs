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

/// Planck's law, unnormalised (the scale cancels below): B(λ, T) ∝ λ⁻⁵ / (exp(hc/λkT) − 1).
fn planck(l_nm: f64, t: f64) -> f64 {
    let l = l_nm * 1e-9;
    l.powi(-5) / ((6.626_070_15e-34 * 299_792_458.0 / (l * 1.380_649e-23 * t)).exp() - 1.0)
}

/// A camera's sensitivity `c` (0–2) at `l` [nm], linear between the 10 nm samples from 380 nm.
fn curve(curves: &[[f32; 35]; 3], c: usize, l: f64) -> f64 {
    let x = (l - 380.0) / 10.0;
    if !(0.0..=34.0).contains(&x) {
        return 0.0;
    }
    let i = (x as usize).min(33);
    let t = x - i as f64;
    curves[c][i] as f64 * (1.0 - t) + curves[c][i + 1] as f64 * t
}

#[test]
fn a_camera_sensor_reads_a_blackbody_sky_as_its_curves_and_fitted_matrix_predict() {
    // The sky, a uniform 5000 K blackbody, seen directly through "canon_eos_5d" (white balanced
    // to 6500 K by default) and through "cie1931". The cie1931 film's Y fixes the light's
    // scale s (Y = s ∫ȳB / ∫ȳ); the camera then must read s · M · ∫c̄B / ∫ȳ, with M fitted here
    // as pbrt-v4's PixelSensor fits it, in f64 from the curves and ColorChecker data.
    use prism::spectrum::{camera_sensitivities, cie::xyz_bar_f64, colorchecker_reflectances, daylight, Spectrum};
    let d = tmpdir("camera-sensor");
    let world = r#"LightSource "infinite" "blackbody L" 5000"#;
    let args = |p: &Path| {
        vec![p.to_str().unwrap().to_string(), "--resolution".into(), "8x8".into(), "--spp".into(), "256".into()]
    };
    let cie = write_scene(&d, "cie.pbrt", "", "", world);
    let cam = write_scene(&d, "cam.pbrt", r#""string sensor" "canon_eos_5d""#, "", world);
    let f_cie = render(&d, "cie", &args(&cie).iter().map(String::as_str).collect::<Vec<_>>());
    let f_cam = render(&d, "cam", &args(&cam).iter().map(String::as_str).collect::<Vec<_>>());
    let stats = |f: &Film, c: usize| {
        let v: Vec<f64> =
            (0..f.height).flat_map(|y| (0..f.width).map(move |x| (x, y))).map(|(x, y)| f.xyz(x, y)[c] as f64).collect();
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        (m, (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0) / n).sqrt())
    };

    // The fit, as pbrt-v4 defines it: sums at every whole nm of 360–830 nm.
    let curves = camera_sensitivities("canon_eos_5d").unwrap();
    let e = daylight(6500.0 * 1.4388 / 1.4380).unwrap();
    let w = Spectrum::named("stdillum-D65").unwrap();
    let sum = |f: &dyn Fn(f64) -> [f64; 3]| {
        (360..=830).map(f64::from).fold([0.0; 3], |a, l| {
            let v = f(l);
            [a[0] + v[0], a[1] + v[1], a[2] + v[2]]
        })
    };
    let rgb_of = |r: &dyn Fn(f64) -> f64| sum(&|l| [0, 1, 2].map(|c| curve(curves, c, l) * r(l) * e.eval_f64(l)));
    let xyz_of = |r: &dyn Fn(f64) -> f64, s: &Spectrum| {
        sum(&|l| {
            let b = xyz_bar_f64(l);
            [b.x, b.y, b.z].map(|v| v * r(l) * s.eval_f64(l))
        })
    };
    let (e_g, e_y, w_y) = (rgb_of(&|_| 1.0)[1], xyz_of(&|_| 1.0, &e)[1], xyz_of(&|_| 1.0, &w)[1]);
    // Normal equations: M = (Σ b aᵀ)(Σ a aᵀ)⁻¹, solved for each row by Cramer's rule.
    let (mut ata, mut bta) = ([[0.0f64; 3]; 3], [[0.0f64; 3]; 3]);
    for patch in colorchecker_reflectances() {
        let r = |l: f64| patch.eval_f64(l);
        let a = rgb_of(&r).map(|v| v / e_g);
        let b = xyz_of(&r, &w).map(|v| v / w_y * e_y / e_g);
        for i in 0..3 {
            for j in 0..3 {
                ata[i][j] += a[i] * a[j];
                bta[i][j] += b[i] * a[j];
            }
        }
    }
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    // Row i of M solves ata · mᵢ = (bta row i) (ata is symmetric).
    let m: Vec<[f64; 3]> = (0..3)
        .map(|i| {
            [0, 1, 2].map(|k| {
                let mut a = ata;
                for r in 0..3 {
                    a[r][k] = bta[i][r];
                }
                det(a) / det(ata)
            })
        })
        .collect();

    // The sky through each sensor, on prism's scale (÷ ∫ȳ), by the trapezoid rule at 0.05 nm.
    let y_integral = prism::spectrum::CIE_Y_INTEGRAL as f64;
    let fine = |f: &dyn Fn(f64) -> f64| {
        (0..=9400).map(|i| 360.0 + 0.05 * i as f64).map(|l| f(l) * 0.05).sum::<f64>() - 0.025 * (f(360.0) + f(830.0))
    };
    let sky_y = fine(&|l| xyz_bar_f64(l).y * planck(l, 5000.0)) / y_integral;
    let response = [0, 1, 2].map(|c| fine(&|l| curve(curves, c, l) * planck(l, 5000.0)) / y_integral);
    let (y_cie, y_cie_se) = stats(&f_cie, 1);
    let s = y_cie / sky_y;
    for (c, row) in m.iter().enumerate() {
        let predicted = s * (row[0] * response[0] + row[1] * response[1] + row[2] * response[2]);
        let (got, se) = stats(&f_cam, c);
        let tolerance = 4.0 * (se + predicted * y_cie_se / y_cie) + 2e-3 * predicted;
        assert!((got - predicted).abs() <= tolerance, "XYZ[{c}]: {got} ± {se} vs predicted {predicted}");
    }
}
