//! pbrt-v4 scene defaults and surfaces that are no surface: an `interface` material (and the
//! deprecated `""`/`"none"`) lets camera rays and shadow rays through, `volpath` without media
//! is `path`, a file without `maxdepth` gets pbrt-v4's 5, the Film's `maxcomponentvalue`
//! and `savefp16` and every pixel filter's parameters are read.

use crate::common::{film_difference, test_settings};
use prism::accel::AccelKind;
use prism::filter::FilterKind;
use prism::pbrt::{build, FileSettings};
use prism::pbrt::{parse_str, Warning};
use prism::render::render;

const HEADER: &str = r#"
LookAt 0 4 0  0 0 0  0 0 1
Camera "perspective" "float fov" [ 50 ]
Integrator "volpath"
WorldBegin
LightSource "point" "point3 from" [ 0 1 0 ] "blackbody I" [ 5000 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "bilinearmesh" "point3 P" [ -3 0 -3  3 0 -3  -3 0 3  3 0 3 ]
"#;

/// The point light sits inside this sphere, and the camera looks through it at the floor.
fn sphere(material: &str) -> String {
    format!("AttributeBegin\n Material {material}\n Translate 0 1 0\n Shape \"sphere\" \"float radius\" [ 0.5 ]\nAttributeEnd\n")
}

fn load(text: &str) -> (prism::scene::Scene, FileSettings, Vec<Warning>) {
    let (desc, mut warnings) = parse_str(text, &Default::default()).unwrap();
    let (builder, settings) = build(&desc, &mut warnings).unwrap();
    (builder.build(AccelKind::default_available()).unwrap(), settings, warnings)
}

#[test]
fn an_interface_around_a_light_changes_nothing_for_camera_or_shadow_rays() {
    let s = test_settings((24, 24), 16, 7, 5);
    let (bare, _, warnings) = load(HEADER);
    assert!(warnings.is_empty(), "{warnings:?}");
    let (reference, _) = render(&bare, &s, |_| {}).unwrap();
    for material in [r#""interface""#, r#""""#, r#""none""#] {
        let (scene, _, warnings) = load(&format!("{HEADER}{}", sphere(material)));
        let unsupported: Vec<_> = warnings.iter().filter(|w| w.strict_error().is_some()).collect();
        assert!(unsupported.is_empty(), "{material}: {unsupported:?}");
        if material != r#""interface""# {
            assert!(warnings.iter().any(|w| w.message.contains("deprecated")), "{material}: {warnings:?}");
        }
        let (img, _) = render(&scene, &s, |_| {}).unwrap();
        // The same sample draws reach the same floor points: only the rays' origins differ by
        // the offsets past the sphere, so the images agree within their noise.
        let (m, se, mean) = film_difference(&img, &reference);
        assert!(mean > 0.01, "{material}: black image (mean Y {mean})");
        assert!(m.abs() <= 4.0 * se + 1e-5 * mean, "{material}: mean difference {m} ± {se} of {mean}");
    }
    // An opaque sphere around the light is what failing looks like: the floor goes dark.
    let (opaque, _, _) = load(&format!("{HEADER}{}", sphere(r#""diffuse""#)));
    let (img, _) = render(&opaque, &s, |_| {}).unwrap();
    let (_, _, mean) = film_difference(&img, &reference);
    let (_, _, ref_mean) = film_difference(&reference, &img);
    assert!(mean < 0.5 * ref_mean, "opaque sphere: {mean} vs {ref_mean}");
}

#[test]
fn pbrt_v4_defaults_volpath_depth_and_film_parameters() {
    let film = r#"Film "rgb" "float maxcomponentvalue" [ 4 ] "bool savefp16" [ false ]
PixelFilter "gaussian" "float xradius" [ 2.5 ] "float sigma" [ 0.8 ]"#;
    let (_, settings, warnings) = load(&format!("{film}\n{HEADER}"));
    assert!(warnings.is_empty(), "{warnings:?}");
    let filter = settings.filter.unwrap();
    assert_eq!(filter.kind(), FilterKind::Gaussian { sigma: 0.8 });
    assert_eq!(filter.radius(), glam::Vec2::new(2.5, 1.5));
    assert_eq!(settings.max_depth, Some(5));
    assert_eq!(settings.max_component, Some(4.0));
    assert_eq!(settings.save_fp16, Some(false));
    let deep = HEADER.replace(r#"Integrator "volpath""#, r#"Integrator "path" "integer maxdepth" [ 11 ]"#);
    let (_, settings, _) = load(&deep);
    assert_eq!(settings.max_depth, Some(11));
    for (text, kind, radius) in [
        (
            r#"PixelFilter "mitchell" "float B" [ 0.5 ] "float C" [ 0.25 ]"#,
            FilterKind::Mitchell { b: 0.5, c: 0.25 },
            2.0,
        ),
        (r#"PixelFilter "sinc" "float tau" [ 2 ] "float yradius" [ 3 ]"#, FilterKind::LanczosSinc { tau: 2.0 }, 4.0),
        (r#"PixelFilter "triangle""#, FilterKind::Triangle, 2.0),
        (r#"PixelFilter "box""#, FilterKind::Box, 0.5),
    ] {
        let (_, settings, warnings) = load(&format!("{text}\n{HEADER}"));
        assert!(warnings.is_empty(), "{text}: {warnings:?}");
        let f = settings.filter.unwrap();
        assert_eq!((f.kind(), f.radius().x), (kind, radius), "{text}");
    }
}

/// A one-sided emitter emits on the side its normal faces. With per-vertex normals that is the
/// normals' side, and ReverseOrientation negates the normals (pbrt-v4's `TriangleMesh`), so the
/// camera in front of the normals sees the quad's L = 1 without it and black with it.
#[test]
fn reverse_orientation_flips_a_mesh_with_normals() {
    let quad = r#"AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
Shape "trianglemesh" "point3 P" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "integer indices" [ 0 1 2  0 2 3 ]
  "normal N" [ 0 0 1  0 0 1  0 0 1  0 0 1 ]"#;
    let seen = |reverse: &str| {
        let text = format!(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [ -0.5 0.5 -0.5 0.5 ]\nWorldBegin\n{reverse}\n{quad}\n"
        );
        let (scene, _, _) = load(&text);
        let (film, _) = render(&scene, &test_settings((4, 4), 4, 1, 1), |_| {}).unwrap();
        film.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).sum::<f64>() / film.pixels.len() as f64
    };
    let (front, reversed) = (seen(""), seen("ReverseOrientation"));
    assert!(front > 0.5, "the emitting side is black: {front}");
    assert_eq!(reversed, 0.0, "ReverseOrientation must turn the emitting side away");
}
