//! What happens at a tentative collision of delta tracking, for every free flight prism samples
//! (a scene's media in the volumetric loop, a subsurface material's interior in the random
//! walk): absorption, real scattering or a null collision, chosen with probabilities σ_a/σ_maj,
//! σ_s/σ_maj and σ_n/σ_maj at the hero wavelength, and the throughput β and the rescaled path
//! probabilities r_u, r_l of spectral MIS weighted for the other wavelengths (Miller, Georgiev &
//! Jarosz 2019; pbrt-v4 `VolPathIntegrator::Li`, Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., §14.2.3).

use crate::media::Collision;
use crate::spectrum::SampledSpectrum;

/// The event at a tentative collision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Event {
    /// The path is absorbed (it may have gathered the medium's emission before).
    Absorb,
    /// A real scattering: the phase function continues the path.
    Scatter,
    /// A null collision: the path goes on along the same ray.
    Null,
}

impl Event {
    /// The event at `c` chosen by the uniform `u`.
    #[inline(always)]
    pub fn choose(c: &Collision, u: f32) -> Self {
        let s0 = c.sigma_maj[0];
        let (p_absorb, p_scatter) = (c.mp.sigma_a[0] / s0, c.mp.sigma_s[0] / s0);
        if u < p_absorb {
            Event::Absorb
        } else if u < p_absorb + p_scatter {
            Event::Scatter
        } else {
            Event::Null
        }
    }
}

/// β and r_u after a real scattering at `c`: both ·= T_maj σ_s / (T_maj σ_s)_hero.
#[inline(always)]
pub(super) fn scatter(c: &Collision, beta: &mut SampledSpectrum, r_u: &mut SampledSpectrum) {
    let pdf = c.t_maj[0] * c.mp.sigma_s[0];
    *beta *= c.t_maj * c.mp.sigma_s / pdf;
    *r_u *= c.t_maj * c.mp.sigma_s / pdf;
}

/// β, r_u and r_l after a null collision at `c`: β, r_u ·= T_maj σ_n / (T_maj σ_n)_hero and
/// r_l ·= T_maj σ_maj / (T_maj σ_n)_hero. False when the path can no longer contribute.
#[inline(always)]
pub(super) fn null(
    c: &Collision,
    beta: &mut SampledSpectrum,
    r_u: &mut SampledSpectrum,
    r_l: &mut SampledSpectrum,
) -> bool {
    let sigma_n = (c.sigma_maj - c.mp.sigma_a - c.mp.sigma_s).map(|x| x.max(0.0));
    let pdf = c.t_maj[0] * sigma_n[0];
    if pdf <= 0.0 {
        *beta = SampledSpectrum::zero();
    } else {
        *beta *= c.t_maj * sigma_n / pdf;
        *r_u *= c.t_maj * sigma_n / pdf;
        *r_l *= c.t_maj * c.sigma_maj / pdf;
    }
    !beta.is_black() && !r_u.is_black()
}
