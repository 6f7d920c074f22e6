//! Free-flight sampling against a majorant (pbrt-v4 `SampleT_maj`, §11.4.3–11.4.6): tentative
//! collisions drawn from the exponential distribution of σ_maj along a ray, over the
//! piecewise-constant segments of [`super::majorant`].

use super::coefficients::MediumPoint;
use super::majorant::MajorantSegments;
use super::Medium;
use crate::sampling::Rng;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec3, Vec4};
use std::sync::atomic::{AtomicU64, Ordering};

/// Most tentative collisions one call of [`sample_t_maj`] takes before giving the walk up as
/// absorbed. A walk takes σ_maj·length collisions on average, so only a majorant far beyond any
/// medium a scene can load (or one whose steps vanish against the distance in `f32`) reaches
/// it; the walks cut off are counted ([`take_cut_off_walks`]) so that the bias is reported.
pub const MAX_COLLISIONS: u32 = 1 << 20;

/// Walks cut off at [`MAX_COLLISIONS`] since the last [`take_cut_off_walks`].
static CUT_OFF_WALKS: AtomicU64 = AtomicU64::new(0);

/// The number of free-flight walks cut off at [`MAX_COLLISIONS`] since the last call, and
/// resets it.
pub fn take_cut_off_walks() -> u64 {
    CUT_OFF_WALKS.swap(0, Ordering::Relaxed)
}

/// What a collision callback of [`sample_t_maj`] is given: the point, the medium's coefficients
/// there, the majorant and the majorant transmittance T_maj since the previous collision.
pub struct Collision {
    /// World-space point.
    pub p: Vec3,
    /// Coefficients at `p`.
    pub mp: MediumPoint,
    /// σ_maj at `p`.
    pub sigma_maj: SampledSpectrum,
    /// exp(−∫σ_maj) from the previous collision (or the ray origin) to `p`.
    pub t_maj: SampledSpectrum,
}

/// Samples tentative collisions along `o + t d` (`d` unit) for t in [0, t_max] from the
/// majorant's exponential distribution at the hero wavelength (pbrt-v4 `SampleT_maj`): each is
/// handed to `collide` with the generator, which returns false to stop. Returns the majorant
/// transmittance from the last collision to `t_max`, or 1 when `collide` stopped the walk. `u` is
/// the first distance's uniform, `rng` supplies the rest.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn sample_t_maj(
    medium: &Medium,
    uniform: &MediumPoint,
    o: Vec3,
    d: Vec3,
    t_max: f32,
    u: f32,
    rng: &mut Rng,
    w: &SampledWavelengths,
    collide: impl FnMut(Collision, &mut Rng) -> bool,
) -> SampledSpectrum {
    let segments = medium.majorant_segments(o, d, t_max, uniform, w);
    sample_collisions(segments, |p| medium.point_at(p, uniform, w), o, d, u, rng, collide)
}

/// [`sample_t_maj`] in a homogeneous medium of coefficients `medium` along t in [0, t_max]:
/// σ_maj = σ_t, so every tentative collision is a real one.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn sample_t_maj_homogeneous(
    medium: &MediumPoint,
    o: Vec3,
    d: Vec3,
    t_max: f32,
    u: f32,
    rng: &mut Rng,
    collide: impl FnMut(Collision, &mut Rng) -> bool,
) -> SampledSpectrum {
    let segments = MajorantSegments::single(0.0, t_max, medium.sigma_a + medium.sigma_s);
    sample_collisions(segments, |_| *medium, o, d, u, rng, collide)
}

/// The delta-tracking loop of [`sample_t_maj`] over the majorant `segments`, with the
/// coefficients at a point given by `point_at`.
#[inline(always)]
fn sample_collisions(
    segments: MajorantSegments<'_>,
    point_at: impl Fn(Vec3) -> MediumPoint,
    o: Vec3,
    d: Vec3,
    mut u: f32,
    rng: &mut Rng,
    mut collide: impl FnMut(Collision, &mut Rng) -> bool,
) -> SampledSpectrum {
    let mut t_maj = SampledSpectrum::one();
    let mut collisions = 0u32;
    for seg in segments {
        let s0 = seg.sigma_maj[0];
        if s0 == 0.0 {
            t_maj *= beer_lambert(seg.sigma_maj, finite_length(seg.t_max - seg.t_min));
            continue;
        }
        let mut t_min = seg.t_min;
        loop {
            let t = t_min - (1.0 - u).ln() / s0;
            u = rng.uniform();
            if t < seg.t_max {
                collisions += 1;
                if collisions > MAX_COLLISIONS {
                    CUT_OFF_WALKS.fetch_add(1, Ordering::Relaxed);
                    return SampledSpectrum::zero();
                }
                t_maj *= beer_lambert(seg.sigma_maj, t - t_min);
                let p = o + d * t;
                let mp = point_at(p);
                if !collide(Collision { p, mp, sigma_maj: seg.sigma_maj, t_maj }, rng) {
                    return SampledSpectrum::one();
                }
                t_maj = SampledSpectrum::one();
                t_min = t;
            } else {
                t_maj *= beer_lambert(seg.sigma_maj, finite_length(seg.t_max - t_min));
                break;
            }
        }
    }
    t_maj
}

/// exp(−σ d) at the four wavelengths: one exponential when σ is the same at all four, as a
/// grid's majorant is.
#[inline]
fn beer_lambert(sigma: SampledSpectrum, d: f32) -> SampledSpectrum {
    if sigma.0 == Vec4::splat(sigma[0]) {
        SampledSpectrum::splat((sigma[0] * -d).exp())
    } else {
        (sigma * -d).exp()
    }
}

/// An infinite length is taken as the largest float, so that exp(−σ·len) is 0 for σ > 0 and 1
/// (not NaN) for σ = 0.
#[inline]
fn finite_length(dt: f32) -> f32 {
    if dt.is_finite() {
        dt
    } else {
        f32::MAX
    }
}

/// The χ² p-value of `n` first tentative collisions of [`sample_t_maj`] along `o + t d`
/// against their CDF `cdf` (which reaches 1 − `escape` at `t_max`), in `bins` bins of equal
/// probability plus one for no collision.
#[cfg(test)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn first_collision_p_value(
    medium: &Medium,
    (o, d, t_max): (Vec3, Vec3, f32),
    cdf: impl Fn(f32) -> f64,
    escape: f64,
    bins: usize,
    n: usize,
    seed: u64,
) -> f64 {
    let w = SampledWavelengths::sample_uniform(0.37);
    let uniform = medium.uniform_point(&w);
    let mut counts = vec![0f64; bins + 1];
    let mut rng = Rng::new(seed, 0);
    for _ in 0..n {
        let mut first = None;
        let u = rng.uniform();
        sample_t_maj(medium, &uniform, o, d, t_max, u, &mut rng, &w, |c, _| {
            first = Some((c.p - o).dot(d));
            false
        });
        match first {
            Some(t) => counts[((cdf(t) / (1.0 - escape) * bins as f64) as usize).min(bins - 1)] += 1.0,
            None => counts[bins] += 1.0,
        }
    }
    let expect = |b: usize| if b < bins { (1.0 - escape) / bins as f64 } else { escape } * n as f64;
    let chi2: f64 = counts.iter().enumerate().map(|(b, o)| (o - expect(b)).powi(2) / expect(b)).sum();
    crate::sampling::chi2::chi2_survival(chi2, bins as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_walk_that_cannot_advance_stops_at_the_collision_bound_and_is_counted() {
        // σ of 1e30 (or ∞) makes every step vanish against t ≈ 1 in f32, and null collisions
        // never end the walk: without the bound it never returns.
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut results = Vec::new();
            for sigma in [1e30, f32::INFINITY, 3.4e38] {
                let mp = MediumPoint {
                    sigma_a: SampledSpectrum::splat(0.0),
                    sigma_s: SampledSpectrum::splat(sigma),
                    le: SampledSpectrum::zero(),
                    g: 0.0,
                };
                let mut rng = Rng::new(7, 0);
                let (o, d) = (Vec3::new(1.0, 0.0, 0.0), Vec3::X);
                let mut calls = 0u64;
                let tr = sample_t_maj_homogeneous(&mp, o, d, 1.0, 0.5, &mut rng, |_, _| {
                    calls += 1;
                    true
                });
                results.push((tr, calls));
            }
            tx.send(results).unwrap();
        });
        let results = rx.recv_timeout(std::time::Duration::from_secs(60)).expect("the walks never ended");
        for (tr, calls) in results {
            assert_eq!(tr, SampledSpectrum::zero());
            assert_eq!(calls, u64::from(MAX_COLLISIONS));
        }
        // Other tests' walks never reach the bound, so these three are all the count holds.
        assert_eq!(take_cut_off_walks(), 3);
    }
}
