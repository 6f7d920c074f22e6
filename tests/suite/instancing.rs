//! Object instancing: an instanced scene and its flattened copy (every instance replaced by
//! world-space copies of its meshes) give the same hits and the same image on both backends; rays
//! from inside transformed closed meshes never escape; and many instances of a big mesh cost far
//! less memory than their flattened copies.

use crate::common::{film_difference, pixels_far_off, test_settings};
use glam::{Mat4, Quat, Vec3};
use prism::accel::{self, AccelKind};
use prism::camera::Camera;
use prism::geometry::shapes::{axis_box, icosphere, quad, terrain};
use prism::geometry::{Hit, Instance, InstanceSet, Mesh, Prototype, Ray};
use prism::material::Material;
use prism::render::render;
use prism::sampling::Rng;
use prism::scene::{Emission, SceneBuilder};
use prism::spectrum::Spectrum;

/// Relative tolerance on hit distances between an instance (ray carried into object space) and
/// its flattened copy (vertices carried into world space): both roundings are a few ulps.
const T_REL_TOL: f32 = 1e-4;

fn accels() -> Vec<AccelKind> {
    let mut v = vec![AccelKind::Obvhs];
    if cfg!(embree) {
        v.push(AccelKind::Embree);
    }
    v
}

/// The backends whose hits are tested: [`accels`] and Embree with the watertight triangle test.
fn ray_accels() -> Vec<AccelKind> {
    let mut v = accels();
    if cfg!(embree) {
        v.push(AccelKind::EmbreeWatertight);
    }
    v
}

fn random_dir(rng: &mut Rng) -> Vec3 {
    let z = 1.0 - 2.0 * rng.uniform();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * rng.uniform();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A varied transform: rotation, non-uniform scale (mirrored for some), translation on a grid.
fn placement(i: usize, rng: &mut Rng, spacing: f32) -> Mat4 {
    let (gx, gz) = ((i % 6) as f32, (i / 6) as f32);
    let axis = random_dir(rng);
    let rot = Quat::from_axis_angle(axis, rng.uniform() * 6.0);
    let mut scale = Vec3::new(0.6 + 0.6 * rng.uniform(), 0.6 + 0.6 * rng.uniform(), 0.6 + 0.6 * rng.uniform());
    if i % 5 == 3 {
        scale.x = -scale.x;
    }
    Mat4::from_translation(Vec3::new(gx * spacing - 7.5, 1.5, gz * spacing - 7.5))
        * Mat4::from_quat(rot)
        * Mat4::from_scale(scale)
}

/// Two prototypes (a sphere with a box, and a box alone), 36 instances, a ground and a light.
fn instanced_builder() -> SceneBuilder {
    let mut b = SceneBuilder::new();
    let grey = b.add_material(Material::diffuse(Spectrum::constant(0.6)));
    let red = b.add_material(Material::diffuse(Spectrum::from_rgb(
        [0.8, 0.2, 0.1],
        prism::spectrum::RgbKind::Albedo,
        prism::spectrum::ColorSpace::srgb(),
    )));
    b.add_mesh(terrain(20.0, 16, 0.2, 1), grey, None);
    let em = Emission { spectrum: Spectrum::constant(1.0), scale: 4.0, two_sided: false };
    b.add_mesh(quad(Vec3::new(-5.0, 8.0, -5.0), Vec3::new(10.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 10.0)), grey, Some(em));
    let p0 = b.add_prototype(vec![
        (icosphere(Vec3::ZERO, 1.0, 3), red),
        (axis_box(Vec3::new(-0.3, -1.4, -0.3), Vec3::new(0.3, -0.9, 0.3)), grey),
    ]);
    let p1 = b.add_prototype(vec![(axis_box(Vec3::splat(-0.8), Vec3::splat(0.8)), grey)]);
    let mut rng = Rng::new(5, 0);
    for i in 0..36 {
        assert!(b.add_instance(if i % 3 == 0 { p1 } else { p0 }, placement(i, &mut rng, 3.0)));
    }
    b.set_camera(Camera::look_at(Vec3::new(0.0, 9.0, -14.0), Vec3::new(0.0, 0.0, 0.0), Vec3::Y), 60.0);
    b
}

#[test]
fn instanced_and_flattened_scenes_give_the_same_hits() {
    for kind in ray_accels() {
        let inst = instanced_builder().build(kind).unwrap();
        let mut flat_b = instanced_builder();
        flat_b.flatten_instances();
        let flat = flat_b.build(kind).unwrap();
        assert_eq!(inst.instances().len(), 36);
        assert!(flat.instances().is_empty());
        let mut rng = Rng::new(17, 3);
        let (mut hits, mut instance_hits, mut total) = (0, 0, 0);
        for _ in 0..40_000 {
            let o = Vec3::new(rng.uniform() * 24.0 - 12.0, rng.uniform() * 6.0 + 0.5, rng.uniform() * 24.0 - 12.0);
            let ray = Ray::new(o, random_dir(&mut rng));
            total += 1;
            let (a, b) = (inst.closest_hit(&ray), flat.closest_hit(&ray));
            assert_eq!(inst.occluded(&ray), a.is_some(), "{kind:?}: occluded disagrees with intersect");
            match (a, b) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    hits += 1;
                    let tol = T_REL_TOL * a.t.max(1.0);
                    assert!((a.t - b.t).abs() <= tol, "{kind:?}: t {} vs {} for {ray:?}", a.t, b.t);
                    // Same surface: the flattened copy of the instance's mesh has its material.
                    assert_eq!(
                        inst.primitives()[a.geom_id as usize].material,
                        flat.primitives()[b.geom_id as usize].material
                    );
                    assert_eq!(a.prim_id, b.prim_id, "{kind:?}: prim for {ray:?}");
                    // World-space normals agree in direction (mirrored instances included).
                    let (na, nb) = (a.ng.normalize(), b.ng.normalize());
                    assert!(na.dot(nb).abs() > 0.999, "{kind:?}: normals {na} vs {nb}");
                    if a.inst_id != Hit::NO_INSTANCE {
                        instance_hits += 1;
                        assert!(a.inst_id < 36);
                    }
                }
                (a, b) => panic!("{kind:?}: instanced {a:?} vs flattened {b:?} for {ray:?}"),
            }
        }
        assert!(instance_hits > total / 10, "{kind:?}: only {instance_hits} of {total} rays hit instances");
        assert!(hits > total / 4, "{kind:?}: {hits}/{total}");
    }
}

/// Closed meshes under instance transforms (rotation, non-uniform scale, mirroring, a far
/// translation): rays from inside aimed exactly at the transformed shared vertices and edges
/// never escape, on either backend.
#[test]
fn no_ray_escapes_an_instanced_closed_mesh_from_inside() {
    let protos = [("icosphere", icosphere(Vec3::ZERO, 1.0, 2)), ("box", axis_box(Vec3::splat(-1.0), Vec3::splat(1.0)))];
    let transforms = [
        Mat4::from_translation(Vec3::new(3.0, -2.0, 1.0))
            * Mat4::from_rotation_z(0.4)
            * Mat4::from_scale(Vec3::new(2.0, 0.5, 1.3)),
        Mat4::from_rotation_y(1.1) * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
        Mat4::from_translation(Vec3::new(1e3, 5e2, -2e3))
            * Mat4::from_rotation_x(0.9)
            * Mat4::from_scale(Vec3::splat(7.0)),
    ];
    for kind in ray_accels() {
        for (name, mesh) in &protos {
            let set = InstanceSet {
                world_meshes: vec![],
                prototypes: vec![Prototype { meshes: vec![0] }],
                instances: transforms.iter().map(|&m| Instance::new(0, m).unwrap()).collect(),
            };
            let accel = accel::build_instanced(kind, std::slice::from_ref(mesh), &set).unwrap();
            let mut rng = Rng::new(3, 1);
            let (mut fired, mut escaped) = (0usize, 0usize);
            for inst in &set.instances {
                let to_world = |p: Vec3| inst.world_from_object.transform_point3(p);
                let centre = to_world(Vec3::ZERO);
                let repeats = (2_000 / mesh.len()).max(1);
                for t in mesh.indices.iter().flat_map(|t| std::iter::repeat_n(t, repeats)) {
                    for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                        let (pa, pb) = (to_world(mesh.positions[a as usize]), to_world(mesh.positions[b as usize]));
                        for target in [pa, 0.5 * (pa + pb), pa + (pb - pa) * rng.uniform()] {
                            let local = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 0.6 - Vec3::splat(0.3);
                            let orig = centre + inst.world_from_object.transform_vector3(local);
                            let ray = Ray::new(orig, target - orig);
                            fired += 1;
                            escaped += accel.intersect(&ray).is_none() as usize;
                        }
                    }
                }
            }
            assert!(fired > 10_000, "{name}: only {fired} rays");
            assert_eq!(escaped, 0, "{kind:?} {name}: {escaped} of {fired} rays escaped");
        }
    }
}

/// Accelerator state bytes per placed triangle: 100 instances of a 5120-triangle mesh (512k
/// placed triangles), instanced vs flattened into world-space copies.
#[test]
fn many_instances_of_a_big_mesh_use_far_less_memory_than_flattened() {
    let big = icosphere(Vec3::ZERO, 1.0, 4);
    let n = 100;
    let mut rng = Rng::new(9, 0);
    let transforms: Vec<Mat4> = (0..n).map(|i| placement(i, &mut rng, 3.0)).collect();
    let set = InstanceSet {
        world_meshes: vec![],
        prototypes: vec![Prototype { meshes: vec![0] }],
        instances: transforms.iter().map(|&m| Instance::new(0, m).unwrap()).collect(),
    };
    let flat: Vec<Mesh> = transforms.iter().map(|m| big.transformed(m)).collect();
    let placed = (n * big.len()) as f64;
    assert_eq!(set.placed_triangles(std::slice::from_ref(&big)) as f64, placed);
    for kind in accels() {
        let inst = accel::build_instanced(kind, std::slice::from_ref(&big), &set).unwrap();
        let flat = accel::build(kind, &flat).unwrap();
        let (bi, bf) = (inst.memory_bytes() as f64 / placed, flat.memory_bytes() as f64 / placed);
        eprintln!("{kind:?}: {bi:.2} bytes per placed triangle instanced, {bf:.2} flattened");
        // A flattened BVH holds at least the 36 bytes of vertices per triangle.
        assert!(bf > 36.0, "{kind:?}: flattened accounts only {bf} bytes per triangle");
        assert!(bi * 20.0 < bf, "{kind:?}: instanced {bi} vs flattened {bf} bytes per triangle");
    }
}

/// The same image, within noise, from the instanced scene and its flattened copy (same seed).
#[test]
fn instanced_and_flattened_scenes_render_the_same_image() {
    let settings = test_settings((48, 32), 8, 4, 4);
    for kind in accels() {
        let inst = instanced_builder().build(kind).unwrap();
        let mut flat_b = instanced_builder();
        flat_b.flatten_instances();
        let flat = flat_b.build(kind).unwrap();
        let (a, sa) = render(&inst, &settings, |_| {}).unwrap();
        let (b, sb) = render(&flat, &settings, |_| {}).unwrap();
        assert_eq!((sa.nonfinite, sb.nonfinite), (0, 0));
        let (d, se, mean) = film_difference(&a, &b);
        eprintln!("{kind:?}: mean Y {mean:.4}, difference {d:.2e} ± {se:.2e}");
        assert!(mean > 0.01, "{kind:?}: image too dark to compare ({mean})");
        assert!(d.abs() <= 4.0 * se.max(1e-6 * mean), "{kind:?}: {d} ± {se}");
    }
}

/// Mean Y below which the orchard counts as black (it renders at about 0.74).
const MIN_ORCHARD_Y: f64 = 0.3;

/// scenes/instanced_orchard.pbrt: 13 ObjectInstances of one object become 13 instances of one
/// prototype (not 26 world meshes), and render like their flattened copies on both backends.
#[test]
fn pbrt_object_instances_are_real_instances() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/instanced_orchard.pbrt");
    let load = || {
        let (desc, _) = prism::pbrt::parse_file(&path, &Default::default()).unwrap();
        let mut warnings = Vec::new();
        prism::pbrt::build(&desc, &mut warnings).unwrap().0
    };
    assert_eq!(load().instance_count(), 13);
    let settings = test_settings((64, 36), 8, 2, 3);
    for kind in accels() {
        let inst = load().build(kind).unwrap();
        assert_eq!(inst.instances().len(), 13);
        let mut flat_b = load();
        flat_b.flatten_instances();
        let flat = flat_b.build(kind).unwrap();
        let (a, sa) = render(&inst, &settings, |_| {}).unwrap();
        let (b, sb) = render(&flat, &settings, |_| {}).unwrap();
        assert_eq!((sa.nonfinite, sb.nonfinite), (0, 0));
        let (d, se, mean) = film_difference(&a, &b);
        eprintln!("orchard {kind:?}: mean Y {mean:.4}, difference {d:.2e} ± {se:.2e}");
        // A black image would pass the comparison: the orchard must be lit.
        assert!(mean > MIN_ORCHARD_Y, "{kind:?}: black image (mean Y {mean})");
        assert!(d.abs() <= 4.0 * se.max(1e-6 * mean), "{kind:?}: {d} ± {se}");
    }
}

fn render_cornell(m: Mat4, kind: AccelKind, instanced: bool, seed: u64) -> prism::film::Film {
    let mut b = SceneBuilder::cornell_box();
    if instanced {
        assert!(b.instance_world_geometry().is_some());
    }
    b.transform(m);
    let scene = b.build(kind).unwrap();
    assert_eq!(scene.instances().len(), instanced as usize);
    let settings = test_settings((24, 24), 32, seed, 4);
    let (film, stats) = render(&scene, &settings, |_| {}).unwrap();
    assert_eq!(stats.nonfinite, 0);
    film
}

/// The Cornell box's walls and blocks as one instance whose transform scales and carries them
/// far from the origin (object space stays unit-sized): the image matches the flat unit-scale
/// render within noise, so the hit points' error bounds were carried to world space (with an
/// object-space bound only, spawned rays re-hit their surface: acne and leaks).
#[test]
fn an_instance_far_from_the_origin_renders_without_acne() {
    let unit = Mat4::from_scale(Vec3::splat(1.0 / 556.0));
    for kind in accels() {
        let reference = render_cornell(unit, kind, false, 5);
        let (_, noise, _) = film_difference(&render_cornell(unit, kind, false, 6), &reference);
        for (name, m) in [
            ("unit", unit),
            ("1e3 at +1e5", Mat4::from_translation(Vec3::splat(1e5)) * Mat4::from_scale(Vec3::splat(1e3)) * unit),
            ("1e-2 at +1", Mat4::from_translation(Vec3::ONE) * Mat4::from_scale(Vec3::splat(1e-2)) * unit),
            ("1e-4", Mat4::from_scale(Vec3::splat(1e-4)) * unit),
        ] {
            let f = render_cornell(m, kind, true, 5);
            let (d, _, mean) = film_difference(&f, &reference);
            assert!(mean > 0.05, "{name}: black image");
            assert!(d.abs() <= 4.0 * noise, "{kind:?} {name}: mean difference {d} vs noise {noise} (mean {mean})");
            let bad = pixels_far_off(&f, &reference);
            assert!(bad <= f.pixels.len() / 50, "{kind:?} {name}: {bad} pixels differ wildly");
        }
    }
}
