//! The free flights of the bidirectional estimators' random walks (pbrt-v4 `RandomWalk`'s medium
//! step, PBR 4th ed. §14.1, with the spectral MIS of Miller, Georgiev & Jarosz 2019): delta
//! tracking along a ray through the medium it is in, up to the next surface, ending in a real
//! scattering (a new path vertex), an absorption, or the surface. The throughput β and the
//! rescaled path probability r_u are updated as the volumetric loop updates them
//! ([`super::collision`]), and a connection's segment carries the transmittance between its
//! ends by ratio tracking ([`segment_transmittance`]) with its own rescaled probability r_l.
//! All distances of a path are drawn at one hero wavelength, so its spectral MIS divides its
//! contribution by the average over the wavelengths of the product of all its parts' rescaled
//! probabilities ([`spectral_mis`]), not by the product of their averages.

use super::collision::{self, Event};
use super::transmittance::{distance, ray_rng, transmittance};
use super::Stats;
use crate::geometry::Ray;
use crate::media::{sample_t_maj, HenyeyGreenstein};
use crate::sampling::Sampler;
use crate::scene::{Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// Where a free flight ends.
pub(super) enum Flight {
    /// Absorbed, or its throughput vanished: the walk ends.
    Absorbed,
    /// A real scattering at `p` with this phase function.
    Scattered(Vec3, HenyeyGreenstein),
    /// No scattering before the surface the ray hits (or, with no surface, the ray escapes).
    Passed,
}

/// A free flight along `ray` (unit direction) in `medium` up to `hit`, the surface it meets
/// (`None`: it escapes), β and r_u updated by the events on the way. Outside any medium it
/// passes unchanged.
#[allow(clippy::too_many_arguments)]
pub(super) fn free_flight(
    scene: &Scene,
    ray: &Ray,
    hit: Option<&SurfaceInteraction>,
    medium: Option<u32>,
    beta: &mut SampledSpectrum,
    r_u: &mut SampledSpectrum,
    w: &SampledWavelengths,
    sampler: &mut Sampler,
) -> Flight {
    let Some(m) = medium.and_then(|i| scene.media().get(i as usize)) else { return Flight::Passed };
    let t_hit = hit.map_or(f32::INFINITY, |s| distance(ray, s.p));
    let uniform = m.uniform_point(w);
    let mut rng = ray_rng(sampler);
    let u = sampler.get_1d();
    // r_l of the volumetric loop's light sampling: no part of a random walk.
    let mut r_l = SampledSpectrum::one();
    let (mut scattered, mut absorbed) = (None, false);
    let t_maj = sample_t_maj(m, &uniform, ray.o, ray.d, t_hit, u, &mut rng, w, |c, rng| {
        match Event::choose(&c, rng.uniform()) {
            Event::Absorb => {
                absorbed = true;
                false
            }
            Event::Scatter => {
                collision::scatter(&c, beta, r_u);
                scattered = Some((c.p, HenyeyGreenstein::new(c.mp.g)));
                false
            }
            Event::Null => collision::null(&c, beta, r_u, &mut r_l),
        }
    });
    if absorbed || beta.is_black() || r_u.is_black() || !beta.is_finite() {
        return Flight::Absorbed;
    }
    if let Some((p, phase)) = scattered {
        return Flight::Scattered(p, phase);
    }
    // No collision before the surface: β, r_u ·= T_maj / T_maj,hero.
    let t0 = t_maj[0];
    if t0.is_nan() || t0 <= 0.0 {
        return Flight::Absorbed;
    }
    *beta *= t_maj / t0;
    *r_u *= t_maj / t0;
    Flight::Passed
}

/// Transmittance of the segment `ray` (a shadow ray, which may be unbounded) that starts in
/// `medium`, by ratio tracking through the media and interface surfaces on the way (pbrt-v4
/// `Integrator::Tr`): the estimate T_ray at the hero wavelength's distances and their rescaled
/// probability r_l, T = T_ray / avg r_l alone. `None` when a surface blocks it. Without
/// media, the visibility alone.
pub(super) fn segment_transmittance(
    scene: &Scene,
    ray: Ray,
    medium: Option<u32>,
    w: &SampledWavelengths,
    sampler: &mut Sampler,
    stats: &mut Stats,
) -> Option<(SampledSpectrum, SampledSpectrum)> {
    if !scene.has_media() {
        stats.rays += 1;
        return (!scene.occluded(&ray)).then_some((SampledSpectrum::one(), SampledSpectrum::one()));
    }
    transmittance(scene, ray, medium, w, sampler, stats).map(|(t_ray, r_l, _)| (t_ray, r_l))
}

/// The spectral MIS estimate of a path's contribution `f` (at the hero wavelength's
/// distances) whose parts' rescaled probabilities multiply to `r`: f / avg r (Miller,
/// Georgiev & Jarosz 2019, eq. 9 with the balance heuristic); zero where r vanishes.
#[inline]
pub(super) fn spectral_mis(f: SampledSpectrum, r: SampledSpectrum) -> SampledSpectrum {
    let avg = r.average();
    if avg > 0.0 {
        f / avg
    } else {
        SampledSpectrum::zero()
    }
}
