//! Transmittance of shadow rays through media and interface surfaces by ratio tracking (Novák,
//! Selle & Jarosz 2014, "Residual ratio tracking for estimating attenuation in participating
//! media"; pbrt-v4 §14.2.2): at each tentative collision against the majorant the estimate is
//! multiplied by σ_n/σ_maj instead of ending, with Russian roulette once it is small.

use super::Stats;
use crate::geometry::Ray;
use crate::media::sample_t_maj;
use crate::sampling::rng::hash64;
use crate::sampling::{Rng, Sampler};
use crate::scene::{Scene, MAX_INTERFACE_CROSSINGS};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// A generator seeded from two sampler dimensions (pbrt-v4 seeds its per-ray RNG by hashing
/// them), for the unbounded number of decisions one free flight may need.
pub(super) fn ray_rng(sampler: &mut Sampler) -> Rng {
    let (a, b) = (sampler.get_1d(), sampler.get_1d());
    Rng::new(hash64(&[u64::from(a.to_bits())]), hash64(&[u64::from(b.to_bits())]))
}

/// Distance [scene units] from `ray.o` to a hit at `p` (the ray's direction may not be unit).
#[inline]
pub(super) fn distance(ray: &Ray, p: Vec3) -> f32 {
    (p - ray.o).length()
}

/// Transmittance along a shadow ray starting in `medium`, by ratio tracking through every
/// medium and interface surface on the way (pbrt-v4's loop in `SampleLd`): the estimate T_ray and
/// the rescaled probabilities r_l, r_u of its null collisions. `None` when an opaque surface
/// blocks the ray or Russian roulette ends it.
pub(super) fn transmittance(
    scene: &Scene,
    mut ray: Ray,
    mut medium: Option<u32>,
    w: &SampledWavelengths,
    sampler: &mut Sampler,
    stats: &mut Stats,
) -> Option<(SampledSpectrum, SampledSpectrum, SampledSpectrum)> {
    let one = SampledSpectrum::one();
    let (mut t_ray, mut r_l, mut r_u) = (one, one, one);
    let mut rng = ray_rng(sampler);
    let end = ray.t_max.is_finite().then(|| ray.at(ray.t_max));
    for _ in 0..MAX_INTERFACE_CROSSINGS {
        stats.rays += 1;
        let si = scene.intersect(&ray);
        if si.as_ref().is_some_and(|s| !s.is_passthrough()) {
            return None;
        }
        if let Some(m) = medium.and_then(|i| scene.media().get(i as usize)) {
            let len = ray.d.length();
            let d = ray.d / len;
            let t_end = si.as_ref().map_or(ray.t_max * len, |s| distance(&ray, s.p));
            let uniform = m.uniform_point(w);
            let u = rng.uniform();
            let t_maj = sample_t_maj(m, &uniform, ray.o, d, t_end, u, &mut rng, w, |c, rng| {
                let sigma_n = (c.sigma_maj - c.mp.sigma_a - c.mp.sigma_s).map(|x| x.max(0.0));
                let pdf = c.t_maj[0] * c.sigma_maj[0];
                t_ray *= c.t_maj * sigma_n / pdf;
                r_l *= c.t_maj * c.sigma_maj / pdf;
                r_u *= c.t_maj * sigma_n / pdf;
                // Russian roulette once the MIS-weighted estimate is small.
                let tr = t_ray / (r_l + r_u).average();
                if tr.max_value() < 0.05 {
                    if rng.uniform() < 0.75 {
                        t_ray = SampledSpectrum::zero();
                    } else {
                        t_ray /= 0.25;
                    }
                }
                !t_ray.is_black()
            });
            let t0 = t_maj[0];
            if t0.is_nan() || t0 <= 0.0 {
                return None;
            }
            t_ray *= t_maj / t0;
            r_l *= t_maj / t0;
            r_u *= t_maj / t0;
        }
        if t_ray.is_black() || !t_ray.is_finite() {
            return None;
        }
        let Some(s) = si else { return Some((t_ray, r_l, r_u)) };
        medium = s.medium_interface().medium_toward(ray.d, s.shading.ng, medium);
        ray = match end {
            Some(e) => s.spawn_ray_to_point(e),
            None => s.spawn_ray(ray.d),
        };
    }
    None
}
