//! Embree writes no byte past the hit record prism declares, on every path that fills one: its
//! triangle kernel and the watertight user geometry, in a flat scene and under an instance
//! (whose hits carry the instance words). A canary follows the `RTCRayHit` in memory.

use glam::{Mat4, Vec3};

use super::device::Device;
use super::ffi;
use super::instanced::InstancedScene;
use super::library_check::GuardedRayHit;
use super::scene::Scene;
use super::TriangleTest;
use crate::geometry::{Instance, InstanceSet, Prototype};
use crate::geometry::{Mesh, Ray};

/// A unit quad in z = 0 (two triangles), so the probe ray at (0.25, 0.5) hits triangle 0.
fn quad() -> Mesh {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    Mesh::new(p, vec![[0, 1, 2], [0, 2, 3]])
}

/// The probe ray: straight down onto the quad from z = 1 (shifted by `dx` in x).
fn probe(dx: f32) -> GuardedRayHit {
    GuardedRayHit::new(Scene::rtc_ray(&Ray::new(Vec3::new(0.75 + dx, 0.25, 1.0), Vec3::NEG_Z)))
}

fn assert_record_kept(g: &GuardedRayHit, what: &str) {
    assert_eq!(g.rh.hit.geomID, 0, "{what}: the probe ray must hit mesh 0 ({:?})", g.rh);
    // 1 up to the rounding of the kernel Embree picks for the CPU (1 − 2⁻²⁴ from its AVX2 kernel).
    assert!((g.rh.ray.tfar - 1.0).abs() <= 4.0 * f32::EPSILON, "{what}: t = {}", g.rh.ray.tfar);
    assert!(
        g.overwritten_past_record().is_empty(),
        "{what}: words {:?} past the hit record were written",
        g.overwritten_past_record()
    );
    // Every declared instance word was written: a record declared one word shorter (as Embree
    // 4.2's headers declare 4.3+'s hit) would have been overrun.
    let words = g.instance_words();
    assert!(words.iter().all(|&w| w != 0xA5A5_A5A5), "{what}: instance words {words:x?} not all written");
}

#[test]
fn no_byte_past_the_hit_record_is_written_flat_or_instanced_by_either_triangle_test() {
    let mut instance_words = Vec::new();
    for test in [TriangleTest::Embree, TriangleTest::Watertight] {
        let q = ffi::RTCBuildQuality_RTC_BUILD_QUALITY_MEDIUM;
        // Triangles, and (with Embree's test) the two triangles paired into an Embree quad.
        for choice in [super::BuildChoice::MEDIUM, super::BuildChoice { quads: true, ..super::BuildChoice::MEDIUM }] {
            let flat = Scene::build(Device::new().unwrap(), &[quad()], choice, test).unwrap();
            let mut g = probe(0.0);
            flat.raw_intersect(&mut g.rh);
            assert_record_kept(&g, &format!("{test:?}, flat, {choice:?}"));
            assert_eq!(g.instance_words()[0], ffi::RTC_INVALID_GEOMETRY_ID, "{test:?}, flat: no instance");
        }

        // One world mesh (top-level geometry 0, far away) and one instance (geometry 1) of the
        // quad moved by +10 in x.
        let far = Mesh::new(
            vec![Vec3::splat(100.0), Vec3::new(101.0, 100.0, 100.0), Vec3::new(100.0, 101.0, 100.0)],
            vec![[0, 1, 2]],
        );
        let set = InstanceSet {
            world_meshes: vec![1],
            prototypes: vec![Prototype { meshes: vec![0] }],
            instances: vec![Instance::new(0, Mat4::from_translation(Vec3::new(10.0, 0.0, 0.0))).unwrap()],
        };
        let shapes = crate::accel::ShapeTable::new(Default::default());
        for quads in [false, true] {
            let meshes = [quad(), far.clone()];
            let inst =
                InstancedScene::build(Device::new().unwrap(), &meshes, &shapes, &set, q, test, None, quads).unwrap();
            let mut g = probe(10.0);
            inst.raw_intersect(&mut g.rh);
            assert_record_kept(&g, &format!("{test:?}, instanced, quads {quads}"));
            assert_eq!(g.instance_words()[0], 1, "{test:?}: the instance is top-level geometry 1");
            if !quads {
                instance_words.push(g.instance_words());
            }
        }
    }
    // The watertight callbacks copy the same instance words Embree's own kernel writes.
    assert_eq!(instance_words[0], instance_words[1], "instance words: Embree's kernel vs the user geometry");
}
