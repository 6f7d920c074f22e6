//! Speed ratios between backends, measured robustly on a shared, noisy machine: the backends
//! take turns on the same 4096-ray chunks (the first backend rotates from chunk to chunk), so
//! load changes hit all of them alike; each pass gives one throughput per backend, and the
//! ratios are reported as the median (and range) over passes.
//!
//! One thread: each chunk is timed by the thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`), which
//! excludes time the thread spent descheduled. (`/proc/thread-self/schedstat`, the
//! earlier timer, lags by up to a scheduler tick, longer than a chunk takes: its per-pass ratios
//! spread over a factor 2–4.) Two threads: the chunk is split over a
//! 2-thread rayon pool and timed by the wall clock.
//!
//! `cargo bench --bench accel_ratio` (release profile). `PRISM_BENCH_PASSES` (default 8),
//! `PRISM_BENCH_SCALE` as in `accel.rs`. With `PRISM_BENCH_RAW=1` every pass's throughput is
//! also printed as a tab-separated line `pass, index, query, threads, backend, M rays/s`, for
//! comparing two builds run in turn (scripts/bench-embree4.sh: Embree 4 against Embree 3).

use std::time::Instant;

use cpu_time::ThreadTime;

use prism::accel::{Accel, AccelKind};
use prism::geometry::{Mesh, Ray};
use rayon::prelude::*;

mod common;
use common::{coherent_rays, incoherent_rays, scene, RAYS};

/// Rays per interleaved chunk.
const CHUNK: usize = 4096;

#[derive(Clone, Copy)]
enum Query {
    Closest,
    /// Shadow rays bounded at t = 50 (as in accel.rs).
    Any,
}

fn run(accel: &dyn Accel, rays: &[Ray], q: Query) -> usize {
    match q {
        Query::Closest => rays.iter().filter(|r| accel.intersect(r).is_some()).count(),
        Query::Any => rays.iter().filter(|r| accel.occluded(&Ray::segment(r.o, r.d, 50.0))).count(),
    }
}

/// One pass: throughput [M rays/s] per backend, and hit counts.
fn pass(
    backends: &[(&str, Box<dyn Accel>)],
    rays: &[Ray],
    q: Query,
    pool: Option<&rayon::ThreadPool>,
) -> Vec<(f64, usize)> {
    let n = backends.len();
    let mut secs = vec![0.0f64; n];
    let mut hits = vec![0usize; n];
    for (c, chunk) in rays.chunks(CHUNK * if pool.is_some() { 2 } else { 1 }).enumerate() {
        for k in 0..n {
            let b = (c + k) % n;
            let accel = backends[b].1.as_ref();
            match pool {
                None => {
                    let t0 = ThreadTime::now();
                    hits[b] += run(accel, chunk, q);
                    secs[b] += t0.elapsed().as_secs_f64();
                }
                Some(pool) => {
                    let t0 = Instant::now();
                    hits[b] += pool.install(|| chunk.par_chunks(256).map(|r| run(accel, r, q)).sum::<usize>());
                    secs[b] += t0.elapsed().as_secs_f64();
                }
            }
        }
    }
    secs.iter().zip(&hits).map(|(&s, &h)| (rays.len() as f64 / s * 1e-6, h)).collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

fn main() {
    if std::env::args().any(|a| a == "--list" || a == "--test") {
        return; // `cargo test --benches` / criterion-style listing: nothing to run here.
    }
    prism::accel::init_render_thread();
    let passes: usize = std::env::var("PRISM_BENCH_PASSES").ok().and_then(|s| s.parse().ok()).unwrap_or(8);
    let meshes = scene();
    let tris: usize = meshes.iter().map(Mesh::len).sum();
    let kinds =
        [AccelKind::Embree, AccelKind::EmbreeWatertight].into_iter().filter(|_| cfg!(embree)).chain([AccelKind::Obvhs]);
    let backends: Vec<(&str, Box<dyn Accel>)> = kinds
        .map(|kind| {
            let t0 = Instant::now();
            let a = prism::accel::build(kind, &meshes).expect("accelerator");
            println!(
                "build {}: {:.2} s ({tris} triangles, {:.1} MB)",
                kind.name(),
                t0.elapsed().as_secs_f64(),
                a.memory_bytes() as f64 / 1e6
            );
            (kind.name(), a)
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .start_handler(|_| prism::accel::init_render_thread())
        .build()
        .expect("rayon pool");
    let incoherent = incoherent_rays(backends[0].1.as_ref());
    let primary = coherent_rays();
    let loads = [
        ("closest hit, incoherent", &incoherent, Query::Closest),
        ("any hit (t ≤ 50), incoherent", &incoherent, Query::Any),
        ("closest hit, primary", &primary, Query::Closest),
    ];
    let names: Vec<&str> = backends.iter().map(|b| b.0).collect();
    let raw = std::env::var_os("PRISM_BENCH_RAW").is_some_and(|v| v == "1");
    println!("\n{RAYS} rays per set, {passes} passes, ratios of throughput (median, range over passes)\n");
    print!("| query | threads |");
    for n in &names {
        print!(" {n} [M rays/s] |");
    }
    // Ratios: each backend ÷ the first (Embree's triangle kernel when built with Embree), and
    // embree-watertight ÷ obvhs.
    let mut ratio_cols: Vec<(usize, usize)> = (1..names.len()).map(|i| (i, 0)).collect();
    if names.len() == 3 {
        ratio_cols.insert(1, (1, 2));
    }
    for &(i, j) in &ratio_cols {
        print!(" {} ÷ {} |", names[i], names[j]);
    }
    println!("\n|---|---|{}", "---|".repeat(names.len() + ratio_cols.len()));
    for (label, rays, q) in loads {
        for threads in [1, 2] {
            let p = (threads == 2).then_some(&pool);
            let runs: Vec<Vec<(f64, usize)>> = (0..passes).map(|_| pass(&backends, rays, q, p)).collect();
            if raw {
                for (k, run) in runs.iter().enumerate() {
                    for (name, (mrays, _)) in names.iter().zip(run) {
                        println!("pass\t{k}\t{label}\t{threads}\t{name}\t{mrays:.4}");
                    }
                }
            }
            let hits: Vec<usize> = runs[0].iter().map(|r| r.1).collect();
            print!("| {label} | {threads} |");
            for b in 0..names.len() {
                print!(" {:.2} |", median(runs.iter().map(|r| r[b].0).collect()));
            }
            for &(i, j) in &ratio_cols {
                let r: Vec<f64> = runs.iter().map(|p| p[i].0 / p[j].0).collect();
                let (lo, hi) = r.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
                print!(" {:.2}× ({lo:.2}–{hi:.2}) |", median(r));
            }
            println!();
            eprintln!("hits per backend: {hits:?}");
        }
    }
}
