//! Ray-intersection benchmarks: BVH build time and rays/s for coherent (camera) and incoherent
//! (random) rays over a ~1M-triangle scene, on one thread and on all cores.
//!
//! Embree is also measured through raw `rtcIntersect1` calls (the wrapper-overhead baseline).
//! Backends plug in through [`bench_backend`] with a builder returning `Box<dyn Accel>`; add a line
//! in `benches` for each. `PRISM_BENCH_SCALE` (default 1.0) scales the triangle count for quick
//! smoke runs, e.g. `PRISM_BENCH_SCALE=0.05 cargo bench --no-default-features --bench accel`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use prism::accel::{Accel, BuildQuality, ObvhsAccel};
use prism::geometry::{Mesh, Ray};
use rayon::prelude::*;

mod common;
use common::{coherent_rays, incoherent_rays, scene, RAYS};

/// Closest hits over `rays`, on this thread or on rayon's pool; returns the hit count.
fn trace(accel: &dyn Accel, rays: &[Ray], parallel: bool) -> usize {
    if parallel {
        rays.par_iter().filter(|r| accel.intersect(r).is_some()).count()
    } else {
        rays.iter().filter(|r| accel.intersect(r).is_some()).count()
    }
}

/// Shadow-ray queries over `rays` (bounded at t = 50).
fn occlude(accel: &dyn Accel, rays: &[Ray], parallel: bool) -> usize {
    let f = |r: &Ray| accel.occluded(&Ray::segment(r.o, r.d, 50.0));
    if parallel {
        rays.par_iter().filter(|r| f(r)).count()
    } else {
        rays.iter().filter(|r| f(r)).count()
    }
}

/// Build and trace benchmarks for one backend. `build` turns the scene into an accelerator.
pub fn bench_backend(c: &mut Criterion, name: &str, meshes: &[Mesh], build: &dyn Fn(&[Mesh]) -> Box<dyn Accel>) {
    let tris: usize = meshes.iter().map(Mesh::len).sum();
    let mut g = c.benchmark_group(format!("{name}/build"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(tris as u64));
    g.bench_function(BenchmarkId::from_parameter(tris), |b| b.iter(|| black_box(build(meshes))));
    g.finish();

    let accel = build(meshes);
    let sets = [("coherent", coherent_rays()), ("incoherent", incoherent_rays(accel.as_ref()))];
    let mut g = c.benchmark_group(format!("{name}/rays"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(RAYS as u64));
    for (kind, rays) in &sets {
        for (threads, parallel) in [("1thread", false), ("allcores", true)] {
            g.bench_function(format!("intersect/{kind}/{threads}"), |b| {
                b.iter(|| trace(accel.as_ref(), rays, parallel))
            });
            g.bench_function(format!("occluded/{kind}/{threads}"), |b| {
                b.iter(|| occlude(accel.as_ref(), rays, parallel))
            });
        }
    }
    g.finish();
}

/// The Embree wrapper against raw `rtcIntersect1` on the same rays (one thread): the wrapper's
/// overhead is the ratio of the two.
#[cfg(embree)]
fn bench_embree_raw(c: &mut Criterion, meshes: &[Mesh]) {
    let accel = prism::accel::embree::EmbreeAccel::new(meshes).expect("embree device");
    let sets = [("coherent", coherent_rays()), ("incoherent", incoherent_rays(&accel))];
    let mut g = c.benchmark_group("embree-raw/rays");
    g.sample_size(10);
    g.throughput(Throughput::Elements(RAYS as u64));
    for (kind, rays) in &sets {
        g.bench_function(format!("intersect/{kind}/1thread"), |b| b.iter(|| accel.raw_trace_count(rays)));
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    // Embree asks for flush-to-zero/denormals-are-zero on every thread that traces rays.
    let _ = rayon::ThreadPoolBuilder::new().start_handler(|_| prism::accel::init_render_thread()).build_global();
    prism::accel::init_render_thread();
    let meshes = scene();
    #[cfg(embree)]
    {
        bench_backend(c, "embree", &meshes, &|m| {
            Box::new(prism::accel::embree::EmbreeAccel::new(m).expect("embree device"))
        });
        bench_embree_raw(c, &meshes);
        bench_backend(c, "embree-watertight", &meshes, &|m| {
            Box::new(prism::accel::embree::EmbreeAccel::watertight(m).expect("embree device"))
        });
    }
    bench_backend(c, "obvhs", &meshes, &|m| Box::new(ObvhsAccel::with_quality(m, BuildQuality::Medium)));
    bench_backend(c, "obvhs-fast", &meshes, &|m| Box::new(ObvhsAccel::with_quality(m, BuildQuality::Fast)));
}

criterion_group!(accel_benches, benches);
criterion_main!(accel_benches);
