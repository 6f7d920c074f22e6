//! How the image error and the speed of tessellated spheres depend on the number of latitude
//! bands (longitude segments are twice as many):
//!
//!     cargo run --release --example sphere_tessellation
//!
//! Five diffuse spheres and an emissive sphere (exact, sampled by its cone) over a ground quad,
//! rendered with the same seed and samples at each resolution, as exact quadrics ("analytic"),
//! and at 384 bands (the reference). Paths that
//! meet slightly different triangles diverge, so the pixel difference carries noise besides the
//! geometry's error; the noise alone is measured between two seeds of the reference. Printed:
//! bands, triangles, samples per second, the image mean relative to the reference's, the RMSE
//! of pixels and of 8×8-pixel block means (noise shrinks 8× there, silhouettes stay), all
//! relative to the reference's mean luminance.
//!
//! Then the cost of the intersection alone: a million rays at one sphere, through the exact
//! test (`Quadric::intersect`), through each backend's analytic quadric and through obvhs's BVH
//! over the sphere's triangles.

use glam::{Mat4, Vec3};
use prism::accel::{self, Accel, AccelKind, ExtraShapes, ObvhsAccel};
use prism::camera::Camera;
use prism::film::Film;
use prism::geometry::shapes::quad;
use prism::geometry::{Mesh, PlacedQuadric, Quadric, Ray};
use prism::material::Material;
use prism::render::{render, RenderSettings, SamplerKind};
use prism::sampling::Rng;
use prism::scene::{Emission, SceneBuilder};
use prism::spectrum::Spectrum;
use std::time::Instant;

const SPHERES: [(f32, f32, f32, f32); 5] = [
    (-1.6, 0.5, 0.0, 0.5),
    (0.0, 0.7, 0.4, 0.7),
    (1.5, 0.4, -0.6, 0.4),
    (0.8, 0.3, 1.6, 0.3),
    (-0.7, 0.25, -1.2, 0.25),
];

/// The scene with spheres of `bands` latitude bands, or exact ones (`None`).
fn scene(bands: Option<u32>, accel: AccelKind) -> prism::scene::Scene {
    let mut b = SceneBuilder::new();
    let grey = b.add_material(Material::diffuse(Spectrum::constant(0.5)));
    let white = b.add_material(Material::diffuse(Spectrum::constant(0.8)));
    b.add_mesh(quad(Vec3::new(-6.0, 0.0, -6.0), Vec3::Z * 12.0, Vec3::X * 12.0), grey, None);
    let sphere = |r: f32| Quadric::Sphere { radius: r, z_min: -r, z_max: r, phi_max: 360.0 };
    for (x, y, z, r) in SPHERES {
        let at = Mat4::from_translation(Vec3::new(x, y, z));
        match bands {
            Some(n) => b.add_mesh(sphere(r).tessellate_n(2 * n, n).transformed(&at), white, None),
            None => b.add_quadric(PlacedQuadric::new(sphere(r), at, false).unwrap(), white, None),
        };
    }
    let (c, r) = (Vec3::new(-1.0, 3.0, 1.0), 0.6);
    let emission = Emission { spectrum: Spectrum::constant(1.0), scale: 4.0, two_sided: false };
    b.add_quadric(PlacedQuadric::new(sphere(r), Mat4::from_translation(c), false).unwrap(), white, Some(emission));
    b.set_camera(Camera::look_at(Vec3::new(0.0, 2.5, -6.0), Vec3::new(0.0, 0.5, 0.0), Vec3::Y), 40.0);
    b.build(accel).expect("scene builds")
}

fn luminance(f: &Film) -> Vec<f64> {
    f.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum.max(1e-12)).collect()
}

fn main() {
    let accel = AccelKind::default_available();
    let settings = RenderSettings {
        resolution: (160, 120),
        spp: 64,
        seed: 3,
        sampler: SamplerKind::Independent,
        ..Default::default()
    };
    let run = |bands: Option<u32>, seed: u64| {
        let s = scene(bands, accel);
        let t = Instant::now();
        let (film, _) = render(&s, &RenderSettings { seed, ..settings.clone() }, |_| {}).expect("film");
        let secs = t.elapsed().as_secs_f64();
        (s.triangle_count(), secs, luminance(&film))
    };
    let (w, h) = (settings.resolution.0 as usize, settings.resolution.1 as usize);
    let blocks = |img: &[f64]| -> Vec<f64> {
        let mut out = Vec::new();
        for by in 0..h / 8 {
            for bx in 0..w / 8 {
                let s: f64 = (0..64).map(|k| img[(by * 8 + k / 8) * w + bx * 8 + k % 8]).sum();
                out.push(s / 64.0);
            }
        }
        out
    };
    let rmse =
        |a: &[f64], b: &[f64]| (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
    let (_, _, reference) = run(Some(384), 3);
    let (_, _, other_seed) = run(Some(384), 4);
    let mean = reference.iter().sum::<f64>() / reference.len() as f64;
    assert!(mean > 0.0, "the reference is black");
    println!("backend {accel:?}, {w}x{h} px, {} spp", settings.spp);
    println!(
        "noise (384 bands, seeds 3 and 4): pixel RMSE {:.5}, block RMSE {:.5}",
        rmse(&reference, &other_seed) / mean,
        rmse(&blocks(&reference), &blocks(&other_seed)) / mean
    );
    println!("bands  triangles  Msamples/s  mean ratio  pixel RMSE  block RMSE");
    for bands in [Some(12), Some(24), Some(48), Some(96), Some(192), None] {
        let (tris, secs, img) = run(bands, 3);
        let bands = bands.map_or("exact".to_string(), |n| n.to_string());
        let samples = (w * h) as f64 * settings.spp as f64;
        let m = img.iter().sum::<f64>() / img.len() as f64;
        println!(
            "{bands:5}  {tris:9}  {:10.3}  {:10.5}  {:10.5}  {:10.5}",
            samples / secs / 1e6,
            m / mean,
            rmse(&img, &reference) / mean,
            rmse(&blocks(&img), &blocks(&reference)) / mean
        );
    }
    intersection_cost();
}

/// Rays per second of the exact sphere test and of obvhs over the tessellation, and how often
/// they disagree on hit or miss (rays through the sliver between mesh and sphere).
fn intersection_cost() {
    let mut rng = Rng::new(5, 5);
    let mut u = || rng.uniform();
    let rays: Vec<Ray> = (0..1_000_000)
        .map(|_| {
            let o = Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize_or_zero() * 10.0;
            let aim = Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5) * 2.4;
            Ray::new(o, (aim - o).normalize())
        })
        .collect();
    println!("one sphere of radius 1, {} rays", rays.len());
    println!("test                       Mrays/s   hits   disagreements");
    let q = Quadric::Sphere { radius: 1.0, z_min: -1.0, z_max: 1.0, phi_max: 360.0 };
    let t = Instant::now();
    let exact: Vec<bool> = rays.iter().map(|r| q.intersect(r.o, r.d, r.t_max).is_some()).collect();
    let secs = t.elapsed().as_secs_f64();
    let hits = exact.iter().filter(|&&h| h).count();
    println!("exact                      {:7.2}  {hits:6}  -", rays.len() as f64 / secs / 1e6);
    let placed = PlacedQuadric::new(q, Mat4::IDENTITY, false).unwrap();
    let mut kinds = vec![AccelKind::Obvhs];
    if AccelKind::default_available() != AccelKind::Obvhs {
        kinds.push(AccelKind::default_available());
    }
    for kind in kinds {
        let extra = ExtraShapes { curves: &[], quadrics: &[(0, &placed)] };
        let a = accel::build_with_extra(kind, &[Mesh::default()], extra).expect("builds");
        let t = Instant::now();
        let hits = rays.iter().filter(|r| a.intersect(r).is_some()).count();
        let secs = t.elapsed().as_secs_f64();
        println!("{:<26} {:7.2}  {hits:6}  -", format!("{} analytic", a.name()), rays.len() as f64 / secs / 1e6);
    }
    for bands in [24, 48, 96] {
        let mesh = q.tessellate_n(2 * bands, bands);
        let tris = mesh.len();
        let accel = ObvhsAccel::new(&[mesh]);
        let t = Instant::now();
        let tess: Vec<bool> = rays.iter().map(|r| accel.intersect(r).is_some()).collect();
        let secs = t.elapsed().as_secs_f64();
        let hits = tess.iter().filter(|&&h| h).count();
        let differ = tess.iter().zip(&exact).filter(|(a, b)| a != b).count();
        println!("obvhs, {bands:3} bands {tris:7} tris {:7.2}  {hits:6}  {differ}", rays.len() as f64 / secs / 1e6);
    }
}
