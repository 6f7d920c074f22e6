//! Motion blur: a moving instance hit at time t is the instance placed at its interpolated
//! transform (pbrt-v4's `AnimatedTransform`, PBR 4th ed. §3.10.1) on every backend; a square
//! translating by its own width over the shutter blurs into the tent-shaped coverage the
//! shutter integral gives, and so does a curve of that shape, moving by itself or held by a
//! moving object instance; a moving instance of a sphere blurs as the moving sphere does; a
//! scene where nothing moves draws no time sample.

use crate::common::{backends, film_difference, pbrt_scene as scene, pixels_far_off, test_settings};
use glam::{Mat4, Quat, Vec3};
use prism::camera::Camera;
use prism::geometry::shapes::{axis_box, icosphere};
use prism::geometry::{AnimatedTransform, Hit, Ray};
use prism::material::Material;
use prism::render::render;
use prism::sampling::Rng;
use prism::scene::{Scene, SceneBuilder};
use prism::spectrum::Spectrum;

/// Relative tolerance on hit distances: object-space rays through two roundings of the same
/// transform, a few ulps each.
const T_REL_TOL: f32 = 1e-4;

/// The motions under test: keyframes T·R·S with diagonal positive stretches, so the polar
/// decomposition and Embree's quaternion decomposition coincide.
fn motions() -> [AnimatedTransform; 2] {
    let axis = Vec3::new(0.3, 1.0, -0.2).normalize();
    let a = Mat4::from_translation(Vec3::new(-2.0, 1.0, 0.0)) * Mat4::from_scale(Vec3::new(1.0, 0.6, 1.2));
    let b = Mat4::from_translation(Vec3::new(1.5, 1.8, 0.5))
        * Mat4::from_quat(Quat::from_axis_angle(axis, 2.1))
        * Mat4::from_scale(Vec3::new(1.4, 0.9, 0.7));
    let c = Mat4::from_translation(Vec3::new(0.0, 0.5, 4.0));
    let d = Mat4::from_translation(Vec3::new(0.0, 2.5, 4.0)) * Mat4::from_rotation_z(1.2);
    [AnimatedTransform::new(a, 0.0, b, 1.0), AnimatedTransform::new(c, 0.0, d, 1.0)]
}

/// A sphere with a box below it, moved by `place` (the instance's motion, or its transform at
/// one time).
fn builder(place: impl Fn(&mut SceneBuilder, u32, &AnimatedTransform) -> bool) -> SceneBuilder {
    let mut b = SceneBuilder::new();
    let grey = b.add_material(Material::diffuse(Spectrum::constant(0.6)));
    let p = b.add_prototype(vec![
        (icosphere(Vec3::ZERO, 1.0, 3), grey),
        (axis_box(Vec3::new(-0.4, -1.6, -0.4), Vec3::new(0.4, -1.0, 0.4)), grey),
    ]);
    for m in motions() {
        assert!(place(&mut b, p, &m));
    }
    b.set_camera(Camera::look_at(Vec3::new(0.0, 2.0, -8.0), Vec3::new(0.0, 1.0, 2.0), Vec3::Y), 60.0);
    b
}

/// The closest hit of `ray` in both scenes agree: the same surface, distance and normal.
fn assert_same_hit(what: &str, a: Option<Hit>, b: Option<Hit>, ray: &Ray, scene: &Scene) -> bool {
    match (a, b) {
        (None, None) => false,
        (Some(a), Some(b)) => {
            let tol = T_REL_TOL * a.t.max(1.0);
            assert!((a.t - b.t).abs() <= tol, "{what}: t {} vs {} for {ray:?}", a.t, b.t);
            assert_eq!(a.inst_id, b.inst_id, "{what}: instance for {ray:?}");
            assert_eq!(a.prim_id, b.prim_id, "{what}: triangle for {ray:?}");
            assert_eq!(
                scene.primitives()[a.geom_id as usize].material,
                scene.primitives()[b.geom_id as usize].material
            );
            let (na, nb) = (a.ng.normalize(), b.ng.normalize());
            assert!(na.dot(nb) > 0.999, "{what}: normals {na} vs {nb}");
            true
        }
        (a, b) => panic!("{what}: moving {a:?} vs placed {b:?} for {ray:?}"),
    }
}

#[test]
fn a_moving_instance_at_time_t_is_hit_as_the_instance_placed_at_t_on_every_backend() {
    for kind in backends() {
        let moving = builder(|b, p, m| b.add_moving_instance(p, *m)).build(kind).unwrap();
        assert_eq!(moving.shutter, Some((0.0, 1.0)));
        let mut rng = Rng::new(23, 1);
        let mut hits = 0;
        for t in [0.0, 0.2, 0.5, 0.77, 1.0] {
            let placed = builder(|b, p, m| b.add_instance(p, m.interpolate(t))).build(kind).unwrap();
            assert_eq!(placed.shutter, None);
            for _ in 0..4000 {
                // Rays from a box around the motion towards a point near the paths.
                let o = Vec3::new(rng.uniform() * 12.0 - 6.0, rng.uniform() * 6.0 - 1.0, -6.0);
                let target = Vec3::new(rng.uniform() * 6.0 - 3.0, rng.uniform() * 4.0, rng.uniform() * 6.0);
                let ray = Ray::new(o, (target - o).normalize()).at_time(t);
                let what = format!("{kind:?} at t = {t}");
                let (a, b) = (moving.closest_hit(&ray), placed.closest_hit(&Ray::new(ray.o, ray.d)));
                assert_eq!(moving.occluded(&ray), a.is_some(), "{what}: occluded disagrees with intersect");
                hits += assert_same_hit(&what, a, b, &ray, &moving) as usize;
            }
        }
        assert!(hits > 4000, "{kind:?}: only {hits} of 20000 rays hit");
    }
}

/// An orthographic view (4 × 4 world units on 64 × 64 pixels, world x = column) of a black
/// square x ∈ [−1, 0] that translates by its own width during the shutter, in front of a
/// uniformly emitting wall, and a square that does not move, y ∈ [−1.5, 1.5].
const TRANSLATING_SQUARE: &str = r#"
LookAt 0 0 -5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -2 2 -2 2 ] "float shutteropen" [ 0 ] "float shutterclose" [ 1 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 1 1 1 ] "bool twosided" true
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "bilinearmesh" "point3 P" [ -3 -3 1  3 -3 1  -3 3 1  3 3 1 ]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  ActiveTransform StartTime
  Translate 0 0 0
  ActiveTransform EndTime
  Translate 1 0 0
  ActiveTransform All
  Shape "bilinearmesh" "point3 P" [ -1 -1.5 0  0 -1.5 0  -1 1.5 0  0 1.5 0 ]
AttributeEnd
"#;

/// The fraction of the shutter interval [0, 1] during which the square [−1 + t, t] covers
/// world x: a tent rising over [−1, 0] and falling over [0, 1].
fn coverage(x: f64) -> f64 {
    (1.0 - x.abs()).max(0.0)
}

/// The square of [`TRANSLATING_SQUARE`] as a flat curve (a ribbon facing the ray: the
/// orthographic rays see a band 1 wide) along y at x = −0.5.
const CURVE_SQUARE: &str =
    r#"Shape "curve" "point3 P" [ -0.5 -1.5 0  -0.5 -0.5 0  -0.5 0.5 0  -0.5 1.5 0 ] "float width" 1"#;

/// [`TRANSLATING_SQUARE`]'s square shape.
const SQUARE: &str = r#"Shape "bilinearmesh" "point3 P" [ -1 -1.5 0  0 -1.5 0  -1 1.5 0  0 1.5 0 ]"#;

/// [`TRANSLATING_SQUARE`] with the curve square, and with the curve square as an object
/// instance that translates.
fn translating_curves() -> [String; 2] {
    let moving_curve = TRANSLATING_SQUARE.replace(SQUARE, CURVE_SQUARE);
    let instanced = moving_curve.replace(
        "AttributeBegin\n  Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n  ActiveTransform StartTime",
        &format!(
            "ObjectBegin \"c\"\n  Material \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n  {CURVE_SQUARE}\nObjectEnd\n\
             AttributeBegin\n  ActiveTransform StartTime"
        ),
    );
    let instanced = instanced
        .replace(&format!("ActiveTransform All\n  {CURVE_SQUARE}"), "ActiveTransform All\n  ObjectInstance \"c\"");
    assert!(moving_curve.contains("curve") && instanced.contains("ObjectInstance"), "{instanced}");
    [moving_curve, instanced]
}

#[test]
fn a_translating_square_blurs_into_its_shutter_coverage() {
    assert!(TRANSLATING_SQUARE.contains(SQUARE));
    let [curve, instanced_curve] = translating_curves();
    for (what, text) in [("square", TRANSLATING_SQUARE), ("curve", &curve), ("instanced curve", &instanced_curve)] {
        assert_blurs_into_the_tent(what, text);
    }
}

/// The image of `text` (a [`TRANSLATING_SQUARE`]) transmits 1 − coverage in each column.
fn assert_blurs_into_the_tent(what: &str, text: &str) {
    const N: u32 = 64;
    let settings = test_settings((N, N), 64, 5, 1);
    for accel in backends() {
        let kind = format!("{what} {accel:?}");
        let s = scene(text, accel);
        assert_eq!(s.shutter, Some((0.0, 1.0)));
        let film = render(&s, &settings, |_| {}).unwrap().0;
        let y = |col: u32, row: u32| {
            let p = &film.pixels[(row * N + col) as usize];
            p.xyz_sum.y / p.weight_sum
        };
        // The wall's radiance: the mean of the columns the square never reaches (|x| > 1.25).
        let rows = 10..54; // |y| < 1.375: inside the square's height.
        let wall: Vec<f64> =
            rows.clone().flat_map(|r| (0..12).chain(52..N).map(move |c| (c, r))).map(|(c, r)| y(c, r)).collect();
        let l = wall.iter().sum::<f64>() / wall.len() as f64;
        assert!(l > 0.1, "{kind}: the wall is black ({l})");
        // The box filter averages each pixel's area, and the tent is linear inside every pixel
        // (its kinks at x = −1, 0, 1 are pixel edges), so each pixel's expected value is
        // L · (1 − coverage) at its centre. The standard error of each column's mean is
        // measured from its spread over the rows.
        let mut worst = 0.0f64;
        for col in 12..52 {
            let x = -2.0 + (f64::from(col) + 0.5) * 4.0 / f64::from(N);
            let v: Vec<f64> = rows.clone().map(|r| y(col, r) / l).collect();
            let n = v.len() as f64;
            let mean = v.iter().sum::<f64>() / n;
            let var = v.iter().map(|a| (a - mean) * (a - mean)).sum::<f64>() / (n - 1.0);
            let se = (var / n).sqrt().max(1e-3);
            let want = 1.0 - coverage(x);
            let z = (mean - want).abs() / se;
            worst = worst.max(z);
            assert!(z <= 4.0, "{kind}: column {col} (x = {x:.3}) transmits {mean:.4} ± {se:.4}, want {want:.4}");
        }
        // A sharp image (the square at its start or end position) would be 0 over a unit width.
        let middle: f64 = rows.clone().map(|r| y(31, r) / l).sum::<f64>() / rows.len() as f64;
        assert!(middle < 0.1, "{kind}: x = −0.03 is covered for 97% of the shutter, transmits {middle}");
        eprintln!("{kind}: worst column {worst:.2}σ");
    }
}

#[test]
fn only_a_scene_where_something_moves_samples_a_time() {
    let still = TRANSLATING_SQUARE.replace("Translate 1 0 0", "Translate 0 0 0");
    for kind in backends() {
        assert_eq!(scene(&still, kind).shutter, None);
        assert_eq!(scene(TRANSLATING_SQUARE, kind).shutter, Some((0.0, 1.0)));
    }
}

/// Motions Embree cannot follow with two quaternion steps, so it samples them
/// (`SAMPLED_STEPS` = 33 steps over the scene's time span [0, 1]): a stretch along a rotated
/// axis, a mirror at both keyframes, a rigid motion over [0.25, 0.75] (its ends on steps) and
/// one over [0.1, 0.6] (its ends between steps), side by side.
fn sampled_motions() -> [AnimatedTransform; 4] {
    let a = Mat4::from_translation(Vec3::new(1.3, 0.5, 0.2));
    let turned = Mat4::from_translation(Vec3::new(-0.4, 1.0, 0.7)) * Mat4::from_rotation_y(1.3);
    let mirror = Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0));
    let at = |x: f32| Mat4::from_translation(Vec3::new(x, 0.0, 3.0));
    [
        AnimatedTransform::new(at(-4.5) * a, 0.0, at(-4.5) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)) * turned, 1.0),
        AnimatedTransform::new(at(-1.5) * a * mirror, 0.0, at(-1.5) * turned * mirror, 1.0),
        AnimatedTransform::new(at(1.5) * a, 0.25, at(1.5) * turned, 0.75),
        AnimatedTransform::new(at(4.5) * a, 0.1, at(4.5) * turned, 0.6),
    ]
}

/// The largest distance [scene units] between where Embree's sampled steps put a point of the
/// prototype (|p| ≤ 1.7) and where the polar interpolation does, for `sampled_motions`: the
/// bound h²/8 · max|e″| derived in src/accel/embree/motion.rs (`error_bound`, for |p| ≤ √3) for
/// these keyframes, 1.2·10⁻³ to 4.95·10⁻³ (the motions over part of the span); the errors
/// measured there are 10⁻⁶ to 7·10⁻⁵.
const SAMPLED_POSITION_BOUND: f32 = 4.95e-3;

#[test]
fn sampled_motion_steps_place_an_instance_within_their_bound_of_its_interpolated_transform() {
    let build = |place: &dyn Fn(&mut SceneBuilder, u32, &AnimatedTransform) -> bool| {
        let mut b = SceneBuilder::new();
        let grey = b.add_material(Material::diffuse(Spectrum::constant(0.6)));
        let p = b.add_prototype(vec![
            (icosphere(Vec3::ZERO, 1.0, 3), grey),
            (axis_box(Vec3::new(-0.4, -1.6, -0.4), Vec3::new(0.4, -1.0, 0.4)), grey),
        ]);
        for m in sampled_motions() {
            assert!(place(&mut b, p, &m));
        }
        b.set_camera(Camera::look_at(Vec3::new(0.0, 2.0, -8.0), Vec3::new(0.0, 1.0, 2.0), Vec3::Y), 60.0);
        b
    };
    for kind in backends() {
        let moving = build(&|b, p, m| b.add_moving_instance(p, *m)).build(kind).unwrap();
        let mut rng = Rng::new(41, 3);
        let (mut both, mut one_sided, mut worst) = (0usize, 0usize, 0.0f32);
        for t in [0.0, 0.1, 0.2, 0.33, 0.5, 0.6, 0.77, 1.0] {
            let placed = build(&|b, p, m| b.add_instance(p, m.interpolate(t))).build(kind).unwrap();
            for _ in 0..4000 {
                let o = Vec3::new(rng.uniform() * 16.0 - 8.0, rng.uniform() * 6.0 - 1.0, -4.0);
                let target =
                    Vec3::new(rng.uniform() * 12.0 - 6.0, rng.uniform() * 4.0 - 1.0, 1.0 + rng.uniform() * 5.0);
                let ray = Ray::new(o, (target - o).normalize()).at_time(t);
                let what = format!("{kind:?} at t = {t}");
                let (a, b) = (moving.closest_hit(&ray), placed.closest_hit(&Ray::new(ray.o, ray.d)));
                assert_eq!(moving.occluded(&ray), a.is_some(), "{what}: occluded disagrees with intersect");
                if kind == prism::accel::AccelKind::Obvhs {
                    // obvhs interpolates the transform itself: the same hits.
                    both += assert_same_hit(&what, a, b, &ray, &moving) as usize;
                    continue;
                }
                match (a, b) {
                    (Some(a), Some(b)) => {
                        both += 1;
                        assert_eq!(a.inst_id, b.inst_id, "{what}: instance for {ray:?}");
                        // The moving hit lies on the placed surface up to the bound: its offset
                        // along the placed hit's normal (the normal is in world space).
                        let n = b.ng.normalize();
                        let off = n.dot(ray.at(a.t) - ray.at(b.t)).abs();
                        worst = worst.max(off);
                        assert!(off <= SAMPLED_POSITION_BOUND + 1e-4, "{what}: {off} off the surface for {ray:?}");
                    }
                    (None, None) => {}
                    _ => one_sided += 1,
                }
            }
        }
        eprintln!("{kind:?}: {both} hits on both, {one_sided} on one only, largest offset {worst:.2e}");
        assert!(both > 4000, "{kind:?}: only {both} rays hit");
        // A ray passing within the bound of a silhouette may hit on one side only.
        assert!(one_sided * 200 < both, "{kind:?}: {one_sided} one-sided of {both}");
    }
}

/// A partial sphere that moves and turns over the shutter in front of a lit wall: as a moving
/// shape, or held by a moving object instance.
fn moving_sphere(instanced: bool) -> String {
    let motion =
        "ActiveTransform StartTime\n  Translate -0.8 0 0\n  ActiveTransform EndTime\n  Translate 0.9 0.4 0\n  \
                  Rotate 70 0 1 0.3\n  ActiveTransform All";
    let sphere = "Material \"diffuse\" \"rgb reflectance\" [ 0.7 0.4 0.2 ]\n  \
                  Shape \"sphere\" \"float radius\" 0.9 \"float zmin\" -0.5 \"float phimax\" 300";
    let moved = if instanced {
        format!("ObjectBegin \"s\"\n  {sphere}\nObjectEnd\nAttributeBegin\n  {motion}\n  ObjectInstance \"s\"\nAttributeEnd")
    } else {
        format!("AttributeBegin\n  {motion}\n  {sphere}\nAttributeEnd")
    };
    format!(
        r#"LookAt 0 0 -6  0 0 0  0 1 0
Camera "perspective" "float fov" 40
WorldBegin
LightSource "distant" "point3 from" [ -1 2 -3 ] "point3 to" [ 0 0 0 ] "rgb L" [ 2 2 2 ]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 0.6 0.6 0.6 ]
  Shape "bilinearmesh" "point3 P" [ -4 -4 2  4 -4 2  -4 4 2  4 4 2 ]
AttributeEnd
{moved}
"#
    )
}

#[test]
fn a_moving_instance_of_a_sphere_blurs_as_the_moving_sphere_does() {
    // Two different paths: the moving sphere is intersected where it is at the ray's time; the
    // instance carries the ray into its space. The images agree within noise (same seed), and
    // differ from the sphere standing at its start.
    let settings = test_settings((48, 32), 32, 9, 3);
    for kind in backends() {
        let moving = scene(&moving_sphere(false), kind);
        let instanced = scene(&moving_sphere(true), kind);
        assert_eq!((moving.shutter, instanced.shutter), (Some((0.0, 1.0)), Some((0.0, 1.0))));
        assert_eq!((moving.instances().len(), instanced.instances().len()), (0, 1));
        let (a, sa) = render(&instanced, &settings, |_| {}).unwrap();
        let (b, sb) = render(&moving, &settings, |_| {}).unwrap();
        assert_eq!((sa.nonfinite, sb.nonfinite), (0, 0));
        let (d, se, mean) = film_difference(&a, &b);
        eprintln!("{kind:?}: mean Y {mean:.4}, difference {d:.2e} ± {se:.2e}");
        assert!(mean > 0.05, "{kind:?}: black image");
        // With one seed both follow the same paths: their difference is rounding, 10⁻⁹ of Y.
        assert!(d.abs() <= 4.0 * se.max(1e-6 * mean), "{kind:?}: {d} ± {se}");
        let still = moving_sphere(false).replace("Translate 0.9 0.4 0\n  Rotate 70 0 1 0.3", "Translate -0.8 0 0");
        assert!(!still.contains("Rotate"));
        let still = scene(&still, kind);
        let (c, _) = render(&still, &settings, |_| {}).unwrap();
        assert!(pixels_far_off(&a, &c) > a.pixels.len() / 20, "{kind:?}: the blur is not visible");
    }
}
