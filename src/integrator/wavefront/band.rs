//! The wavefront loop over a band of pixels: its pixel samples in batches, each batch advanced
//! bounce by bounce through the stages, then added to the film in the scalar loop's order.

use super::super::{camera_sample, Integrator, Stats};
use super::clock::{Clock, Stage};
use super::diffuse::DiffuseQueue;
use super::other_kinds::OtherQueue;
use super::paths::Paths;
use super::surface::surface;
use crate::camera::Camera;
use crate::film::Pixel;
use crate::filter::Filter;
use crate::geometry::{Hit, Ray};
use crate::light::LightSampleContext;
use crate::sampling::SamplerKind;
use crate::scene::Scene;
use crate::sensor::Sensor;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::TextureFootprint;
use glam::Vec3;
use std::cell::RefCell;
use std::ops::Range;

/// Paths per batch.
const BATCH: usize = 4096;

/// What every band of a pass shares.
pub struct BandJob<'a> {
    pub scene: &'a Scene,
    pub camera: &'a Camera,
    pub integrator: &'a Integrator,
    pub filter: &'a Filter,
    pub sensor: &'a Sensor,
    pub sampler: SamplerKind,
    pub seed: u64,
    /// The render's samples per pixel and image size (pbrt-v4's samplers depend on them).
    pub spp: u64,
    pub resolution: (u32, u32),
    /// The camera-ray differentials, when textures need them.
    pub differentials: Option<&'a TextureFootprint>,
}

/// Samples `range` of every pixel of `pixels`, whose pixel `i` is `pixel_at(i)` of the full
/// image: the wavefront form of the scalar render loop's band.
pub fn render_band(
    job: &BandJob,
    pixel_at: impl Fn(usize) -> (u32, u32),
    range: Range<u64>,
    pixels: &mut [Pixel],
) -> Stats {
    BUFFERS.with_borrow_mut(|b| render_band_with(job, pixel_at, range, pixels, b))
}

/// A thread's queues and batch, kept from band to band (allocating them anew for every band
/// cost more than a tenth of the render in page faults).
#[derive(Default)]
struct Buffers {
    paths: Paths,
    active: Vec<u32>,
    next: Vec<u32>,
    hits: Vec<Option<Hit>>,
    rays: Vec<Ray>,
    shadows: Vec<Ray>,
    shadow_light: Vec<(u32, SampledSpectrum)>,
    blocked: Vec<bool>,
    diffuse: DiffuseQueue,
    samples: Vec<(u32, u64)>,
    /// What the samplers in `paths` were made for: kind, samples per pixel, image size, seed
    /// (a thread may render with others next).
    sampler_kind: Option<(SamplerKind, u64, (u32, u32), u64)>,
}

thread_local! {
    static BUFFERS: RefCell<Buffers> = RefCell::default();
}

fn render_band_with(
    job: &BandJob,
    pixel_at: impl Fn(usize) -> (u32, u32),
    range: Range<u64>,
    pixels: &mut [Pixel],
    b: &mut Buffers,
) -> Stats {
    let mut stats = Stats::default();
    let mut clock = Clock::new();
    let made_for = (job.sampler, job.spp, job.resolution, job.seed);
    if b.sampler_kind != Some(made_for) {
        b.paths.sampler.clear();
        b.sampler_kind = Some(made_for);
    }
    let Buffers { paths, active, next, hits, rays, shadows, shadow_light, blocked, diffuse, samples, .. } = b;
    let mut other = OtherQueue::default();
    samples.clear();
    samples.extend((0..pixels.len() as u32).flat_map(|i| range.clone().map(move |s| (i, s))));
    for batch in samples.chunks(BATCH) {
        // Camera rays.
        paths.clear();
        active.clear();
        for (k, &(i, s)) in batch.iter().enumerate() {
            if paths.sampler.len() <= k {
                paths.sampler.push(job.sampler.make(job.spp, job.resolution, job.seed));
            }
            let wavelengths = SampledWavelengths::sample_visible;
            let c = camera_sample(
                job.scene,
                job.camera,
                job.filter,
                job.differentials,
                &mut paths.sampler[k],
                wavelengths,
                pixel_at(i as usize),
                s,
                job.seed,
            );
            paths.pixel.push((i, s));
            paths.lambdas.push(c.lambdas);
            paths.filter_weight.push(c.filter_weight);
            paths.differentials.push(c.differentials);
            let (ray, weight) = c.ray.map_or((Ray::new(Vec3::ZERO, Vec3::Z), 0.0), |r| (r.ray, r.weight));
            paths.state.push(super::super::state::PathState::new(ray.o));
            paths.ray.push(ray);
            paths.camera_weight.push(weight);
            if c.ray.is_some() {
                active.push(k as u32);
            }
        }
        clock.lap(Stage::Camera);

        while !active.is_empty() {
            rays.clear();
            rays.extend(active.iter().map(|&k| paths.ray[k as usize]));
            hits.clear();
            hits.resize(rays.len(), None);
            job.scene.accel().intersect_batch(rays, hits);
            clock.lap(Stage::Intersect);

            diffuse.clear();
            surface(job.integrator, job.scene, paths, active, hits, diffuse, &mut other, &mut stats);
            clock.lap(Stage::Surface);

            diffuse.shade();
            clock.lap(Stage::Diffuse);

            shadows.clear();
            shadow_light.clear();
            next.clear();
            for (j, &k) in diffuse.path.iter().enumerate() {
                let ku = k as usize;
                let time = paths.ray[ku].time;
                if diffuse.shadow_ok[j] {
                    // pbrt-v4's ShadowEpsilon: stop short of the light itself.
                    shadows
                        .push(Ray::segment(diffuse.shadow_o.get(j), diffuse.shadow_d.get(j), 1.0 - 1e-4).at_time(time));
                    shadow_light.push((k, diffuse.contribution.get(j)));
                }
                if diffuse.next_ok[j] {
                    let state = &mut paths.state[ku];
                    state.beta *= diffuse.factor.get(j);
                    state.prev_pdf = diffuse.pdf[j];
                    state.r_l = state.r_u / state.prev_pdf;
                    state.specular_bounce = false;
                    state.any_non_specular = true;
                    state.prev = LightSampleContext::surface(diffuse.p.get(j), diffuse.n.get(j));
                    paths.ray[ku] = Ray::new(diffuse.next_o.get(j), diffuse.next_d.get(j)).at_time(time);
                    next.push(k);
                }
            }
            clock.lap(Stage::Scatter);

            other.shade(job.integrator, paths, shadows, shadow_light, next);
            clock.lap(Stage::OtherKinds);

            blocked.clear();
            blocked.resize(shadows.len(), false);
            job.scene.accel().occluded_batch(shadows, blocked);
            stats.rays += shadows.len() as u64;
            clock.lap(Stage::Shadow);

            for (&(k, l), &b) in shadow_light.iter().zip(blocked.iter()) {
                if !b {
                    paths.state[k as usize].l += l;
                }
            }
            // The continuing paths in batch order, so that packets hold neighbouring pixels.
            next.sort_unstable();
            active.clear();
            for &k in next.iter() {
                let ku = k as usize;
                let state = &mut paths.state[ku];
                if !state.beta.is_black() && job.integrator.roulette(state, &mut paths.sampler[ku]) {
                    active.push(k);
                }
            }
            clock.lap(Stage::Roulette);
        }

        // Film, in batch order: each pixel's samples in index order.
        for (k, &(i, s)) in paths.pixel.iter().enumerate() {
            let l: SampledSpectrum = paths.state[k].l * paths.camera_weight[k];
            let (x, y) = pixel_at(i as usize);
            stats.samples += 1;
            let xyz = job.sensor.record(&l, &paths.lambdas[k]);
            if !xyz.is_finite() {
                stats.nonfinite += 1;
                if stats.nonfinite_at.len() < 16 {
                    stats.nonfinite_at.push((x, y, s, paths.state[k].depth));
                }
                continue;
            }
            let (px, weight) = (&mut pixels[i as usize], paths.filter_weight[k]);
            px.xyz_sum += xyz.as_dvec3() * weight as f64;
            px.weight_sum += weight as f64;
            px.samples += 1;
        }
        clock.lap(Stage::Film);
    }
    stats.stage_ns = clock.ns;
    stats
}
