//! Tests of the obvhs backend against a brute-force loop over the same watertight triangle test.

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use super::*;
use crate::accel::watertight::ShearedRay;
use crate::geometry::shapes::{axis_box, icosphere, quad, terrain, triangle_soup, uv_sphere};
use crate::sampling::Rng;

/// O(n) reference: the closest hit, ties broken by smallest (geom_id, prim_id) like ObvhsAccel.
fn brute_intersect(meshes: &[Mesh], ray: &Ray) -> Option<Hit> {
    let r = ShearedRay::new(ray.o, ray.d)?;
    let mut best: Option<Hit> = None;
    for (g, m) in meshes.iter().enumerate() {
        for p in 0..m.len() {
            let [p0, p1, p2] = m.triangle(p);
            let limit = best.map_or(ray.t_max, |b| b.t);
            if let Some(h) = r.intersect(p0, p1, p2, limit) {
                if best.is_none_or(|b| h.t < b.t) {
                    let ng = (p1 - p0).cross(p2 - p0);
                    best = Some(Hit {
                        t: h.t,
                        geom_id: g as u32,
                        prim_id: p as u32,
                        u: h.u,
                        v: h.v,
                        ng,
                        inst_id: Hit::NO_INSTANCE,
                    });
                }
            }
        }
    }
    best
}

fn brute_occluded(meshes: &[Mesh], ray: &Ray) -> bool {
    let Some(r) = ShearedRay::new(ray.o, ray.d) else {
        return false;
    };
    meshes.iter().any(|m| {
        (0..m.len()).any(|p| {
            let [p0, p1, p2] = m.triangle(p);
            r.intersect(p0, p1, p2, ray.t_max).is_some_and(|h| h.t < ray.t_max)
        })
    })
}

fn test_scene() -> Vec<Mesh> {
    vec![
        icosphere(Vec3::new(0.0, 1.0, 0.0), 1.0, 3),
        axis_box(Vec3::new(1.5, 0.0, -1.0), Vec3::new(2.5, 1.0, 1.0)),
        uv_sphere(Vec3::new(-2.0, 1.0, 0.5), 0.8, 8, 16),
        terrain(8.0, 16, 0.3, 5),
        triangle_soup(800, Vec3::new(-3.0, 0.5, -3.0), Vec3::new(3.0, 3.0, -1.5), 0.15, 11),
        quad(Vec3::new(-4.0, 0.0, 3.0), Vec3::new(8.0, 0.0, 0.0), Vec3::new(0.0, 4.0, 0.0)),
        axis_box(Vec3::splat(-0.3), Vec3::splat(0.3))
            .transformed(&(Mat4::from_translation(Vec3::new(0.0, 2.5, 1.5)) * Mat4::from_rotation_y(0.7))),
    ]
}

fn random_dir(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - 1.0;
        if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Edge midpoints and vertices of a mesh: the targets where a non-watertight test leaks.
fn edge_and_vertex_targets(m: &Mesh) -> Vec<Vec3> {
    let mut t = m.positions.clone();
    for &[a, b, c] in &m.indices {
        for (p, q) in [(a, b), (b, c), (c, a)] {
            if p < q {
                t.push(0.5 * (m.positions[p as usize] + m.positions[q as usize]));
            }
        }
    }
    t
}

fn test_rays(meshes: &[Mesh]) -> Vec<Ray> {
    let mut rays = Vec::new();
    // Coherent: a pinhole camera grid looking at the scene.
    let eye = Vec3::new(0.5, 3.0, 9.0);
    let n = 256;
    for i in 0..n {
        for j in 0..n {
            let x = (j as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            let y = (i as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            rays.push(Ray::new(eye, Vec3::new(x * 0.6, y * 0.4 - 0.3, -1.0)));
        }
    }
    // Incoherent: random origins around the scene, random directions, some bounded.
    let mut rng = Rng::new(1234, 0);
    for k in 0..40_000 {
        let o = Vec3::new(rng.uniform() * 10.0 - 5.0, rng.uniform() * 5.0 - 1.0, rng.uniform() * 10.0 - 5.0);
        let d = random_dir(&mut rng) * (0.5 + rng.uniform());
        let t_max = if k % 4 == 0 { rng.uniform() * 4.0 } else { f32::INFINITY };
        rays.push(Ray::segment(o, d, t_max));
    }
    // Aimed exactly at shared edges and vertices of the closed meshes, from outside.
    for &g in &[0usize, 1, 2, 6] {
        for target in edge_and_vertex_targets(&meshes[g]) {
            let o = Vec3::new(0.0, 2.0, 0.0) + random_dir(&mut rng) * 7.0;
            rays.push(Ray::new(o, target - o));
        }
    }
    rays
}

#[test]
fn agrees_with_brute_force_on_coherent_random_and_edge_aimed_rays() {
    let meshes = test_scene();
    let accel = ObvhsAccel::new(&meshes);
    let rays = test_rays(&meshes);
    assert!(rays.len() >= 100_000, "{}", rays.len());
    let hits: usize = rays
        .par_iter()
        .enumerate()
        .map(|(k, ray)| {
            let got = accel.intersect(ray);
            assert_eq!(got, brute_intersect(&meshes, ray), "{ray:?}");
            // Every third ray for occlusion: the brute-force reference dominates the test's time.
            if k % 3 == 0 {
                assert_eq!(accel.occluded(ray), brute_occluded(&meshes, ray), "{ray:?}");
            }
            got.is_some() as usize
        })
        .sum();
    // Most rays see something; the test would be vacuous otherwise.
    assert!(hits > rays.len() / 2, "{hits} of {}", rays.len());
}

#[test]
fn occlusion_is_consistent_with_closest_hit() {
    let meshes = test_scene();
    let accel = ObvhsAccel::with_quality(&meshes, BuildQuality::Fast);
    let mut checked = 0;
    for ray in test_rays(&meshes).iter().step_by(3) {
        let unbounded = Ray::new(ray.o, ray.d);
        let hit = accel.intersect(&unbounded);
        assert_eq!(accel.occluded(&unbounded), hit.is_some());
        if let Some(h) = hit {
            // Nothing strictly closer than the closest hit; the hit itself blocks a longer segment.
            assert!(!accel.occluded(&Ray::segment(ray.o, ray.d, h.t)), "{ray:?}");
            assert!(accel.occluded(&Ray::segment(ray.o, ray.d, h.t.next_up())), "{ray:?}");
            assert_eq!(accel.intersect(&Ray::segment(ray.o, ray.d, h.t)), Some(h));
            checked += 1;
        }
    }
    assert!(checked > 10_000, "{checked}");
}

#[test]
fn no_ray_escapes_closed_meshes_from_inside() {
    let meshes = vec![
        icosphere(Vec3::new(0.1, -0.2, 0.3), 1.3, 5),
        uv_sphere(Vec3::new(5.0, 0.0, 0.0), 1.0, 64, 128),
        axis_box(Vec3::new(-8.0, -1.0, -1.0), Vec3::new(-6.0, 1.0, 2.0)),
        axis_box(Vec3::splat(-1.0), Vec3::splat(1.0)).transformed(
            &(Mat4::from_translation(Vec3::new(0.0, 6.0, 0.0)) * Mat4::from_euler(glam::EulerRot::XYZ, 0.3, 0.5, 0.7)),
        ),
    ];
    let accel = ObvhsAccel::new(&meshes);
    let mut total = 0usize;
    for (g, m) in meshes.iter().enumerate() {
        let targets = edge_and_vertex_targets(m);
        let c = m.bounds().center();
        let mut rng = Rng::new(77, g as u64);
        // The centre plus interior points (convex shapes: shrunken vertex combinations are inside).
        let mut origins = vec![c];
        for _ in 0..15 {
            let [a, b, d] = m.triangle((rng.uniform() * m.len() as f32) as usize);
            let (wa, wb) = (rng.uniform(), rng.uniform());
            let onface = a + (b - a) * wa * (1.0 - wb) + (d - a) * wb;
            origins.push(c + (onface - c) * (0.05 + 0.9 * rng.uniform()));
        }
        let escaped: usize = origins
            .par_iter()
            .map(|&o| {
                targets
                    .iter()
                    .filter(|&&t| match accel.intersect(&Ray::new(o, t - o)) {
                        // Convex: the only exit is at the target itself, t = 1.
                        Some(h) => h.geom_id != g as u32 || (h.t - 1.0).abs() > 1e-4,
                        None => true,
                    })
                    .count()
            })
            .sum();
        assert_eq!(escaped, 0, "mesh {g}");
        total += origins.len() * targets.len();
    }
    assert!(total > 1_000_000, "{total}");
}

#[test]
fn empty_scenes_hit_nothing() {
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    for meshes in [vec![], vec![Mesh::default(), Mesh::new(vec![Vec3::ONE], vec![])]] {
        let accel = ObvhsAccel::new(&meshes);
        assert_eq!(accel.intersect(&ray), None);
        assert!(!accel.occluded(&ray));
        assert!(accel.bounds().is_empty());
        assert_eq!(accel.stats().triangles, 0);
    }
}

#[test]
fn degenerate_triangles_and_bad_indices_are_skipped_and_counted() {
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0), // collinear with 0, 1
        Vec3::new(f32::NAN, 0.0, 0.0),
        Vec3::new(0.0, f32::INFINITY, 0.0),
    ];
    let indices = vec![[0, 1, 3], [0, 0, 2], [0, 1, 4], [5, 1, 2], [0, 1, 99], [0, 1, 2]];
    let accel = ObvhsAccel::new(&[Mesh::new(positions, indices)]);
    let s = accel.stats();
    assert_eq!((s.triangles, s.skipped_degenerate, s.skipped_bad_index), (1, 4, 1));
    let hit = accel.intersect(&Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z)).unwrap();
    assert_eq!((hit.geom_id, hit.prim_id), (0, 5));
    assert_eq!(hit.ng, Vec3::Z);
    assert_eq!(accel.bounds(), Bounds3 { min: Vec3::ZERO, max: Vec3::new(1.0, 1.0, 0.0) });
}

#[test]
fn bad_rays_hit_nothing_without_panicking() {
    let accel = ObvhsAccel::new(&[icosphere(Vec3::ZERO, 1.0, 2)]);
    let bad = [
        Ray::new(Vec3::NAN, Vec3::X),
        Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::ZERO),
        Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(f32::INFINITY, 0.0, 0.0)),
        Ray::segment(Vec3::new(-3.0, 0.0, 0.0), Vec3::X, -1.0),
        Ray::segment(Vec3::new(-3.0, 0.0, 0.0), Vec3::X, f32::NAN),
    ];
    for r in bad {
        assert_eq!(accel.intersect(&r), None, "{r:?}");
        assert!(!accel.occluded(&r), "{r:?}");
    }
    // Axis-parallel directions with signed zeros still hit.
    for d in [Vec3::new(1.0, 0.0, -0.0), Vec3::new(1.0, -0.0, 0.0)] {
        assert!(accel.intersect(&Ray::new(Vec3::new(-3.0, 0.0, 0.0), d)).is_some());
    }
}

#[test]
fn coincident_triangles_and_all_qualities_agree_with_brute_force() {
    // 20k copies of one triangle: PLOC sees identical boxes, the worst case for tree depth.
    let one = quad(Vec3::ZERO, Vec3::X, Vec3::Y);
    let stack = Mesh::new(one.positions.clone(), (0..10_000).flat_map(|_| one.indices.clone()).collect());
    let meshes = vec![stack, triangle_soup(3000, Vec3::splat(-1.0), Vec3::splat(2.0), 0.2, 3)];
    let mut rng = Rng::new(5, 5);
    let rays: Vec<Ray> = (0..500)
        .map(|_| Ray::new(Vec3::new(rng.uniform(), rng.uniform(), 3.0), random_dir(&mut rng) - 2.0 * Vec3::Z))
        .collect();
    for q in [BuildQuality::Fastest, BuildQuality::Fast, BuildQuality::Medium, BuildQuality::Slow] {
        let accel = ObvhsAccel::with_quality(&meshes, q);
        assert_eq!(accel.stats().triangles, 23_000);
        for ray in &rays {
            assert_eq!(accel.intersect(ray), brute_intersect(&meshes, ray), "{q:?} {ray:?}");
        }
    }
}

#[test]
fn linear_fallback_agrees_with_traversal() {
    // The fallback only triggers for trees deeper than the traversal stack; force it to test the path.
    let meshes = test_scene();
    let accel = ObvhsAccel::new(&meshes);
    assert!(!accel.stats().linear_fallback && accel.stats().max_depth > 0);
    let mut linear = ObvhsAccel::new(&meshes);
    linear.stats.linear_fallback = true;
    for ray in test_rays(&meshes).iter().step_by(20) {
        assert_eq!(linear.intersect(ray), accel.intersect(ray), "{ray:?}");
        assert_eq!(linear.occluded(ray), accel.occluded(ray), "{ray:?}");
    }
}

#[test]
fn huge_page_arrays_agree_with_heap_arrays_and_brute_force() {
    // 32,768 + 5,120 triangles: 2.4 MB of triangle records, more than one 2 MiB huge page.
    let meshes = vec![terrain(8.0, 128, 0.5, 9), icosphere(Vec3::new(0.0, 1.5, 0.0), 1.0, 4)];
    let accel = ObvhsAccel::new(&meshes);
    assert_eq!(accel.triangles.is_mapped(), cfg!(unix));
    let heap = ObvhsAccel::new(&meshes).without_huge_pages();
    assert!(!heap.triangles.is_mapped() && !heap.nodes.is_mapped());
    assert_eq!(accel.memory_bytes(), heap.memory_bytes());
    let mut rng = Rng::new(77, 3);
    let rays: Vec<Ray> = (0..4000)
        .map(|_| {
            let o = Vec3::new(rng.uniform() * 8.0 - 4.0, rng.uniform() * 3.0 - 0.5, rng.uniform() * 8.0 - 4.0);
            Ray::new(o, random_dir(&mut rng))
        })
        .collect();
    let hits: usize = rays
        .par_iter()
        .enumerate()
        .map(|(k, ray)| {
            let got = accel.intersect(ray);
            assert_eq!(got, heap.intersect(ray), "{ray:?}");
            assert_eq!(accel.occluded(ray), heap.occluded(ray), "{ray:?}");
            if k % 8 == 0 {
                assert_eq!(got, brute_intersect(&meshes, ray), "{ray:?}");
            }
            got.is_some() as usize
        })
        .sum();
    assert!(hits > rays.len() / 3, "{hits} of {}", rays.len());
}

/// A hit's floats as bits: stricter than `==` (which equates +0 and -0).
fn hit_bits(h: &Hit) -> (u32, u32, u32, [u32; 3], u32, u32) {
    (h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), h.ng.to_array().map(f32::to_bits), h.geom_id, h.prim_id)
}

#[test]
fn dispatched_and_baseline_queries_agree_bit_for_bit() {
    // The trait methods run the AVX2+FMA variant on a CPU that has both (`obvhs_isa.rs`); the
    // inherent methods called here are inlined into this test, compiled for the baseline target.
    // Both must return the same bits.
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
    #[cfg(not(target_arch = "x86_64"))]
    let avx2 = false;
    // Without AVX2+FMA at run time, or with a build that already targets AVX2, the dispatcher
    // runs the baseline code itself: the comparison would hold trivially.
    if !avx2 || cfg!(target_feature = "avx2") {
        eprintln!("skipped: dispatched and baseline queries are the same code on this CPU and build");
        return;
    }
    let meshes = test_scene();
    let accel = ObvhsAccel::new(&meshes);
    let rays = test_rays(&meshes);
    let (mut hits, mut all_hits) = (0, 0);
    let (mut got_all, mut want_all) = (Vec::new(), Vec::new());
    for (k, ray) in rays.iter().enumerate() {
        let got = accel.intersect(ray);
        assert_eq!(got.as_ref().map(hit_bits), accel.closest_hit(ray).as_ref().map(hit_bits), "{ray:?}");
        assert_eq!(accel.occluded(ray), accel.any_hit(ray), "{ray:?}");
        if k % 4 == 0 {
            got_all.clear();
            want_all.clear();
            accel.intersect_all(ray, &mut got_all);
            accel.every_hit(ray, &mut want_all);
            assert_eq!(
                got_all.iter().map(hit_bits).collect::<Vec<_>>(),
                want_all.iter().map(hit_bits).collect::<Vec<_>>()
            );
            all_hits += got_all.len();
        }
        hits += got.is_some() as usize;
    }
    assert!(hits > rays.len() / 2 && all_hits > hits / 4, "{hits} {all_hits} of {}", rays.len());
}
