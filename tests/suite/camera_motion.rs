//! A moving camera (pbrt-v4's camera `AnimatedTransform`): only the motion of the camera
//! relative to the scene is seen, so a camera moving one way past a still scene renders the
//! image of a still camera watching the scene move the opposite way, on every backend. The
//! scenes are black shapes against a uniform infinite light, which no motion changes, so a
//! sample's value is whether its camera ray escapes at its time: the two renders draw the same
//! samples and differ only where rounding flips a ray grazing a silhouette; both must differ
//! from the sharp image of a camera that does not move.

use crate::common::{backends, pbrt_scene as scene, test_settings};
use prism::film::Film;
use prism::render::render;

/// A sphere and a box, black, as the object "scene" (so that a moving instance of it turns
/// about the world's origin, where the cameras are: pbrt-v4 interpolates a transform's
/// translation linearly and its rotation about the origin).
const OBJECT: &str = r#"
ObjectBegin "scene"
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  AttributeBegin
    Translate -0.6 -0.5 7
    Shape "sphere" "float radius" [ 1 ]
  AttributeEnd
  AttributeBegin
    Translate 0.8 -1.5 6
    Shape "trianglemesh" "integer indices" [ 0 1 2  0 2 3  4 5 6  4 6 7  0 1 5  0 5 4  3 2 6  3 6 7  1 2 6  1 6 5  0 3 7  0 7 4 ]
      "point3 P" [ 0 0 0  1 0 0  1 1.6 0  0 1.6 0  0 0 1  1 0 1  1 1.6 1  0 1.6 1 ]
  AttributeEnd
ObjectEnd
"#;

/// `camera` (transforms and the Camera directive), a uniform infinite light, and the object
/// placed by `motion` (transform directives, or nothing for a still scene).
fn scene_text(camera: &str, motion: &str) -> String {
    format!(
        "{camera}\nCamera \"perspective\" \"float fov\" [ 45 ]\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n{OBJECT}\nAttributeBegin\n{motion}\nObjectInstance \"scene\"\nAttributeEnd\n"
    )
}

/// A camera at the origin looking down +z, still.
const STILL: &str = "";

/// Its camera-from-world transform ends translated by −1.5 along x: it slides 1.5 to its
/// right over the shutter. As the scene's motion: the scene slides 1.5 to the left.
const SLIDE: &str = "ActiveTransform EndTime\nTranslate -1.5 0 0\nActiveTransform All";

/// Its camera-from-world transform ends rotated 20° about +y: it turns 20° to its left. As
/// the scene's motion: the scene turns 20° the other way about the camera.
const TURN: &str = "ActiveTransform EndTime\nRotate 20 0 1 0\nActiveTransform All";

/// Per-pixel luminance.
fn luminance(f: &Film) -> Vec<f64> {
    f.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect()
}

/// Root-mean-square difference of two images.
fn rms(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / a.len() as f64).sqrt()
}

/// Renders the moving-camera scene, the moving-scene one with the same samples, the
/// moving-camera scene with other samples (the noise level) and the still camera; checks the
/// first two agree far better than noise, on average within its standard error, and that the
/// still camera's sharp image is farther from both than noise.
fn assert_only_relative_motion_is_seen(motion: &str, what: &str) {
    const N: u32 = 48;
    let settings = |seed| test_settings((N, N), 16, seed, 3);
    for kind in backends() {
        let a = scene(&scene_text(motion, STILL), kind);
        let b = scene(&scene_text(STILL, motion), kind);
        let still = scene(&scene_text(STILL, STILL), kind);
        assert_eq!((a.shutter, b.shutter, still.shutter), (Some((0.0, 1.0)), Some((0.0, 1.0)), None));
        let img = |s: &prism::scene::Scene, seed| luminance(&render(s, &settings(seed), |_| {}).unwrap().0);
        let (ya, yb, ya_other, y_still) = (img(&a, 3), img(&b, 3), img(&a, 4), img(&still, 3));
        let mean = ya.iter().sum::<f64>() / ya.len() as f64;
        assert!(mean > 0.05, "{what}, {kind:?}: the image is black ({mean})");
        let noise = rms(&ya, &ya_other);
        let same_samples = rms(&ya, &yb);
        let sharp = rms(&ya, &y_still);
        // The mean difference is within 4 standard errors of the per-pixel differences.
        let d: Vec<f64> = ya.iter().zip(&yb).map(|(x, y)| x - y).collect();
        let md = d.iter().sum::<f64>() / d.len() as f64;
        let se = (d.iter().map(|v| (v - md) * (v - md)).sum::<f64>() / (d.len() as f64 - 1.0) / d.len() as f64).sqrt();
        eprintln!("{what}, {kind:?}: rms moving camera vs moving scene {same_samples:.2e}, noise {noise:.2e}, vs still camera {sharp:.2e}; mean difference {md:.2e} ± {se:.2e}");
        assert!(same_samples < 0.1 * noise, "{what}, {kind:?}: {same_samples} vs noise {noise}");
        assert!(md.abs() <= 4.0 * se.max(1e-9), "{what}, {kind:?}: mean difference {md} ± {se}");
        assert!(
            sharp > 2.0 * noise,
            "{what}, {kind:?}: the still camera's image is as near as noise ({sharp} vs {noise})"
        );
    }
}

#[test]
fn a_camera_sliding_past_a_still_scene_sees_the_scene_sliding_past_a_still_camera() {
    assert_only_relative_motion_is_seen(SLIDE, "sliding");
}

#[test]
fn a_turning_camera_sees_the_scene_turning_the_other_way_about_it() {
    assert_only_relative_motion_is_seen(TURN, "turning");
}

#[test]
fn the_camera_named_coordinate_system_moves_with_the_camera() {
    // pbrt-v4 names both of the camera's transforms "camera": a shape placed there moves with
    // it, so it stays put on the film while the rest of the scene blurs.
    let text = format!(
        "{SLIDE}\nCamera \"perspective\"\nWorldBegin\nCoordSysTransform \"camera\"\nTranslate 0 0 3\nShape \"sphere\" \"float radius\" [ 0.5 ]\n"
    );
    for kind in backends() {
        let s = scene(&text, kind);
        assert_eq!(s.shutter, Some((0.0, 1.0)));
        // Rays from the camera's position at each time straight ahead hit the sphere 2.5 away;
        // where the camera started, the sphere has gone by time 1.
        for t in [0.0, 0.3, 1.0] {
            let ray = |x: f32| prism::geometry::Ray::new(glam::Vec3::new(x, 0.0, 0.0), glam::Vec3::Z).at_time(t);
            let hit = s.closest_hit(&ray(1.5 * t)).expect("the sphere ahead");
            assert!((hit.t - 2.5).abs() < 1e-3, "{kind:?} at {t}: t = {}", hit.t);
            assert_eq!(s.closest_hit(&ray(0.0)).is_some(), t < 0.5, "{kind:?} at {t}");
        }
    }
}
