//! The ray-benchmark scene and ray sets, shared by `accel.rs` (criterion), `accel_ratio.rs`
//! (interleaved backend ratios) and `obvhs_huge_pages.rs`. `PRISM_BENCH_SCALE` (default 1.0)
//! scales the triangle count.

// Each bench uses a subset of these helpers.
#![allow(dead_code)]

use prism::accel::Accel;
use prism::geometry::shapes::{icosphere, terrain};
use prism::geometry::{Mesh, Ray};
use prism::math::Vec3;
use prism::sampling::Rng;

/// Rays per batch in the ray benchmarks.
pub const RAYS: usize = 1 << 18;

/// Terrain (~70%) plus a finely tessellated sphere (~30%): ~1M triangles at scale 1.
pub fn scene() -> Vec<Mesh> {
    let scale: f32 = std::env::var("PRISM_BENCH_SCALE").ok().and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let res = ((350_000.0 * scale).sqrt() as u32).max(4);
    let subdiv = ((327_680.0 * scale / 20.0).log(4.0).round() as u32).clamp(1, 7);
    vec![terrain(100.0, res, 4.0, 1), icosphere(Vec3::new(0.0, 12.0, 0.0), 8.0, subdiv)]
}

/// A 512×512 pinhole camera looking down at the scene.
pub fn coherent_rays() -> Vec<Ray> {
    let eye = Vec3::new(0.0, 40.0, 80.0);
    let forward = (Vec3::new(0.0, 5.0, 0.0) - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let n = (RAYS as f32).sqrt() as usize;
    (0..n * n)
        .map(|k| {
            let x = ((k % n) as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            let y = ((k / n) as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            Ray::new(eye, (forward + 0.7 * x * right + 0.7 * y * up).normalize())
        })
        .collect()
}

/// Random origins in the scene's bounds with uniformly random directions (like diffuse bounces).
pub fn incoherent_rays(accel: &dyn Accel) -> Vec<Ray> {
    let b = accel.bounds();
    let mut rng = Rng::new(2024, 0);
    (0..RAYS)
        .map(|_| {
            let o = b.min + (b.max - b.min) * Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            let z = 1.0 - 2.0 * rng.uniform();
            let phi = std::f32::consts::TAU * rng.uniform();
            let r = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(o, Vec3::new(r * phi.cos(), r * phi.sin(), z))
        })
        .collect()
}
