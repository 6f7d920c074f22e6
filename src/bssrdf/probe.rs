//! The separable tabulated BSSRDF at an exit point p_o, and importance sampling of the entry
//! point p_i by probe rays (pbrt-v4 `TabulatedBSSRDF`; King, Kulla, Conty & Fajardo 2013,
//! "BSSRDF Importance Sampling").
//!
//! A probe axis is chosen among the shading frame's normal (probability ½) and its two tangents
//! (¼ each), a wavelength among the path's four (¼ each: the profile radius differs per
//! wavelength, so sampling is spectral), and a radius from that wavelength's profile. The probe
//! is the chord of the sphere of radius r_max (the 99.9 % quantile of that profile) through the
//! sampled point, parallel to the axis. The density of a found p_i with normal n_i is the
//! one-sample MIS combination over the 3 axes × 4 wavelengths:
//! pdf(p_i) = Σ_axis Σ_λ P(axis) P(λ) p_λ(r_axis) / (2π r_axis) |n_i · axis|, counting a
//! strategy only where its sphere contains p_i.

use super::BssrdfTable;
use crate::math::{Frame, Vec2, Vec3, PI};
use crate::spectrum::SampledSpectrum;

/// The profile quantile that bounds the probe sphere.
const R_MAX_QUANTILE: f32 = 0.999;
/// Probabilities of probing along the frame's s, t and n axes.
const AXIS_PROB: [f32; 3] = [0.25, 0.25, 0.5];

/// A probe segment: find every surface of the same object between `p0` and `p1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeSegment {
    /// Start.
    pub p0: Vec3,
    /// End.
    pub p1: Vec3,
}

/// S_p and its sampling at an exit point for the path's four wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct TabulatedBssrdf<'a> {
    table: &'a BssrdfTable,
    po: Vec3,
    frame: Frame,
    /// Extinction σ_t per wavelength [1/scene unit].
    sigma_t: SampledSpectrum,
    /// Single-scattering albedo per wavelength.
    rho: SampledSpectrum,
    /// Probe-sphere radius per wavelength [scene units] (0: that wavelength cannot sample).
    r_max: [f32; 4],
}

impl<'a> TabulatedBssrdf<'a> {
    /// At `po` with shading `frame`, for a medium of extinction `sigma_t` and albedo `rho`.
    pub fn new(table: &'a BssrdfTable, po: Vec3, frame: Frame, sigma_t: SampledSpectrum, rho: SampledSpectrum) -> Self {
        let mut r_max = [0.0f32; 4];
        for c in 0..4 {
            if sigma_t[c] > 0.0 && sigma_t[c].is_finite() {
                r_max[c] = table.sample_radius(rho[c], R_MAX_QUANTILE).map_or(0.0, |r| r / sigma_t[c]);
            }
        }
        Self { table, po, frame, sigma_t, rho, r_max }
    }

    /// S_p(r) = σ_t² P(ρ, r σ_t) / (2π r σ_t) per wavelength [1/area]: the radial profile's
    /// density of diffuse reflectance per unit area at distance r.
    pub fn sr(&self, r: f32) -> SampledSpectrum {
        let mut s = SampledSpectrum::zero();
        for c in 0..4 {
            let st = self.sigma_t[c];
            let ro = r * st;
            if st > 0.0 && ro > 0.0 && ro.is_finite() {
                s[c] = st * st * self.table.profile(self.rho[c], ro) / (2.0 * PI * ro);
            }
        }
        s
    }

    /// S_p(p_i) = S_r(|p_i − p_o|).
    pub fn sp(&self, pi: Vec3) -> SampledSpectrum {
        self.sr((pi - self.po).length())
    }

    /// Samples a probe segment: `u1` picks the axis and the wavelength, `u2` radius and angle.
    pub fn sample(&self, u1: f32, u2: Vec2) -> Option<ProbeSegment> {
        let (axis, u1) = if u1 < 0.25 {
            (0, u1 / 0.25)
        } else if u1 < 0.5 {
            (1, (u1 - 0.25) / 0.25)
        } else {
            (2, (u1 - 0.5) / 0.5)
        };
        let c = ((u1 * 4.0) as usize).min(3);
        let r_max = self.r_max[c];
        if r_max.is_nan() || r_max <= 0.0 {
            return None;
        }
        let r = self.table.sample_radius(self.rho[c], u2.x)? / self.sigma_t[c];
        if r.is_nan() || r >= r_max {
            return None;
        }
        let (a, b, z) = self.axes(axis);
        let phi = 2.0 * PI * u2.y;
        let half = (r_max * r_max - r * r).sqrt();
        let center = self.po + (a * phi.cos() + b * phi.sin()) * r;
        Some(ProbeSegment { p0: center - z * half, p1: center + z * half })
    }

    /// Area density [1/area] of finding `pi` (surface normal `ni`) with [`Self::sample`],
    /// before the choice among the hits on the probe.
    pub fn pdf_sp(&self, pi: Vec3, ni: Vec3) -> f32 {
        let d = self.frame.to_local(pi - self.po);
        let n = self.frame.to_local(ni);
        let dist2 = d.length_squared();
        let r_proj = [(d.y * d.y + d.z * d.z).sqrt(), (d.z * d.z + d.x * d.x).sqrt(), (d.x * d.x + d.y * d.y).sqrt()];
        let mut pdf = 0.0;
        for c in 0..4 {
            let st = self.sigma_t[c];
            if self.r_max[c].is_nan() || self.r_max[c] <= 0.0 || dist2 >= self.r_max[c] * self.r_max[c] {
                continue;
            }
            for axis in 0..3 {
                let ro = r_proj[axis] * st;
                if ro > 0.0 {
                    let planar = st * st * self.table.radius_pdf(self.rho[c], ro) / (2.0 * PI * ro);
                    pdf += 0.25 * AXIS_PROB[axis] * planar * n[axis].abs();
                }
            }
        }
        pdf
    }

    /// (tangent a, tangent b, probe direction) for axis 0 = s, 1 = t, 2 = n.
    fn axes(&self, axis: usize) -> (Vec3, Vec3, Vec3) {
        let f = &self.frame;
        match axis {
            0 => (f.t, f.n, f.s),
            1 => (f.n, f.s, f.t),
            _ => (f.s, f.t, f.n),
        }
    }
}
