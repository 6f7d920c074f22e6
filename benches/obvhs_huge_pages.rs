//! obvhs ÷ Embree ray throughput measured side by side, for machines too busy for absolute
//! timings: the backends take turns on 4096-ray chunks of the same incoherent rays (one thread),
//! and each chunk is timed by this thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`, exact to the
//! nanosecond, unlike `/proc/thread-self/schedstat`, which lags by up to a scheduler tick), so
//! time spent in other processes is not counted. One pass traces every ray once per backend;
//! the ratio of a pass is Embree's CPU time over the other backend's (> 1: faster than Embree).
//!
//! Backends: Embree (feature `embree`), obvhs (arrays in huge-page-advised memory) and
//! "obvhs-heap", the same BVH with its arrays in ordinary heap memory.
//!
//! `cargo bench --bench obvhs_huge_pages` (release profile). Environment: `PRISM_RATIO_PASSES`
//! (default 8), `PRISM_BENCH_SCALE` (as for `accel.rs`).

use std::time::Instant;

use cpu_time::ThreadTime;
use prism::accel::{Accel, ObvhsAccel};
use prism::geometry::Ray;

mod common;
use common::{incoherent_rays, scene};

/// Rays per turn.
const CHUNK: usize = 4096;
/// Any-hit rays are segments of this length (as in `accel.rs`).
const SHADOW_T: f32 = 50.0;

/// AnonHugePages of the whole process in MiB (`/proc/self/smaps_rollup`), NaN if unreadable.
fn process_huge_mib() -> f64 {
    let text = std::fs::read_to_string("/proc/self/smaps_rollup").unwrap_or_default();
    let line = text.lines().find_map(|l| l.strip_prefix("AnonHugePages:"));
    line.and_then(|l| l.trim().trim_end_matches("kB").trim().parse::<f64>().ok()).map_or(f64::NAN, |kb| kb / 1024.0)
}

/// Closest-hit or any-hit work over one chunk; returns a count so nothing is optimised away.
fn run(accel: &dyn Accel, rays: &[Ray], any_hit: bool) -> usize {
    if any_hit {
        rays.iter().filter(|r| accel.occluded(&Ray::segment(r.o, r.d, SHADOW_T))).count()
    } else {
        rays.iter().filter(|r| accel.intersect(r).is_some()).count()
    }
}

/// One pass: per backend, the CPU seconds over all chunks (the starting backend rotates per chunk).
fn pass(backends: &[(&str, &dyn Accel)], rays: &[Ray], any_hit: bool, counts: &mut [usize]) -> Vec<f64> {
    let mut cpu = vec![0u64; backends.len()];
    for (c, chunk) in rays.chunks(CHUNK).enumerate() {
        for k in 0..backends.len() {
            let b = (c + k) % backends.len();
            let start = ThreadTime::now();
            counts[b] += run(backends[b].1, chunk, any_hit);
            cpu[b] += start.elapsed().as_nanos() as u64;
        }
    }
    cpu.iter().map(|&ns| ns as f64 * 1e-9).collect()
}

/// Median and range of `xs`.
fn summary(mut xs: Vec<f64>) -> String {
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    let median = if n % 2 == 1 { xs[n / 2] } else { 0.5 * (xs[n / 2 - 1] + xs[n / 2]) };
    format!("median {median:.3}×  range {:.3}–{:.3}  ({n} passes)", xs[0], xs[n - 1])
}

fn main() {
    prism::accel::init_render_thread();
    let passes: usize = std::env::var("PRISM_RATIO_PASSES").ok().and_then(|s| s.parse().ok()).unwrap_or(8);
    let meshes = scene();
    let triangles: usize = meshes.iter().map(|m| m.len()).sum();
    #[cfg(embree)]
    let embree = prism::accel::embree::EmbreeAccel::new(&meshes).expect("embree device");
    let t0 = Instant::now();
    let obvhs = ObvhsAccel::new(&meshes);
    let build = t0.elapsed().as_secs_f64();
    let heap = ObvhsAccel::new(&meshes).without_huge_pages();
    let views: Vec<(&str, &dyn Accel)> = vec![
        #[cfg(embree)]
        ("embree", &embree),
        ("obvhs", &obvhs),
        ("obvhs-heap", &heap),
    ];
    let rays = incoherent_rays(&obvhs);
    println!("{triangles} triangles, {} incoherent rays, {passes} passes, obvhs build {build:.2} s", rays.len());
    let huge_mb = |a: &ObvhsAccel| a.huge_page_bytes().map_or(f64::NAN, |b| b as f64 / (1 << 20) as f64);
    println!(
        "obvhs arrays {:.1} MiB, of which in huge pages (AnonHugePages): {:.1} MiB; obvhs-heap: {:.1} MiB",
        obvhs.memory_bytes() as f64 / (1 << 20) as f64,
        huge_mb(&obvhs),
        huge_mb(&heap)
    );
    println!("whole process (Embree included) in huge pages: {:.1} MiB", process_huge_mib());

    for any_hit in [false, true] {
        let label = if any_hit { "any hit (t ≤ 50)" } else { "closest hit" };
        let mut counts = vec![0; views.len()];
        let mut cpu: Vec<Vec<f64>> = vec![Vec::new(); views.len()];
        for _ in 0..passes {
            for (b, s) in pass(&views, &rays, any_hit, &mut counts).into_iter().enumerate() {
                cpu[b].push(s);
            }
        }
        assert!(counts.windows(2).all(|w| w[0] == w[1]), "backends disagree on hit counts: {counts:?}");
        for (b, (name, _)) in views.iter().enumerate() {
            let mrays: Vec<f64> = cpu[b].iter().map(|s| rays.len() as f64 / s * 1e-6).collect();
            println!("{label:17} {name:11} M rays/s (CPU time): {}", summary(mrays).replace('×', ""));
        }
        for (num, den) in [(1, 0), (2, 0), (1, 2)].into_iter().filter(|&(a, b)| a.max(b) < views.len()) {
            let ratios: Vec<f64> = cpu[den].iter().zip(&cpu[num]).map(|(d, n)| d / n).collect();
            println!("{label:17} {} ÷ {}: {}", views[num].0, views[den].0, summary(ratios));
        }
    }
    println!("after the passes, obvhs in huge pages: {:.1} MiB", huge_mb(&obvhs));
}
