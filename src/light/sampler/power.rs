//! Choosing a light in proportion to its emitted power, uniform when all powers are 0 (pbrt-v4's
//! `PowerLightSampler`). The choice inverts the cumulative distribution (O(log n)), which is
//! monotone in `u`: the remainder of `u` within the chosen light's interval is a fresh uniform for
//! sampling a point on the light ("sample reuse", as Mitsuba 3's
//! `DiscreteDistribution::sample_reuse`). (An alias table is O(1) but not monotone, and would
//! scatter the strata.)

use crate::light::selection_flux::{max_value, visible_flux};
use crate::light::{AreaLight, Light};
use crate::sampling::Distribution1D;
use crate::spectrum::Spectrum;
use std::collections::HashMap;
use std::sync::Arc;

/// Each light's emitted flux as the power sampler weighs it ([`Light::power`]), 0 where it is
/// not finite and positive.
pub(super) fn light_powers(lights: &[Light], scene_radius: f32) -> Vec<f32> {
    // An emissive mesh is one light per triangle sharing one spectrum: weigh it once.
    per_light(lights, visible_flux, |a, v| a.power_given(v), |l| l.power(scene_radius))
}

/// Each light's flux as the BVH sampler weighs it ([`Light::bound_flux`]), 0 where it is not
/// finite and positive.
pub(super) fn light_bound_fluxes(lights: &[Light]) -> Vec<f32> {
    per_light(lights, max_value, |a, v| a.bound_flux_given(v), Light::bound_flux)
}

/// `area(light, of_spectrum(spectrum))` for a triangle, `of_spectrum` evaluated once per shared
/// spectrum, and `other(light)` for every other light; non-finite or negative values become 0.
fn per_light(
    lights: &[Light],
    of_spectrum: fn(&Spectrum) -> f32,
    area: impl Fn(&AreaLight, f32) -> f32,
    other: impl Fn(&Light) -> f32,
) -> Vec<f32> {
    let mut cache: HashMap<*const Spectrum, f32> = HashMap::new();
    lights
        .iter()
        .map(|l| match l {
            Light::Area(a) => {
                let v = *cache.entry(Arc::as_ptr(&a.spectrum)).or_insert_with(|| of_spectrum(&a.spectrum));
                area(a, v)
            }
            l => other(l),
        })
        .map(|p| if p.is_finite() { p.max(0.0) } else { 0.0 })
        .collect()
}

/// Power-proportional light selection, independent of the shading point.
#[derive(Clone, Debug)]
pub struct PowerLightSampler {
    table: Option<Distribution1D>,
}

impl PowerLightSampler {
    /// The table over `powers`, one per light.
    pub fn new(powers: &[f32]) -> Self {
        Self { table: (!powers.is_empty()).then(|| Distribution1D::new(powers)) }
    }

    /// Picks a light index for `u` in [0, 1): the index, its probability and `u` remapped to a
    /// fresh uniform in [0, 1).
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32, f32)> {
        self.table.as_ref().map(|t| t.sample_discrete(u))
    }

    /// Probability of picking light `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.table.as_ref().map_or(0.0, |t| t.discrete_pmf(i))
    }
}
