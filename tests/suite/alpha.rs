//! Alpha cut-outs (pbrt-v4's shape `alpha`), on every backend: camera rays see through the cut
//! squares of a textured mask, and a fractional alpha lets through, in expectation, its
//! complement of the light that shadow rays carry.

use crate::common::{backends, pbrt_scene as scene, test_settings};
use prism::film::Film;
use prism::render::render;

fn y(film: &Film, x: u32, yy: u32) -> f64 {
    let p = &film.pixels[(yy * film.width + x) as usize];
    p.xyz_sum.y / p.weight_sum
}

/// A 2 × 2 checkerboard mask on a quad that fills the view, under a uniform sky of radiance 1:
/// through the cut squares the camera sees the sky (Y = 1), on the kept ones the white diffuse
/// quad (Y = ρ = 0.5: a lone plane under a uniform sky reflects ρ L).
#[test]
fn camera_rays_see_through_the_cut_squares() {
    let text = r#"
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" [ 22.62 ]
WorldBegin
LightSource "infinite" "rgb L" [ 1 1 1 ]
Texture "mask" "float" "checkerboard" "float uscale" [ 2 ] "float vscale" [ 2 ] "float tex1" [ 1 ] "float tex2" [ 0 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "bilinearmesh" "point3 P" [ -1 -1 0  1 -1 0  -1 1 0  1 1 0 ] "point2 uv" [ 0 0  1 0  0 1  1 1 ]
  "texture alpha" "mask"
"#;
    // tan(11.31°) · 5 = 1: the quad fills the view.
    let s = test_settings((32, 32), 64, 3, 5);
    for accel in backends() {
        let (film, _) = render(&scene(text, accel), &s, |_| {}).unwrap();
        // Pixel centres of the four squares: one parity keeps the quad, the other cuts it.
        let corners = [(8, 8), (24, 8), (8, 24), (24, 24)].map(|(x, yy)| y(&film, x, yy));
        let (mut sky, mut quad) = (0, 0);
        for v in corners {
            if (v - 1.0).abs() < 0.02 {
                sky += 1;
            } else if (v - 0.5).abs() < 0.1 {
                quad += 1;
            } else {
                panic!("{accel:?}: a square's centre has Y {v}, neither the sky's 1 nor the quad's 0.5: {corners:?}");
            }
        }
        assert_eq!((sky, quad), (2, 2), "{accel:?}: {corners:?}");
        assert!((corners[0] - corners[3]).abs() < 0.1 && (corners[1] - corners[2]).abs() < 0.1, "{corners:?}");
    }
}

/// A sun straight above a floor, with a quad of alpha a between them and the camera below the
/// quad: direct light only (depth 1), so each floor sample is lit with probability 1 − a and the
/// image's mean falls to (1 − a) × the unshadowed one, within the Bernoulli standard error.
#[test]
fn fractional_alpha_passes_its_complement_of_the_light() {
    let base = r#"
LookAt 0 0 1  0 0 0  0 1 0
Camera "perspective" "float fov" [ 60 ]
WorldBegin
LightSource "distant" "point3 from" [ 0 0 10 ] "point3 to" [ 0 0 0 ] "rgb L" [ 3 3 3 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "bilinearmesh" "point3 P" [ -5 -5 0  5 -5 0  -5 5 0  5 5 0 ]
"#;
    let a = 0.25;
    let occluder =
        format!("Shape \"bilinearmesh\" \"point3 P\" [ -5 -5 2  5 -5 2  -5 5 2  5 5 2 ] \"float alpha\" [ {a} ]\n");
    let (w, h, spp) = (24u32, 24u32, 16u64);
    let s = test_settings((w, h), spp, 11, 1);
    for accel in backends() {
        let (open, _) = render(&scene(base, accel), &s, |_| {}).unwrap();
        let (shaded, _) = render(&scene(&format!("{base}{occluder}"), accel), &s, |_| {}).unwrap();
        let mean =
            |f: &Film| (0..h).flat_map(|yy| (0..w).map(move |x| (x, yy))).map(|(x, yy)| y(f, x, yy)).sum::<f64>();
        let ratio = mean(&shaded) / mean(&open);
        let n = f64::from(w * h) * spp as f64;
        let se = (a * (1.0 - a) / n).sqrt();
        assert!(mean(&open) > 0.0, "{accel:?}: black image");
        assert!((ratio - (1.0 - a)).abs() <= 4.0 * se, "{accel:?}: lit fraction {ratio} vs {} ± {se}", 1.0 - a);
    }
}
