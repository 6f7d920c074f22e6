//! Curves on Embree (native flat Bézier curves for flat and cylinder curves, user geometry
//! running pbrt-v4's intersector for ribbons) against obvhs (a curve BVH with pbrt-v4's
//! recursive intersector): build time and closest-hit rays/s on one thread over a bundle of
//! 10 000 hair strands (20 000 cubic segments), as cylinder curves and as ribbons. Camera rays are a pinhole's grid
//! over the bundle; random rays start 4 units out and aim at random points in it. The backends
//! take turns on each 4096-ray chunk, timed by the thread's CPU time; the figure is the median
//! over passes.
//!
//! `cargo bench --bench curves`; `PRISM_BENCH_PASSES` (default 5).

use std::time::Instant;

use cpu_time::ThreadTime;
use glam::Vec3;

use prism::accel::{self, Accel, AccelKind};
use prism::geometry::shapes::{hair_bundle, rays_into_hair_bundle};
use prism::geometry::{CurveKind, Mesh, Ray};

const CHUNK: usize = 4096;

/// A 512² pinhole image of the bundle from 2.5 units in front of it.
fn camera_rays() -> Vec<Ray> {
    let eye = Vec3::new(0.0, 0.6, -2.5);
    let n = 512;
    (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f32 / n as f32 - 0.5, 0.5 - (i / n) as f32 / n as f32);
            Ray::new(eye, Vec3::new(0.6 * x, 0.6 * y, 1.0).normalize())
        })
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let passes: usize = std::env::var("PRISM_BENCH_PASSES").ok().and_then(|s| s.parse().ok()).unwrap_or(5);
    for kind in [CurveKind::Cylinder, CurveKind::Ribbon] {
        bench(kind, passes);
    }
}

/// Builds both backends over the bundle as curves of `kind` and times their rays.
fn bench(kind: CurveKind, passes: usize) {
    let curves = hair_bundle(10_000, kind, 1);
    let meshes = vec![Mesh::default()];
    let backends: Vec<(&str, Box<dyn Accel>)> = [("embree", AccelKind::Embree), ("obvhs", AccelKind::Obvhs)]
        .into_iter()
        .map(|(name, accel_kind)| {
            let t0 = Instant::now();
            let a = accel::build_with_curves(accel_kind, &meshes, &[(0, &curves)]).expect("build");
            println!(
                "{kind:?}, {name}: build {:.3} s over {} segments",
                t0.elapsed().as_secs_f64(),
                curves.segments.len()
            );
            (name, a)
        })
        .collect();
    for (label, rays) in [("camera", camera_rays()), ("random", rays_into_hair_bundle(1 << 18, 7))] {
        let mut rates = vec![Vec::new(); backends.len()];
        let mut hits = vec![0usize; backends.len()];
        for _ in 0..passes {
            let mut secs = vec![0.0f64; backends.len()];
            for (c, chunk) in rays.chunks(CHUNK).enumerate() {
                for k in 0..backends.len() {
                    let b = (c + k) % backends.len();
                    let t0 = ThreadTime::now();
                    hits[b] += chunk.iter().filter(|r| backends[b].1.intersect(r).is_some()).count();
                    secs[b] += t0.elapsed().as_secs_f64();
                }
            }
            for (r, s) in rates.iter_mut().zip(secs) {
                r.push(rays.len() as f64 / s * 1e-6);
            }
        }
        for (b, (name, _)) in backends.iter().enumerate() {
            let r = rates[b].clone();
            println!(
                "{kind:?}, {label}: {name} {:.2} M rays/s (median of {passes}; range {:.2}–{:.2}), hit fraction {:.3}",
                median(r.clone()),
                r.iter().cloned().fold(f64::INFINITY, f64::min),
                r.iter().cloned().fold(0.0, f64::max),
                hits[b] as f64 / (passes * rays.len()) as f64
            );
        }
    }
}
