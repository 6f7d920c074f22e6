//! Numerical robustness: the Cornell box renders the same at any scale and far from the origin
//! (spawned rays are offset by a bound on the hit point's rounding error, not a global epsilon),
//! and degenerate geometry never produces NaN pixels.

use crate::common::{film_difference as diff, pixels_far_off, test_settings};
use glam::{Mat4, Vec3};
use prism::accel::AccelKind;
use prism::film::Film;
use prism::geometry::Mesh;
use prism::material::Material;
use prism::render::{render, RenderSettings};
use prism::scene::SceneBuilder;
use prism::spectrum::Spectrum;

fn settings() -> RenderSettings {
    test_settings((24, 24), 32, 5, 4)
}

fn render_cornell(m: Mat4, accel: AccelKind, seed: u64) -> Film {
    let mut b = SceneBuilder::cornell_box();
    b.transform(m);
    let scene = b.build(accel).unwrap();
    let (film, stats) = render(&scene, &RenderSettings { seed, ..settings() }, |_| {}).unwrap();
    assert_eq!(stats.nonfinite, 0);
    film
}

#[test]
fn cornell_box_is_the_same_at_every_scale_and_far_from_the_origin() {
    for accel in [AccelKind::Obvhs].into_iter().chain(cfg!(embree).then_some(AccelKind::Embree)) {
        // The box is 556 mm wide: bring it to unit size first.
        let unit = Mat4::from_scale(Vec3::splat(1.0 / 556.0));
        let reference = render_cornell(unit, accel, 5);
        // The noise level: the mean difference between two independent unit-scale renders.
        let (_, noise, _) = diff(&render_cornell(unit, accel, 6), &reference);
        for (name, m) in [
            ("1e-4", Mat4::from_scale(Vec3::splat(1e-4)) * unit),
            ("1e-2", Mat4::from_scale(Vec3::splat(1e-2)) * unit),
            ("1e2", Mat4::from_scale(Vec3::splat(1e2)) * unit),
            ("1e5", Mat4::from_scale(Vec3::splat(1e5)) * unit),
            // Far from the origin: at 1e5 an f32 step is 0.0078, so the box must be large enough
            // (1000 units) that the light's 0.1 mm gap below the ceiling survives rounding.
            ("1e3 at +1e5", Mat4::from_translation(Vec3::splat(1e5)) * Mat4::from_scale(Vec3::splat(1e3)) * unit),
        ] {
            let f = render_cornell(m, accel, 5);
            let (d, _, mean) = diff(&f, &reference);
            assert!(mean > 0.05, "{name}: black image");
            // Same seed, so any difference is systematic; it must hide inside the image noise.
            assert!(
                d.abs() <= 4.0 * noise,
                "{accel:?} scale {name}: mean difference {d} vs noise {noise} (mean {mean})"
            );
            let bad = pixels_far_off(&f, &reference);
            assert!(bad <= f.pixels.len() / 50, "{accel:?} scale {name}: {bad} pixels differ wildly");
        }
    }
}

/// The Cornell box plus a mesh of `bad` triangles and two good ones (one inverted), and a
/// non-manifold mesh. `bad`: zero area (duplicate vertex), NaN and Inf vertices, a collapsed
/// triangle, an index out of range.
fn with_meshes(bad: bool) -> SceneBuilder {
    let mut b = SceneBuilder::cornell_box();
    let m = b.add_material(Material::diffuse(Spectrum::constant(0.5)));
    let (nan, inf) = (f32::NAN, f32::INFINITY);
    let v = |x, y, z| Vec3::new(x, y, z);
    let good = [v(300.0, 200.0, 300.0), v(400.0, 200.0, 300.0), v(300.0, 300.0, 300.0)];
    let mesh = if bad {
        let mut p = vec![v(100.0, 100.0, 100.0), v(100.0, 100.0, 100.0), v(200.0, 100.0, 100.0), v(nan, 0.0, 0.0)];
        p.push(v(inf, 1.0, 0.0));
        p.extend(good);
        Mesh::new(p, vec![[0, 1, 2], [3, 4, 5], [2, 2, 2], [5, 6, 7], [7, 6, 5], [0, 9, 1]])
    } else {
        Mesh::new(good.to_vec(), vec![[0, 1, 2], [2, 1, 0]])
    };
    b.add_mesh(mesh, m, None);
    // Non-manifold: three triangles sharing one edge, plus a back-to-back duplicate.
    let non_manifold = Mesh::new(
        vec![
            v(200.0, 300.0, 200.0),
            v(350.0, 300.0, 200.0),
            v(275.0, 400.0, 250.0),
            v(275.0, 200.0, 250.0),
            v(275.0, 300.0, 100.0),
        ],
        vec![[0, 1, 2], [0, 1, 3], [0, 1, 4], [1, 0, 2]],
    );
    b.add_mesh(non_manifold, m, None);
    b
}

#[test]
fn degenerate_geometry_is_skipped_with_one_warning_and_no_nans() {
    let b = with_meshes(true);
    assert_eq!(b.warnings.len(), 1, "{:?}", b.warnings);
    assert!(b.warnings[0].contains("skipped 4 degenerate"), "{:?}", b.warnings);
    assert!(with_meshes(false).warnings.is_empty());
    for accel in [AccelKind::Obvhs].into_iter().chain(cfg!(embree).then_some(AccelKind::Embree)) {
        let scene = with_meshes(true).build(accel).unwrap();
        let (film, stats) = render(&scene, &settings(), |_| {}).unwrap();
        assert_eq!(stats.nonfinite, 0, "{accel:?}");
        // Skipped means gone: the image is that of the scene without the bad triangles (same
        // seeds, so equal up to paths that part where the two BVHs order equal-distance hits).
        let clean = with_meshes(false).build(accel).unwrap();
        let (reference, _) = render(&clean, &settings(), |_| {}).unwrap();
        let (d, se, mean) = diff(&film, &reference);
        assert!(mean > 0.1, "{accel:?}: black image (mean Y {mean})");
        assert!(d.abs() <= 4.0 * se + 1e-6 * mean, "{accel:?}: mean difference {d} ± {se}");
        let bad = pixels_far_off(&film, &reference);
        assert!(bad <= film.pixels.len() / 50, "{accel:?}: {bad} pixels differ wildly");
    }
}

#[test]
fn geometry_beyond_any_bvh_is_never_hit_and_breaks_nothing() {
    // A sphere scaled to 1e30 on one axis at the end of its motion, one whose transform
    // overflows, triangles with a vertex at -1e30 among sound ones and an instance scaled to
    // 1e30: no BVH can hold their boxes (obvhs's build panicked on them). Beside them a unit sphere in front of
    // the camera must still be seen.
    let text = r#"
        LookAt 0 0 5  0 0 0  0 1 0
        Camera "perspective" "float fov" [ 30 ]
        Sampler "independent" "integer pixelsamples" [ 4 ]
        Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
        WorldBegin
        LightSource "infinite" "rgb L" [ 1 1 1 ]
        Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
        ObjectBegin "pebble"
          Shape "trianglemesh" "integer indices" [ 0 1 2 ] "point3 P" [ 0 0 0  1 0 0  0 1 0 ]
        ObjectEnd
        Shape "sphere" "float radius" [ 1 ]
        AttributeBegin
          ActiveTransform StartTime
          Translate 3 0 0
          ActiveTransform EndTime
          Scale 1 1 1e30
          ActiveTransform All
          Shape "sphere" "float radius" [ 0.5 ]
        AttributeEnd
        AttributeBegin
          Translate -3 0 0
          Scale 1e30 1e30 1e30
          Shape "sphere" "float radius" [ 1e30 ]
        AttributeEnd
        Shape "trianglemesh" "integer indices" [ 0 1 2  0 2 3  1 2 3  0 1 3  4 5 6  5 6 7 ]
          "point3 P" [ -50 -3 -50  50 -3 -50  50 -3 50  -50 -3 -1e30
                       -2 -2 -2  -1 -2 -2  -2 -1 -2  -1 -1 -2 ]
        AttributeBegin
          Translate 0 -2 -3
          ObjectInstance "pebble"
        AttributeEnd
        AttributeBegin
          Scale 1e30 1e30 1e30
          ObjectInstance "pebble"
        AttributeEnd
        AttributeBegin
          Translate 1 -2 -3
          ObjectInstance "pebble"
        AttributeEnd
    "#;
    for accel in crate::common::backends() {
        let scene = crate::common::pbrt_scene(text, accel);
        let (film, stats) = render(&scene, &test_settings((16, 16), 4, 1, 5), |_| {}).unwrap();
        assert_eq!(stats.nonfinite, 0, "{accel:?}");
        // The unit sphere fills the centre pixel: a diffuse 0.5 under a white sky of unit
        // luminance, which every point of the convex sphere sees whole, has Y = 0.5.
        let centre = &film.pixels[8 * 16 + 8];
        let y = centre.xyz_sum.y / centre.weight_sum;
        assert!((y - 0.5).abs() < 0.1, "{accel:?}: centre Y {y}");
    }
}
