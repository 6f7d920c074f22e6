//! Object instances hold every shape pbrt-v4 lets them hold: curves, exact quadrics (sphere,
//! partial sphere, disk, cylinder) and moving shapes inside `ObjectBegin`, and moving curves
//! anywhere. Each scene is read twice — instanced, and written flat with every shape placed by
//! hand — and the two give the same surfaces ray by ray on every backend (distance, world-space
//! point within its error bound, normal, (u, v), material) and the same image within noise. An
//! instanced sphere is the exact sphere: grazing rays hit it or miss it as the closed form says,
//! at points on it within their error bounds (an inscribed mesh lies up to 1.1·10⁻³ of the
//! radius inside it). None of these scenes reads with an unsupported-feature warning
//! (`common::pbrt_scene` checks it).

use crate::common::{film_difference, pbrt_scene, test_settings};
use glam::{DVec3, Mat4, Quat, Vec3};
use prism::accel::AccelKind;
use prism::geometry::{AnimatedTransform, Hit, Ray, Shape};
use prism::render::render;
use prism::sampling::Rng;
use prism::scene::{Scene, SurfaceInteraction};

/// Relative tolerance on hit distances between a shape met through an instance (ray carried into
/// object space) and its flat copy (shape carried into world space): a few ulps of each.
const T_REL_TOL: f32 = 1e-4;

/// Every backend and triangle test.
fn ray_accels() -> Vec<AccelKind> {
    let mut v = vec![AccelKind::Obvhs];
    if cfg!(embree) {
        v.extend([AccelKind::Embree, AccelKind::EmbreeWatertight]);
    }
    v
}

/// A camera, a sun, a sky and a ground under `world`.
fn scene_text(world: &str) -> String {
    format!(
        r#"LookAt 0 5 -13  0 0.5 1  0 1 0
Camera "perspective" "float fov" 50
WorldBegin
LightSource "distant" "point3 from" [ 1 4 -2 ] "point3 to" [ 0 0 0 ] "rgb L" [ 3 3 3 ]
LightSource "infinite" "rgb L" [ 0.3 0.35 0.4 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "bilinearmesh" "point3 P" [ -20 -2.5 -20  20 -2.5 -20  -20 -2.5 20  20 -2.5 20 ]
{world}
"#
    )
}

/// `body` as one object placed by each of `placements` (transform directives), instanced.
fn instanced(body: &str, placements: &[&str]) -> String {
    let uses: String =
        placements.iter().map(|p| format!("AttributeBegin\n{p}\nObjectInstance \"o\"\nAttributeEnd\n")).collect();
    scene_text(&format!("ObjectBegin \"o\"\n{body}\nObjectEnd\n{uses}"))
}

/// The same as [`instanced`], every copy of `body` written out in the world.
fn flat(body: &str, placements: &[&str]) -> String {
    scene_text(&placements.iter().map(|p| format!("AttributeBegin\n{p}\n{body}\nAttributeEnd\n")).collect::<String>())
}

/// Curves of the three kinds, in object space.
const CURVES: &str = r#"
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.9 0.9 0.8 ]
  Shape "curve" "point3 P" [ -1 -0.8 -0.5  -0.3 0.9 -0.7  0.4 -0.6 -0.6  1.2 0.8 -0.4 ] "float width" 0.15
  Shape "curve" "point3 P" [ -1 0.8 0.9  -0.2 -0.9 1  0.5 0.7 0.8  1 -0.6 0.7 ]
    "float width0" 0.2 "float width1" 0.05 "string type" "cylinder"
  Shape "curve" "point3 P" [ -0.8 -0.2 0.2  -0.2 0.5 0.3  0.3 -0.5 0.1  0.9 0.2 0.2 ]
    "float width" 0.25 "string type" "ribbon" "normal N" [ 0 0 -1  0 1 -1 ]
AttributeEnd
"#;

/// A full and a partial sphere, an annulus and a partial cylinder, each moved in object space.
const QUADRICS: &str = r#"
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.8 0.3 0.2 ]
  Shape "sphere" "float radius" 0.7
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.2 0.7 0.3 ]
  Translate 0 0 1.2
  Shape "disk" "float radius" 0.9 "float innerradius" 0.25 "float phimax" 300
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.3 0.3 0.8 ]
  Translate 1.1 0 0
  Rotate 90 1 0 0
  Shape "cylinder" "float radius" 0.3 "float zmin" -0.8 "float zmax" 0.6 "float phimax" 270
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.1 ]
  Translate -1.1 0.3 0
  ReverseOrientation
  Shape "sphere" "float radius" 0.5 "float zmin" -0.3 "float zmax" 0.45 "float phimax" 290
AttributeEnd
"#;

/// A square of two triangles under the shapes.
const QUAD: &str = r#"
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.4 0.2 0.6 ]
  Shape "trianglemesh" "point3 P" [ -0.9 -1 -0.9  0.9 -1 -0.9  0.9 -1 0.9  -0.9 -1 0.9 ]
    "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
"#;

/// Similarities, one of them mirroring: a curve's width scales with them alone.
const SIMILARITIES: [&str; 3] = [
    "Translate 3 0 1\nRotate 30 0 1 0\nScale 1.5 1.5 1.5",
    "Translate -3.2 0.5 2\nRotate -70 1 1 0\nScale 0.7 0.7 0.7",
    "Translate 0 1 -1.5\nRotate 15 0 0 1\nScale -1 1 1",
];

/// A non-uniform scale (quadrics are exact under any affine transform).
const STRETCH: &str = "Translate 0.5 -0.5 4.5\nRotate 20 0 0 1\nScale 1 1.8 0.6";

/// Rays from around the scene toward the instances, at times spread over the shutter.
fn rays(n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 1);
    (0..n)
        .map(|i| {
            let mut u3 = || Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            let o = Vec3::new(-9.0, -2.0, -9.0) + u3() * Vec3::new(18.0, 8.0, 18.0);
            let target = Vec3::new(-5.0, -2.0, -3.0) + u3() * Vec3::new(10.0, 5.0, 9.0);
            Ray::new(o, (target - o).normalize()).at_time((i % 11) as f32 / 10.0)
        })
        .collect()
}

/// What is compared of a hit: its material (as text, since the two scenes number their
/// materials in different orders) and whether it is on a curve.
fn material_of(s: &Scene, h: &Hit) -> (String, bool) {
    let p = &s.primitives()[h.geom_id as usize];
    (format!("{:?}", s.materials()[p.material as usize]), matches!(p.shape, Shape::Curves(_)))
}

/// Counts of [`assert_same_surfaces`].
#[derive(Debug, Default)]
struct Agreement {
    /// Rays that hit in both scenes.
    hits: usize,
    /// …on a primitive of an object instance.
    instance_hits: usize,
    /// …on curves, quadrics.
    curve_hits: usize,
    quadric_hits: usize,
    /// Rays that hit in one scene only, or on different surfaces: at a silhouette, where the
    /// two placements decide differently (curves, and shapes `a` places approximately, only).
    edge_cases: usize,
}

/// The surface `ray` meets in `a` (shapes in instances) is the one it meets in `b` (the same
/// shapes written flat): the same distance, material and normal, the same point within the two
/// error bounds, the same (u, v) — but v across a curve, which runs the other way in a
/// mirrored instance, and a triangle's default (u, v), which a mirrored flat copy's re-wound
/// corners move —, an error bound no coarser than 10⁻⁴ of the coordinates off curves (a
/// curve's is its width), and occlusion agreeing with intersection.
///
/// Embree meets curves by its own approximation, which is not the same in object and in world
/// space: there t and u are held to the tolerances its curves keep to pbrt-v4's
/// (tests/suite/curves.rs: 10⁻² in t relative and in u), and the normals to facing the same
/// side (a cylinder curve's normal turns by 180° across the width, so an error of 10⁻³ in u
/// turns it by degrees). `t_abs` is how far `a`'s surfaces may stand from `b`'s along their
/// normals, where `a` follows its motion only approximately.
fn assert_same_surfaces(what: &str, a: &Scene, b: &Scene, rays: &[Ray], t_abs: f32) -> Agreement {
    let embree = a.accel().name().starts_with("embree");
    let mut n = Agreement::default();
    for ray in rays {
        let (ha, hb) = (a.closest_hit(ray), b.closest_hit(ray));
        assert_eq!(a.occluded(ray), ha.is_some(), "{what}: occluded disagrees with intersect for {ray:?}");
        let (ha, hb) = match (ha, hb) {
            (None, None) => continue,
            (Some(ha), Some(hb)) => (ha, hb),
            (ha, hb) => {
                let curve = |s: &Scene, h: Option<Hit>| h.is_some_and(|h| material_of(s, &h).1);
                let approximate = t_abs > 0.0 || curve(a, ha) || curve(b, hb);
                assert!(approximate, "{what}: instanced {ha:?} vs flat {hb:?} for {ray:?}");
                n.edge_cases += 1;
                continue;
            }
        };
        let (ma, mb) = (material_of(a, &ha), material_of(b, &hb));
        let approximate = embree && ma.1;
        let (t_rel, n_min, uv_tol) = if approximate { (1e-2, 0.0, 1e-2) } else { (T_REL_TOL, 0.9999, 1e-3) };
        // A surface displaced by t_abs along its normal moves a hit by t_abs / |cos θ| along the
        // ray, and (u, v) on shapes about 1 across by about as much.
        let cos = b.interaction(ray, &hb).shading.ng.dot(ray.d.normalize()).abs().max(1e-3);
        let tol = t_rel * ha.t.max(1.0) + t_abs / cos;
        let uv_tol = uv_tol + 4.0 * t_abs / cos;
        if ma != mb || (ha.t - hb.t).abs() > tol || (approximate && (ha.u - hb.u).abs() > uv_tol) {
            assert!(t_abs > 0.0 || ma.1 || mb.1, "{what}: instanced {ha:?} {ma:?} vs flat {hb:?} {mb:?} for {ray:?}");
            n.edge_cases += 1;
            continue;
        }
        n.hits += 1;
        n.instance_hits += (ha.inst_id != Hit::NO_INSTANCE) as usize;
        let (sa, sb): (SurfaceInteraction, SurfaceInteraction) = (a.interaction(ray, &ha), b.interaction(ray, &hb));
        let on_curve = ma.1;
        n.curve_hits += on_curve as usize;
        n.quadric_hits += matches!(a.primitives()[ha.geom_id as usize].shape, Shape::Quadric(_)) as usize;
        let slack = Vec3::splat(tol * ray.d.length());
        let off = (sa.p - sb.p).abs();
        assert!(
            off.cmple(sa.p_err + sb.p_err + slack).all(),
            "{what}: p {} vs {} ± {} {}",
            sa.p,
            sb.p,
            sa.p_err,
            sb.p_err
        );
        if !on_curve {
            let bound = 1e-4 * (sa.p.abs().max_element() + 1.0);
            assert!(sa.p_err.max_element() < bound, "{what}: error bound {} at {}", sa.p_err, sa.p);
        }
        let (na, nb) = (sa.shading.ng, sb.shading.ng);
        assert!(na.dot(nb) > n_min, "{what}: normals {na} vs {nb} at {} (curve: {on_curve})", sa.p);
        assert!(sa.shading.ns.dot(sb.shading.ns) > n_min, "{what}: shading normals at {}", sa.p);
        let mirrored = |s: &Scene, h: &Hit| s.instances().get(h.inst_id as usize).is_some_and(|i| i.handedness < 0.0);
        let flipped = mirrored(a, &ha) != mirrored(b, &hb);
        if flipped && !on_curve && !matches!(a.primitives()[ha.geom_id as usize].shape, Shape::Quadric(_)) {
            // A mirrored flat mesh is re-wound: its triangles' default (u, v) corners move.
            continue;
        }
        let dv = if flipped && on_curve { (sa.uv.y - (1.0 - sb.uv.y)).abs() } else { (sa.uv.y - sb.uv.y).abs() };
        // v across an Embree curve follows u's error as the normal does.
        let dv = if approximate { 0.0 } else { dv };
        assert!(
            (sa.uv.x - sb.uv.x).abs() < uv_tol && dv < uv_tol,
            "{what}: uv {} vs {} at {} ({ha:?}, {hb:?}, {ma:?})",
            sa.uv,
            sb.uv,
            sa.p
        );
    }
    n
}

/// Reads `instanced_text` and `flat_text` on every backend and compares their hits.
fn compare_hits(what: &str, instanced_text: &str, flat_text: &str, min: impl Fn(&Agreement, usize)) {
    let rays = rays(30_000, 7);
    for kind in ray_accels() {
        let (a, b) = (pbrt_scene(instanced_text, kind), pbrt_scene(flat_text, kind));
        assert!(!a.instances().is_empty() && b.instances().len() < a.instances().len());
        let n = assert_same_surfaces(&format!("{what} {kind:?}"), &a, &b, &rays, 0.0);
        eprintln!("{what} {kind:?}: {n:?} of {} rays", rays.len());
        min(&n, rays.len());
        // A silhouette decided differently is rare.
        assert!(n.edge_cases * 500 <= n.hits, "{what} {kind:?}: {} edge cases of {} hits", n.edge_cases, n.hits);
    }
}

#[test]
fn curves_and_quadrics_in_instances_meet_rays_as_their_flat_copies_do() {
    let body = format!("{CURVES}{QUADRICS}{QUAD}");
    compare_hits("curves and quadrics", &instanced(&body, &SIMILARITIES), &flat(&body, &SIMILARITIES), |n, rays| {
        assert!(n.instance_hits > rays / 10 && n.curve_hits > rays / 100 && n.quadric_hits > rays / 20, "{n:?}");
    });
    let placements = [SIMILARITIES[0], STRETCH];
    let body = format!("{QUADRICS}{QUAD}");
    compare_hits("stretched quadrics", &instanced(&body, &placements), &flat(&body, &placements), |n, rays| {
        assert!(n.quadric_hits > rays / 20, "{n:?}");
    });
}

/// `shapes` moving inside an attribute block: translated and turned over the shutter.
fn moving(shapes: &str) -> String {
    format!(
        "AttributeBegin\nActiveTransform StartTime\nTranslate -0.4 0 0\nActiveTransform EndTime\n\
         Translate 0.5 0.4 0.2\nRotate 50 0.3 1 0\nActiveTransform All\n{shapes}\nAttributeEnd\n"
    )
}

#[test]
fn moving_shapes_in_instances_meet_rays_as_their_flat_copies_do() {
    // Inside the object: moving curves, quadrics and triangles beside a static disk. The flat
    // copy moves from I·S₀ to I·S₁ as one transform, which is the instance's product I·S(t) for
    // a similarity I; an instance sliding by a translation keeps that so.
    let body = format!(
        "{}\nAttributeBegin\nTranslate 0 -1.6 0\nShape \"disk\" \"float radius\" 1.2\nAttributeEnd",
        moving(&format!("{CURVES}{QUADRICS}{QUAD}"))
    );
    let sliding = "ActiveTransform EndTime\nTranslate 0.6 0 -0.3\nActiveTransform All";
    let placements = [SIMILARITIES[0], SIMILARITIES[1], &format!("{}\n{sliding}", SIMILARITIES[2])];
    let text = instanced(&body, &placements);
    compare_hits("moving shapes", &text, &flat(&body, &placements), |n, rays| {
        assert!(n.instance_hits > rays / 10 && n.curve_hits > rays / 200 && n.quadric_hits > rays / 20, "{n:?}");
    });
    // One prototype for the static disk, one per moving shape (3 curves, 4 quadrics, 1 mesh),
    // each placed once per ObjectInstance.
    let s = pbrt_scene(&text, AccelKind::Obvhs);
    assert_eq!(s.instances().len(), 3 * 9);
    assert_eq!(s.shutter, Some((0.0, 1.0)));
}

/// The world matrix of `placement` and `motion` at `t` as a pbrt-v4 `Transform` directive.
fn transform_directive(m: Mat4) -> String {
    let v = m.to_cols_array();
    format!("Transform [ {} ]", v.map(|x| format!("{x:.9}")).join(" "))
}

#[test]
fn a_turning_instance_of_a_moving_shape_is_the_product_of_the_two_motions() {
    // The instance turns while the sphere and curves inside it move: no single transform
    // between the products at the ends describes it (pbrt-v4 interpolates the two factors
    // separately). At each time the instanced scene is the static scene placed at
    // outer(t) · inner(t).
    let outer = AnimatedTransform::new(
        Mat4::from_translation(Vec3::new(0.0, 0.5, 1.0)),
        0.0,
        Mat4::from_translation(Vec3::new(0.5, 0.5, 1.0)) * Mat4::from_quat(Quat::from_rotation_y(1.4)),
        1.0,
    );
    let inner = AnimatedTransform::new(
        Mat4::from_translation(Vec3::new(-1.5, 0.0, 0.0)),
        0.0,
        Mat4::from_translation(Vec3::new(1.5, 0.6, 0.0)) * Mat4::from_rotation_z(0.9),
        1.0,
    );
    // Shapes at the object's origin: a shape's own transform would make its motion another
    // interpolation (pbrt-v4 interpolates S₀·T to S₁·T, not S(t)·T).
    let shapes = format!(
        "{CURVES}\nShape \"sphere\" \"float radius\" 0.7 \"float zmin\" -0.4 \"float phimax\" 320\n\
         Shape \"disk\" \"float radius\" 1.1 \"float innerradius\" 0.8"
    );
    let set = |m: Mat4| transform_directive(m);
    let object = format!(
        "ObjectBegin \"o\"\nAttributeBegin\nActiveTransform StartTime\n{}\nActiveTransform EndTime\n{}\n\
         ActiveTransform All\n{shapes}\nAttributeEnd\nObjectEnd\n\
         AttributeBegin\nActiveTransform StartTime\n{}\nActiveTransform EndTime\n{}\nActiveTransform All\n\
         ObjectInstance \"o\"\nAttributeEnd\n",
        set(inner.start),
        set(inner.end),
        set(outer.start),
        set(outer.end)
    );
    // obvhs evaluates the product at each ray's time; Embree interpolates between 129 samples of
    // it, which departs from it by at most L θ²/8 per step of turn θ = (1.4 + 0.9)/128 at
    // distance L ≈ 4 from the axes: 1.6·10⁻⁴ (6·10⁻⁵ measured by emulating Embree's
    // interpolation), allowed thrice.
    let step = (1.4f32 + 0.9) / 128.0;
    for kind in ray_accels() {
        let t_abs = if kind == AccelKind::Obvhs { 0.0 } else { 3.0 * 4.0 * step * step / 8.0 };
        let moving = pbrt_scene(&scene_text(&object), kind);
        let mut hits = 0;
        for (k, t) in [0.0f32, 0.3, 0.5, 0.85, 1.0].into_iter().enumerate() {
            let m = outer.interpolate(t) * inner.interpolate(t);
            let placed = pbrt_scene(&scene_text(&format!("AttributeBegin\n{}\n{shapes}\nAttributeEnd", set(m))), kind);
            let rays: Vec<Ray> = rays(6000, 20 + k as u64).into_iter().map(|r| r.at_time(t)).collect();
            let n = assert_same_surfaces(&format!("{kind:?} at t = {t}"), &moving, &placed, &rays, t_abs);
            assert!(n.edge_cases * 200 <= n.hits, "{kind:?} at {t}: {n:?}");
            hits += n.instance_hits;
        }
        assert!(hits > 1500, "{kind:?}: {hits} hits on the moving shapes");
    }
}

#[test]
fn moving_curves_at_time_t_are_the_curves_placed_at_t() {
    let (start, end) = (
        Mat4::from_translation(Vec3::new(-1.0, 0.0, 0.5)),
        Mat4::from_translation(Vec3::new(1.0, 1.0, 0.0))
            * Mat4::from_rotation_y(0.8)
            * Mat4::from_scale(Vec3::splat(1.6)),
    );
    let motion = AnimatedTransform::new(start, 0.0, end, 1.0);
    let text = scene_text(&format!(
        "AttributeBegin\nActiveTransform StartTime\n{}\nActiveTransform EndTime\n{}\nActiveTransform All\n{CURVES}\nAttributeEnd",
        transform_directive(start),
        transform_directive(end)
    ));
    for kind in ray_accels() {
        let moving = pbrt_scene(&text, kind);
        assert_eq!(moving.shutter, Some((0.0, 1.0)));
        let mut hits = 0;
        for (k, t) in [0.0f32, 0.4, 0.7, 1.0].into_iter().enumerate() {
            let m = transform_directive(motion.interpolate(t));
            let placed = pbrt_scene(&scene_text(&format!("AttributeBegin\n{m}\n{CURVES}\nAttributeEnd")), kind);
            let rays: Vec<Ray> = rays(8000, 40 + k as u64).into_iter().map(|r| r.at_time(t)).collect();
            let n = assert_same_surfaces(&format!("{kind:?} at t = {t}"), &moving, &placed, &rays, 0.0);
            assert!(n.edge_cases * 200 <= n.hits, "{kind:?} at {t}: {n:?}");
            hits += n.curve_hits;
        }
        assert!(hits > 300, "{kind:?}: {hits} curve hits");
    }
}

/// Renders the instanced and the flat scene with one seed: the same image within noise, not black.
fn assert_same_image(what: &str, instanced_text: &str, flat_text: &str) {
    let settings = test_settings((48, 36), 16, 3, 4);
    for kind in crate::common::backends() {
        let (a, sa) = render(&pbrt_scene(instanced_text, kind), &settings, |_| {}).unwrap();
        let (b, sb) = render(&pbrt_scene(flat_text, kind), &settings, |_| {}).unwrap();
        assert_eq!((sa.nonfinite, sb.nonfinite), (0, 0));
        let (d, se, mean) = film_difference(&a, &b);
        eprintln!("{what} {kind:?}: mean Y {mean:.4}, difference {d:.2e} ± {se:.2e}");
        assert!(mean > 0.05, "{what} {kind:?}: black image ({mean})");
        assert!(d.abs() <= 4.0 * se.max(1e-6 * mean), "{what} {kind:?}: {d} ± {se}");
    }
}

#[test]
fn instanced_curves_quadrics_and_moving_shapes_render_as_their_flat_copies() {
    let body = format!("{CURVES}{QUADRICS}{QUAD}");
    assert_same_image("static", &instanced(&body, &SIMILARITIES), &flat(&body, &SIMILARITIES));
    let placements = [SIMILARITIES[0], SIMILARITIES[1]];
    let body = moving(&body);
    assert_same_image("moving", &instanced(&body, &placements), &flat(&body, &placements));
}

/// The closed-form hit of `o + t d` with the sphere of `center` and `radius` (f64), and the
/// ray's distance from the centre relative to the radius.
fn sphere_hit(center: DVec3, radius: f64, o: DVec3, d: DVec3) -> (Option<f64>, f64) {
    let oc = o - center;
    let (a, b, c) = (d.dot(d), 2.0 * oc.dot(d), oc.dot(oc) - radius * radius);
    let impact = (oc - d * (oc.dot(d) / a)).length() / radius;
    let disc = b * b - 4.0 * a * c;
    (if disc < 0.0 { None } else { Some((-b - disc.sqrt()) / (2.0 * a)) }, impact)
}

#[test]
fn an_instanced_sphere_is_exact_where_rays_graze_it() {
    // Rays pass the sphere at 1 ± δ of its radius, δ ∈ [2·10⁻⁴, 10⁻³]: those inside must hit
    // it where the closed form says, at a point whose error bound reaches the sphere, with the
    // sphere's normal; those outside must miss. An inscribed mesh's facets lie up to 1.1·10⁻³ of the radius inside the
    // sphere: it would let many of the inner rays through.
    let placements =
        ["Translate 40 -7 25\nRotate 33 1 0.4 0\nScale 2.5 2.5 2.5", "Translate -3 2 1\nScale -0.3 0.3 0.3"];
    let ms = [
        Mat4::from_translation(Vec3::new(40.0, -7.0, 25.0))
            * Mat4::from_axis_angle(Vec3::new(1.0, 0.4, 0.0).normalize(), 33f32.to_radians())
            * Mat4::from_scale(Vec3::splat(2.5)),
        Mat4::from_translation(Vec3::new(-3.0, 2.0, 1.0)) * Mat4::from_scale(Vec3::new(-0.3, 0.3, 0.3)),
    ];
    let uses: String =
        placements.iter().map(|p| format!("AttributeBegin\n{p}\nObjectInstance \"o\"\nAttributeEnd\n")).collect();
    let text = format!(
        "Camera \"perspective\"\nWorldBegin\nObjectBegin \"o\"\nShape \"sphere\" \"float radius\" 1.5\nObjectEnd\n{uses}"
    );
    for kind in ray_accels() {
        let s = pbrt_scene(&text, kind);
        let mut rng = Rng::new(11, 2);
        let (mut inside, mut outside) = (0, 0);
        for (m, scale) in ms.iter().zip([2.5f64, 0.3]) {
            let (center, radius) = (m.transform_point3(Vec3::ZERO).as_dvec3(), 1.5 * scale);
            for i in 0..20_000 {
                // Through a point at distance (1 ± δ) r from the centre, perpendicular to it.
                let mut u3 = || DVec3::new(rng.uniform() as f64, rng.uniform() as f64, rng.uniform() as f64);
                let axis = (u3() - 0.5).normalize();
                let (e1, phi) = (axis.any_orthonormal_vector(), u3().x * std::f64::consts::TAU);
                let d = e1 * phi.cos() + axis.cross(e1) * phi.sin();
                let delta = 2e-4 + 8e-4 * u3().y;
                let side = if i % 2 == 0 { 1.0 - delta } else { 1.0 + delta };
                let o = center + axis * radius * side - d * 4.0 * radius;
                // Short of the other sphere.
                let ray = Ray::segment(o.as_vec3(), d.as_vec3(), (8.0 * radius) as f32);
                let (exact, impact) = sphere_hit(center, radius, ray.o.as_dvec3(), ray.d.as_dvec3());
                match (exact, s.intersect(&ray)) {
                    (None, None) => outside += 1,
                    (Some(t), Some(si)) => {
                        inside += 1;
                        let p = si.p.as_dvec3();
                        let off = ((p - center).length() - radius).abs();
                        assert!(
                            off <= si.p_err.as_dvec3().length(),
                            "{kind:?}: {p} is {off} off the sphere ± {}",
                            si.p_err
                        );
                        // On the ray: a grazing ray meets the sphere at a distance along it that
                        // rounding moves by ~ε/√δ, but the point stays on both.
                        let (o, d) = (ray.o.as_dvec3(), ray.d.as_dvec3());
                        let from_ray = (p - o).cross(d).length() / d.length();
                        assert!(from_ray <= si.p_err.as_dvec3().length(), "{kind:?}: {p} is {from_ray} off the ray");
                        assert!(((p - o).dot(d) - t).abs() < 1e-3 * radius, "{kind:?}: t {t} vs {}", (p - o).dot(d));
                        // Outward, reversed under a mirror as pbrt-v4 reverses a flat sphere's.
                        let n = (p - center).normalize() * m.determinant().signum() as f64;
                        assert!(si.shading.ng.as_dvec3().dot(n) > 0.99999, "{kind:?}: normal {} at {p}", si.shading.ng);
                    }
                    (exact, si) => panic!(
                        "{kind:?}: closed form {exact:?} (impact {impact}), prism {:?} for {ray:?}",
                        si.map(|si| si.p)
                    ),
                }
            }
        }
        assert!(inside > 15_000 && outside > 15_000, "{kind:?}: {inside} in, {outside} out");
    }
}

#[test]
fn rays_leaving_an_instanced_quadric_far_from_the_origin_never_meet_it_again() {
    // Spheres, a cylinder and an annulus in instances scaled 10⁻³ to 10³ and carried 10⁴ from
    // the origin: from hits on them, rays spawned in random directions on either side (origins
    // offset past the error bound) never meet the surface they leave at the point they left
    // (a ray into a sphere or cylinder meets its far side, at least 10⁻³ of its size away but
    // for the rare ray within 0.03° of the tangent plane).
    let body = r#"
Shape "sphere" "float radius" 1
AttributeBegin
  Translate 3 0 0
  Rotate 90 1 0 0
  Shape "cylinder" "float radius" 0.5 "float zmin" -1 "float zmax" 1
AttributeEnd
AttributeBegin
  Translate -3 0 0
  Shape "disk" "float radius" 1 "float innerradius" 0.2
AttributeEnd
"#;
    let mut rng = Rng::new(3, 9);
    for kind in ray_accels() {
        let mut spawned = 0;
        for (scale, at) in [(1e-3f32, 1e4f32), (1.0, 1e4), (1e3, 1e4), (0.37, 0.0)] {
            let placement =
                format!("Translate {at} {} {}\nRotate 37 1 1 0\nScale {scale} {scale} {scale}", -at, 0.5 * at);
            let text = format!(
                "Camera \"perspective\"\nWorldBegin\n{}",
                instanced(body, &[&placement]).split("WorldBegin\n").nth(1).unwrap()
            );
            let s = pbrt_scene(&text, kind);
            let m = s.instances()[0].world_from_object;
            for _ in 0..4000 {
                let mut u3 = || Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
                let target = m.transform_point3(Vec3::new(-4.0, -1.2, -1.2) + u3() * Vec3::new(8.0, 2.4, 2.4));
                let o = m.transform_point3((u3() - 0.5).normalize() * 12.0);
                let Some(si) = s.intersect(&Ray::new(o, target - o)) else { continue };
                if si.inst == Hit::NO_INSTANCE {
                    continue; // the ground
                }
                let d = (u3() - 0.5).normalize();
                let next = si.spawn_ray(d);
                spawned += 1;
                if let Some(h) = s.closest_hit(&next) {
                    let gap = h.t * d.length();
                    assert!(
                        gap > 1e-3 * scale,
                        "{kind:?}: scale {scale} at {at}: re-hit {gap} from {} ± {}",
                        si.p,
                        si.p_err
                    );
                }
            }
        }
        assert!(spawned > 5000, "{kind:?}: {spawned} spawned rays");
    }
}
