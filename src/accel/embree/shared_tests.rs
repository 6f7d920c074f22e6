//! Meshes Embree reads in place, and compact leaves, trace as Embree's default copy does, and
//! Embree then holds less: no copy of the arrays, index leaves instead of vertex copies.

use super::{BuildChoice, BuildQuality, EmbreeAccel, TriangleTest};
use crate::accel::{build_scene, build_scene_shared, Accel, AccelKind, ExtraShapes};
use crate::geometry::shapes::icosphere;
use crate::geometry::{Hit, InstanceSet, Mesh, Ray};
use crate::sampling::Rng;
use glam::Vec3;
use std::sync::Arc;

const CENTRE: Vec3 = Vec3::new(0.2, -0.1, 0.3);

/// A closed sphere of 20,480 triangles with room after its last vertex (as the scene leaves it).
fn sphere() -> Mesh {
    let mut mesh = icosphere(CENTRE, 1.0, 5);
    mesh.positions.reserve_exact(1);
    mesh
}

/// Rays from random points inside a box around the sphere in random directions.
fn rays(n: usize) -> Vec<Ray> {
    let mut rng = Rng::new(7, 3);
    let mut u = || 2.0 * rng.uniform() - 1.0;
    (0..n).map(|_| Ray::new(Vec3::new(u(), u(), u()) * 1.5, Vec3::new(u(), u(), u()))).collect()
}

fn assert_same_hits(a: &dyn Accel, b: &dyn Accel) {
    let (mut hits, mut inside) = (0, 0);
    for r in &rays(20_000) {
        let ha = a.intersect(r);
        assert_eq!(ha, b.intersect(r), "{r:?}");
        assert_eq!(a.occluded(r), b.occluded(r), "{r:?}");
        hits += ha.is_some() as usize;
        // A ray from well inside the closed sphere (its flat faces lie within 10⁻³ of the
        // radius) meets it.
        if r.o.distance(CENTRE) < 0.99 {
            inside += 1;
            assert!(ha.is_some(), "{r:?}");
        }
    }
    // About 4.2/27 of the box is inside the sphere.
    assert!(inside > 2000 && hits > inside, "{inside} inside, {hits} hits");
}

#[test]
fn shared_arrays_trace_as_a_copy_without_embree_holding_one() {
    let meshes: Arc<[Mesh]> = vec![sphere()].into();
    let none = InstanceSet::default();
    let copied = build_scene(AccelKind::Embree, &meshes, ExtraShapes::default(), &none).unwrap();
    let shared = build_scene_shared(AccelKind::Embree, &meshes, ExtraShapes::default(), &none, None).unwrap();
    assert_same_hits(copied.as_ref(), shared.as_ref());
    let arrays = 12 * (meshes[0].positions.len() + meshes[0].indices.len());
    assert!(
        shared.memory_bytes() + arrays <= copied.memory_bytes(),
        "shared {} + arrays {arrays} > copied {}",
        shared.memory_bytes(),
        copied.memory_bytes()
    );
}

#[test]
fn a_mesh_without_room_after_its_last_vertex_is_copied() {
    let mut mesh = sphere();
    mesh.positions.shrink_to_fit();
    let exact: Arc<[Mesh]> = vec![mesh].into();
    let padded: Arc<[Mesh]> = vec![sphere()].into();
    let none = InstanceSet::default();
    let copied = build_scene_shared(AccelKind::Embree, &exact, ExtraShapes::default(), &none, None).unwrap();
    let shared = build_scene_shared(AccelKind::Embree, &padded, ExtraShapes::default(), &none, None).unwrap();
    assert_same_hits(copied.as_ref(), shared.as_ref());
    assert!(copied.memory_bytes() > shared.memory_bytes());
}

#[test]
fn compact_leaves_trace_as_vertex_leaves_in_less_memory() {
    let meshes = [sphere()];
    let default = EmbreeAccel::with_test(&meshes, BuildChoice::MEDIUM, TriangleTest::Embree).unwrap();
    for quality in [BuildQuality::Medium, BuildQuality::Low] {
        let compact = BuildChoice { quality, compact: true, quads: false };
        let compact = EmbreeAccel::with_test(&meshes, compact, TriangleTest::Embree).unwrap();
        assert_same_hits(&default, &compact);
        assert!(compact.memory_bytes() < default.memory_bytes(), "{quality:?}");
    }
}

/// A closed sphere of 6 n² quads, each listed as two triangles in a row: a cube's faces cut
/// into n × n cells and pushed onto the unit sphere around [`CENTRE`] (points on shared edges
/// are computed from the same coordinates, so they are the same floats).
fn quad_sphere(n: u32) -> Mesh {
    let (mut positions, mut indices) = (Vec::new(), Vec::new());
    let c = |i: u32| -1.0 + 2.0 * i as f32 / n as f32;
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let base = positions.len() as u32;
            for j in 0..=n {
                for i in 0..=n {
                    let mut p = [0.0; 3];
                    (p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3]) = (side, c(i), c(j));
                    positions.push(CENTRE + Vec3::from(p).normalize());
                }
            }
            let id = |i: u32, j: u32| base + j * (n + 1) + i;
            for j in 0..n {
                for i in 0..n {
                    indices.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                    indices.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
    }
    positions.reserve_exact(1);
    Mesh::new(positions, indices)
}

/// A hit and whether the ray is occluded, by one accelerator.
type Trace<'a> = &'a dyn Fn(&Ray) -> (Option<Hit>, bool);

/// The hits of `triangles` and `quads` (the same triangles of `mesh`, the second traced as
/// quads) along `rays`, checked alike: the same hits, misses and occlusion; on a hit the same
/// geometry and instance, t within 10⁻⁵, the same point, and the same triangle or its partner
/// across the quad's diagonal (on which the point lies in both).
fn paired_hits(mesh: &Mesh, rays: &[Ray], triangles: Trace, quads: Trace) -> Vec<(Hit, Hit)> {
    let point = |h: &Hit| {
        let t = mesh.indices[h.prim_id as usize].map(|i| mesh.positions[i as usize]);
        (1.0 - h.u - h.v) * t[0] + h.u * t[1] + h.v * t[2]
    };
    let mut pairs = Vec::new();
    for r in rays {
        let ((a, a_blocked), (b, b_blocked)) = (triangles(r), quads(r));
        assert_eq!(a_blocked, b_blocked, "{r:?}");
        let (Some(a), Some(b)) = (a, b) else {
            assert_eq!(a, b, "{r:?}");
            continue;
        };
        assert_eq!((a.geom_id, a.inst_id), (b.geom_id, b.inst_id), "{r:?}");
        assert!((a.t - b.t).abs() <= 1e-5 * a.t, "{r:?}: {a:?} {b:?}");
        assert!(point(&a).distance(point(&b)) < 1e-5, "{r:?}: {a:?} {b:?}");
        assert!(a.prim_id == b.prim_id || a.prim_id / 2 == b.prim_id / 2, "{r:?}: {a:?} {b:?}");
        pairs.push((a, b));
    }
    pairs
}

#[test]
fn triangles_paired_into_quads_give_the_triangles_hits_in_less_memory() {
    let meshes = [quad_sphere(40)];
    let mut rays = rays(20_000);
    // Also rays aimed at the shared diagonals of the first cells, where either half may report.
    rays.extend((0..200).map(|k| {
        let m = &meshes[0];
        let [a, _, c] = m.indices[2 * k];
        let on_diagonal = m.positions[a as usize].lerp(m.positions[c as usize], 0.37);
        Ray::new(CENTRE, on_diagonal - CENTRE)
    }));
    for compact in [false, true] {
        let triangles = BuildChoice { quality: BuildQuality::Medium, compact, quads: false };
        let triangles = EmbreeAccel::with_test(&meshes, triangles, TriangleTest::Embree).unwrap();
        let quads = BuildChoice { quality: BuildQuality::Medium, compact, quads: true };
        let quads = EmbreeAccel::with_test(&meshes, quads, TriangleTest::Embree).unwrap();
        let trace = |acc: &EmbreeAccel, r: &Ray| (acc.intersect(r), acc.occluded(r));
        let pairs = paired_hits(&meshes[0], &rays, &|r| trace(&triangles, r), &|r| trace(&quads, r));
        assert!(pairs.len() > 4_000, "{}", pairs.len());
        // Off the triangles' edges, the same geometric normal (on the diagonal Embree's may be
        // the other half's).
        for (a, b) in pairs.iter().filter(|(a, _)| a.u.min(a.v).min(1.0 - a.u - a.v) > 1e-4) {
            assert!(a.ng.normalize().dot(b.ng.normalize()) > 0.999_99, "{a:?} {b:?}");
        }
        // From inside the closed sphere (its flat cells lie within 10⁻³ of the radius) a ray
        // meets it.
        for r in rays.iter().filter(|r| r.o.distance(CENTRE) < 0.99) {
            assert!(quads.intersect(r).is_some(), "{r:?}");
        }
        // Embree's BVH over half as many primitives, with the quads' arrays: 0.68× the bytes
        // with vertex leaves, 0.70× with index leaves (measured).
        assert!(quads.memory_bytes() < triangles.memory_bytes(), "compact {compact}");
    }
}

#[test]
fn a_mesh_that_pairs_few_triangles_stays_triangles() {
    // The sphere's triangles in a scattered order (k ↦ 7919 k mod n): neighbours in the list
    // are rarely neighbours on the sphere.
    let mut mesh = sphere();
    let n = mesh.indices.len();
    mesh.indices = (0..n).map(|k| mesh.indices[k * 7919 % n]).collect();
    let meshes = [mesh];
    let quads = BuildChoice { quality: BuildQuality::Medium, compact: false, quads: true };
    let quads = EmbreeAccel::with_test(&meshes, quads, TriangleTest::Embree).unwrap();
    let triangles = EmbreeAccel::with_test(&meshes, BuildChoice::MEDIUM, TriangleTest::Embree).unwrap();
    assert_same_hits(&triangles, &quads);
    assert_eq!(quads.memory_bytes(), triangles.memory_bytes());
}

#[test]
fn instanced_quads_give_the_instanced_triangles_hits_in_less_memory() {
    use super::device::Device;
    use super::instanced::InstancedScene;
    use crate::geometry::{Instance, Prototype};
    let meshes = [quad_sphere(40)];
    let shift = Vec3::new(3.0, 0.0, 0.0);
    let set = InstanceSet {
        world_meshes: vec![],
        prototypes: vec![Prototype { meshes: vec![0] }],
        instances: vec![Instance::new(0, glam::Mat4::from_translation(shift)).unwrap()],
    };
    let shapes = crate::accel::ShapeTable::new(Default::default());
    let q = super::ffi::RTCBuildQuality_RTC_BUILD_QUALITY_MEDIUM;
    let build = |quads| {
        InstancedScene::build(Device::new().unwrap(), &meshes, &shapes, &set, q, TriangleTest::Embree, None, quads)
            .unwrap()
    };
    let (triangles, quads) = (build(false), build(true));
    let rays: Vec<Ray> = rays(20_000).iter().map(|r| Ray::new(r.o + shift, r.d)).collect();
    let trace = |s: &InstancedScene, r: &Ray| (s.intersect(r), s.occluded(r));
    let pairs = paired_hits(&meshes[0], &rays, &|r| trace(&triangles, r), &|r| trace(&quads, r));
    assert!(pairs.len() > 4_000, "{}", pairs.len());
    assert!(quads.memory_bytes() < triangles.memory_bytes());
}
