//! Embree's own curves against pbrt-v4's (prism's curve test, as the obvhs curve BVH runs it)
//! on ribbons whose normal turns by 0° and by 90° along them and on bent flat curves, and the
//! curve user geometry against the same: it must find exactly the obvhs hits.

use glam::Vec3;

use super::super::device::Device;
use super::super::scene::Scene;
use super::super::TriangleTest;
use crate::accel::CurveBvh;
use crate::geometry::curve_hit::curve_surface;
use crate::geometry::shapes::{level_ray_into_ribbon_grid, ribbon_grid};
use crate::geometry::{CurveKind, CurveSegment, Curves, Hit, Mesh, Ray};
use crate::sampling::Rng;

/// Strand width [scene units].
const WIDTH: f32 = 0.05;

/// How a backend's closest hits compare with the obvhs curve BVH's on the same rays.
#[derive(Debug, Default)]
struct Agreement {
    both: usize,
    one_sided: usize,
    other_strand: usize,
    /// Largest distance between the hit points where both hit one strand [widths].
    max_dp: f32,
    max_du: f32,
    /// Largest angle [degrees] between the normal the backend reports (Embree's curves report
    /// one) and pbrt-v4's ribbon normal at the obvhs hit.
    max_normal_deg: f32,
}

fn compare(intersect: impl Fn(&Ray) -> Option<Hit>, curves: &Curves) -> Agreement {
    let bvh = CurveBvh::new(&[(0, curves)]);
    let mut rng = Rng::new(31, 4);
    let mut g = Agreement::default();
    for _ in 0..20_000 {
        let ray = level_ray_into_ribbon_grid(&mut rng);
        match (intersect(&ray), bvh.intersect(&ray)) {
            (Some(x), Some(y)) if x.prim_id != y.prim_id => g.other_strand += 1,
            (Some(x), Some(y)) => {
                g.both += 1;
                g.max_dp = g.max_dp.max((ray.at(x.t) - ray.at(y.t)).length() / WIDTH);
                g.max_du = g.max_du.max((x.u - y.u).abs());
                if x.ng != Vec3::ZERO {
                    let n = curve_surface(&curves.segments[y.prim_id as usize], &ray, y.t, y.u).unwrap().n;
                    let cos = x.ng.normalize().dot(n).abs().min(1.0);
                    g.max_normal_deg = g.max_normal_deg.max(cos.acos().to_degrees());
                }
            }
            (None, None) => {}
            _ => g.one_sided += 1,
        }
    }
    g
}

/// Embree's own curves and the user geometry against the obvhs curve BVH on `curves`: the user
/// geometry finds exactly the obvhs hits; with `differs`, Embree's own curves are more than
/// rounding apart (hits on one side only, hit points a sizeable fraction of the width apart).
fn check(name: &str, curves: &Curves, differs: bool) {
    let native = Scene::native_curves(Device::new().unwrap(), curves).unwrap();
    let q = super::super::BuildChoice::MEDIUM;
    let extra = crate::accel::ExtraShapes { curves: &[(0, curves)], quadrics: &[] };
    let user =
        Scene::build_with_extra(Device::new().unwrap(), &[Mesh::default()], extra, q, TriangleTest::Embree, None)
            .unwrap();
    let n = compare(|r| native.intersect(r), curves);
    let u = compare(|r| user.intersect(r), curves);
    eprintln!("{name}: Embree's curves {n:?}");
    eprintln!("{name}: user geometry   {u:?}");
    assert!(u.both > 2000, "{u:?}");
    assert_eq!((u.one_sided, u.other_strand, u.max_dp, u.max_du), (0, 0, 0.0, 0.0), "{u:?}");
    for r in [Ray::new(Vec3::new(-3.0, 0.5, 0.0), Vec3::X), Ray::new(Vec3::new(0.0, 0.3, 3.0), Vec3::NEG_Z)] {
        assert_eq!(user.occluded(&r), user.intersect(&r).is_some());
    }
    if differs {
        assert!(n.one_sided > 20 && n.max_dp > 0.05, "{n:?}");
    }
}

#[test]
fn embree_ribbons_are_not_pbrt_v4s_and_the_user_geometry_finds_the_obvhs_hits() {
    for twist in [0.0f32, std::f32::consts::FRAC_PI_2] {
        check(&format!("ribbons, twist {:.0}°", twist.to_degrees()), &ribbon_grid(twist, WIDTH), twist > 0.0);
    }
}

#[test]
fn embree_flat_curves_are_polylines_on_bent_segments_and_the_user_geometry_finds_the_obvhs_hits() {
    // S-shaped tapered segments, bent across their length in the plane facing most rays:
    // Embree's four quads per segment cut the bends, pbrt-v4's subdivision follows them.
    for kind in [CurveKind::Flat, CurveKind::Cylinder] {
        let segments = (0..100)
            .map(|i| {
                let root = Vec3::new((i % 10) as f32 / 9.0 - 0.5, 0.0, (i / 10) as f32 / 9.0 - 0.5);
                let cp = [(0.0, 0.0), (0.35, 1.0 / 3.0), (-0.35, 2.0 / 3.0), (0.0, 1.0)]
                    .map(|(x, y)| root + Vec3::new(x * 0.3, y, x * 0.3));
                CurveSegment::new(cp, [WIDTH, 0.3 * WIDTH], kind, [Vec3::ZERO; 2])
            })
            .collect();
        check(&format!("{kind:?}, bent"), &Curves { segments, split_depth: 3, flip_normal: false }, true);
    }
}

/// Closest-hit rays per second on one thread over 10 000 hair strands, flat and as ribbons:
/// Embree's own curves, the curve user geometry and the obvhs curve BVH, taking turns on
/// 4096-ray chunks of rays aimed into the bundle from 4 units out, each timed by the thread's CPU
/// clock; the medians of five passes. `cargo test --release --lib curve_speed -- --ignored
/// --nocapture`.
#[test]
#[ignore = "a measurement, not a check"]
fn curve_speed() {
    use cpu_time::ThreadTime;
    for kind in [CurveKind::Flat, CurveKind::Ribbon] {
        let curves = crate::geometry::shapes::hair_bundle(10_000, kind, 1);
        let native = Scene::native_curves(Device::new().unwrap(), &curves).unwrap();
        let q = super::super::BuildChoice::MEDIUM;
        let extra = crate::accel::ExtraShapes { curves: &[(0, &curves)], quadrics: &[] };
        let user =
            Scene::build_with_extra(Device::new().unwrap(), &[Mesh::default()], extra, q, TriangleTest::Embree, None)
                .unwrap();
        let bvh = CurveBvh::new(&[(0, &curves)]);
        let rays = crate::geometry::shapes::rays_into_hair_bundle(1 << 18, 7);
        type Trace<'a> = &'a dyn Fn(&Ray) -> bool;
        let backends: [(&str, Trace); 3] = [
            ("Embree's own curves", &|r| native.intersect(r).is_some()),
            ("curve user geometry", &|r| user.intersect(r).is_some()),
            ("obvhs curve BVH", &|r| bvh.intersect(r).is_some()),
        ];
        let mut rates = vec![Vec::new(); 3];
        for _ in 0..5 {
            let mut secs = [0.0f64; 3];
            let mut hits = [0usize; 3];
            for (c, chunk) in rays.chunks(4096).enumerate() {
                for k in 0..3 {
                    let b = (c + k) % 3;
                    let t0 = ThreadTime::now();
                    hits[b] += chunk.iter().filter(|r| backends[b].1(r)).count();
                    secs[b] += t0.elapsed().as_secs_f64();
                }
            }
            for b in 0..3 {
                rates[b].push(rays.len() as f64 / secs[b] * 1e-6);
            }
            eprintln!("{kind:?}: hit fractions {:?}", hits.map(|h| h as f64 / rays.len() as f64));
        }
        for (b, (name, _)) in backends.iter().enumerate() {
            rates[b].sort_by(f64::total_cmp);
            eprintln!(
                "{kind:?}, {name}: {:.2} M rays/s (median of 5; {:.2}–{:.2})",
                rates[b][2], rates[b][0], rates[b][4]
            );
        }
    }
}
