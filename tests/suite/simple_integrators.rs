//! pbrt-v4's small integrators: `ambientocclusion` against its closed form between two planes,
//! `randomwalk` and every `simplepath` variant against the reflected sky's closed form and
//! against `path` on a scene with an area light and interreflection, `simplevolpath` against
//! `volpath` on a ball of scattering medium under a sky.

use crate::common::{film, film_difference, prism, stderr, tmpdir};
use prism::film::Film;
use std::path::Path;

/// Renders `text` (an `Integrator` directive is appended before `WorldBegin`) to a .film.
fn render(dir: &Path, name: &str, text: &str, integrator: &str) -> Film {
    let file = dir.join(format!("{name}.pbrt"));
    std::fs::write(&file, text.replace("WorldBegin", &format!("{integrator}\nWorldBegin"))).unwrap();
    let out = dir.join(format!("{name}.film"));
    let o = prism().arg("render").arg(&file).args(["--strict", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    film(&out)
}

/// Mean of the pixels' Y, and its standard error (pixels are independent estimates).
fn mean_y(f: &Film) -> (f64, f64) {
    let y: Vec<f64> = f.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect();
    let n = y.len() as f64;
    let m = y.iter().sum::<f64>() / n;
    (m, (y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt())
}

/// A camera half way between a floor y = 0 and a ceiling y = `h` (both ±1000 wide), looking
/// down at the floor.
fn between_planes(h: f32) -> String {
    format!(
        "LookAt 0 {} 0  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" 40\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
         Sampler \"independent\" \"integer pixelsamples\" 64\nPixelFilter \"box\"\nWorldBegin\n\
         Material \"diffuse\"\n\
         Shape \"trianglemesh\" \"point3 P\" [-1000 0 -1000  1000 0 -1000  1000 0 1000  -1000 0 1000] \"integer indices\" [0 1 2 0 2 3]\n\
         Shape \"trianglemesh\" \"point3 P\" [-1000 {h} -1000  1000 {h} -1000  1000 {h} 1000  -1000 {h} 1000] \"integer indices\" [0 2 1 0 3 2]\n",
        h / 2.0
    )
}

#[test]
fn ambient_occlusion_between_two_planes_is_the_squared_ratio_of_height_to_distance() {
    // A ray leaving the floor at angle θ meets the ceiling at distance h / cos θ: it is open
    // within `maxdistance` d when cos θ < h/d, and the cosine-weighted measure of that set
    // (cos²θ is uniform under it) is (h/d)². Sampled by cosine or uniformly, the same mean.
    let dir = tmpdir("ao-planes");
    let (h, d) = (1.0, 2.0);
    let want = (h / d) * (h / d);
    for cos in ["true", "false"] {
        let ao = format!("Integrator \"ambientocclusion\" \"bool cossample\" {cos} \"float maxdistance\" {d}");
        let (m, se) = mean_y(&render(&dir, &format!("open-{cos}"), &between_planes(h), &ao));
        assert!(m > 0.05, "black image");
        assert!((m - want as f64).abs() < 4.0 * se, "cossample {cos}: {m} ± {se} vs {want}");
    }
    // With no distance limit the ceiling closes every direction; without a ceiling none.
    let closed = render(&dir, "closed", &between_planes(h), "Integrator \"ambientocclusion\"");
    assert_eq!(mean_y(&closed).0, 0.0);
    let floor_only: String =
        between_planes(h).lines().filter(|l| !l.contains(&format!(" {h} -1000"))).collect::<Vec<_>>().join("\n");
    let (m, _) = mean_y(&render(&dir, "sky", &floor_only, "Integrator \"ambientocclusion\""));
    assert!((m - 1.0).abs() < 1e-3, "an unoccluded point is the output space's white (Y = 1): {m}");
}

/// A grey floor (reflectance 0.5) under a uniform white sky, seen from above; 256 samples per
/// pixel put the standard error of the mean near 0.5 % (a 2.5 % bias is 5σ).
const SKY_FLOOR: &str = "LookAt 0 3 0  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" 40\n\
    Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
    Sampler \"independent\" \"integer pixelsamples\" 256\nPixelFilter \"box\"\nWorldBegin\n\
    LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
    Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
    Shape \"trianglemesh\" \"point3 P\" [-1000 0 -1000  1000 0 -1000  1000 0 1000  -1000 0 1000] \"integer indices\" [0 1 2 0 2 3]\n";

/// The estimators under test, as their `Integrator` directives.
const ESTIMATORS: [&str; 5] = [
    "Integrator \"randomwalk\"",
    "Integrator \"simplepath\"",
    "Integrator \"simplepath\" \"bool samplelights\" false",
    "Integrator \"simplepath\" \"bool samplebsdf\" false",
    "Integrator \"simplepath\" \"bool samplelights\" false \"bool samplebsdf\" false",
];

#[test]
fn the_small_estimators_reflect_the_sky_as_the_closed_form_says() {
    // A Lambertian floor of reflectance ρ under a sky of unit radiance: L_o = ρ · 1 = 0.5 in Y
    // (the sky's RGB white is the output space's white, of luminance 1).
    let dir = tmpdir("small-sky");
    for (i, e) in ESTIMATORS.iter().enumerate() {
        let (m, se) = mean_y(&render(&dir, &format!("e{i}"), SKY_FLOOR, e));
        assert!((m - 0.5).abs() < 4.0 * se + 1e-3, "{e}: {m} ± {se}");
    }
}

/// A white box open at the front with a square light in its ceiling, a grey block inside:
/// direct light, interreflection and an emitter both light sampling and paths find.
const ROOM: &str = "LookAt 0 1 -3.2  0 1 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n\
    Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24\n\
    Sampler \"independent\" \"integer pixelsamples\" 64\nPixelFilter \"box\"\nWorldBegin\n\
    Material \"diffuse\" \"rgb reflectance\" [0.7 0.7 0.7]\n\
    Shape \"trianglemesh\" \"point3 P\" [-1 0 -1  1 0 -1  1 0 1  -1 0 1  -1 2 -1  1 2 -1  1 2 1  -1 2 1]\n\
      \"integer indices\" [0 2 1 0 3 2  4 5 6 4 6 7  3 7 6 3 6 2  0 4 7 0 7 3  1 2 6 1 6 5]\n\
    Material \"diffuse\" \"rgb reflectance\" [0.4 0.4 0.4]\n\
    Shape \"trianglemesh\" \"point3 P\" [-0.3 0 -0.2  0.3 0 -0.2  0.3 0.8 -0.2  -0.3 0.8 -0.2] \"integer indices\" [0 1 2 0 2 3]\n\
    AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [4 4 4]\n\
      Shape \"trianglemesh\" \"point3 P\" [-0.5 1.99 -0.5  0.5 1.99 -0.5  0.5 1.99 0.5  -0.5 1.99 0.5] \"integer indices\" [0 1 2 0 2 3]\n\
    AttributeEnd\n";

#[test]
fn the_small_estimators_agree_with_the_path_tracer() {
    // The same radiance at every pixel: the mean over pixels of their differences to `path`
    // is zero within 4 standard errors (pixels are independent estimates).
    let dir = tmpdir("small-room");
    let depth = "\"integer maxdepth\" 4";
    let path = render(&dir, "path", ROOM, &format!("Integrator \"path\" {depth}"));
    let (y, _) = mean_y(&path);
    assert!(y > 0.05, "black image");
    for (i, e) in ESTIMATORS.iter().enumerate() {
        let f = render(&dir, &format!("e{i}"), ROOM, &format!("{e} {depth}"));
        let (d, se, _) = film_difference(&f, &path);
        assert!(d.abs() < 4.0 * se, "{e}: differs from path by {d} ± {se} (mean Y {y})");
    }
}

/// A ball of homogeneous medium (bounded by an `interface` surface; absorbing and scattering
/// forward, both coloured) under a coloured sky, which also fills the view around it.
const MEDIUM_BALL: &str = "LookAt 0 0 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
    Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24\n\
    Sampler \"independent\" \"integer pixelsamples\" 256\nPixelFilter \"box\"\nWorldBegin\n\
    LightSource \"infinite\" \"rgb L\" [0.8 0.9 1.2]\n\
    MakeNamedMedium \"ball\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.2 0.5 1.0] \"rgb sigma_s\" [1.5 1.0 0.6] \"float g\" 0.3\n\
    AttributeBegin\n  MediumInterface \"ball\" \"\"\n  Material \"interface\"\n  Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n";

#[test]
fn simple_volumetric_path_tracing_agrees_with_the_volumetric_path_tracer() {
    // Delta tracking at the hero wavelength without light sampling against null scattering
    // with spectral MIS and next-event estimation: the same image within noise (pixels are
    // independent estimates of the difference).
    let dir = tmpdir("simple-volpath");
    let depth = "\"integer maxdepth\" 8";
    let volpath = render(&dir, "volpath", MEDIUM_BALL, &format!("Integrator \"volpath\" {depth}"));
    let simple = render(&dir, "simple", MEDIUM_BALL, &format!("Integrator \"simplevolpath\" {depth}"));
    let (y, _) = mean_y(&volpath);
    assert!(y > 0.05, "black image");
    let (d, se, _) = film_difference(&simple, &volpath);
    assert!(d.abs() < 4.0 * se, "simplevolpath differs from volpath by {d} ± {se} (mean Y {y})");
    // The ball is in view: its centre is not the sky of the corners.
    let y_at = |f: &Film, i: usize| f.pixels[i].xyz_sum.y / f.pixels[i].weight_sum;
    let (centre, corner) = (y_at(&volpath, 12 * 24 + 12), y_at(&volpath, 0));
    assert!((centre - corner).abs() > 0.1 * corner, "centre {centre}, corner {corner}");
}
