//! pbrt-v4's `regularize`: a caustic that a path tracer cannot find (a point light seen in a
//! smooth mirror from a diffuse floor) appears once the mirror's lobe is widened after the
//! floor's bounce, with about the mirror image's irradiance; without it only the direct light
//! arrives, which is a closed form.

use crate::common::pbrt_scene;
use glam::Vec3;
use prism::accel::AccelKind;
use prism::integrator::Integrator;
use prism::measure::irradiance;

/// A point light at (1, 0, 0.2) and a perfect mirror (reflectance 1, roughness 0) filling the
/// plane z = 2 above a sensor at the origin facing +z.
const SCENE: &str = r#"Camera "perspective" WorldBegin
LightSource "point" "point3 from" [ 1 0 0.2 ] "rgb I" [ 1 1 1 ]
Material "conductor" "rgb reflectance" [ 1 1 1 ] "float roughness" [ 0 ]
Shape "trianglemesh" "point3 P" [ -30 -30 2  30 -30 2  30 30 2  -30 30 2 ] "integer indices" [ 0 1 2 0 2 3 ]
"#;

#[test]
fn regularization_finds_the_mirrored_point_light() {
    let scene = pbrt_scene(SCENE, AccelKind::Obvhs);
    let (p, light) = (Vec3::ZERO, Vec3::new(1.0, 0.0, 0.2));
    // E ∝ I cos θ / d² from the light and from its mirror image at (1, 0, 3.8).
    let e = |q: Vec3| ((q.z / q.length()) / q.length_squared()) as f64;
    let (direct, image) = (e(light), e(Vec3::new(1.0, 0.0, 3.8)));
    let measure = |regularize: bool| {
        let integ = Integrator { max_depth: 2, regularize, ..Default::default() };
        irradiance(&scene, &integ, p, Vec3::Z, 200_000, 3).illuminance
    };
    let (plain, widened) = (measure(false), measure(true));
    // Without: the direct light only, whose sole noise is the wavelengths' (the same in both
    // runs, which share the seed and so the wavelengths).
    let unit = plain.mean / direct;
    assert!(unit > 0.0 && plain.std_err <= 1e-3 * plain.mean, "{} ± {}", plain.mean, plain.std_err);
    // With: the mirror image's irradiance on top, within the energy a GGX lobe of α = 0.1
    // loses or redistributes over the finite solid angle (10 %), and far beyond the noise.
    let caustic = (widened.mean - plain.mean) / unit;
    assert!(widened.std_err < 0.02 * image * unit, "± {}", widened.std_err);
    assert!((caustic / image - 1.0).abs() < 0.10, "caustic {caustic} against the image's {image}");
}

#[test]
fn the_integrator_reads_regularize() {
    for (text, want) in [("", None), ("\"bool regularize\" true", Some(true))] {
        let scene = format!("Integrator \"path\" {text}\n{SCENE}");
        let (desc, mut warnings) = prism::pbrt::parse_str(&scene, &Default::default()).unwrap();
        let (_, file) = prism::pbrt::build(&desc, &mut warnings).unwrap();
        assert_eq!(file.regularize, want);
    }
}
