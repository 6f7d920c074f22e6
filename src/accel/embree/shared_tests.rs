//! Meshes Embree reads in place, and compact leaves, trace as Embree's default copy does, and
//! Embree then holds less: no copy of the arrays, index leaves instead of vertex copies.

use super::{BuildChoice, BuildQuality, EmbreeAccel, TriangleTest};
use crate::accel::{build_scene, build_scene_shared, Accel, AccelKind, ExtraShapes};
use crate::geometry::shapes::icosphere;
use crate::geometry::{InstanceSet, Mesh, Ray};
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
        let compact = BuildChoice { quality, compact: true };
        let compact = EmbreeAccel::with_test(&meshes, compact, TriangleTest::Embree).unwrap();
        assert_same_hits(&default, &compact);
        assert!(compact.memory_bytes() < default.memory_bytes(), "{quality:?}");
    }
}
