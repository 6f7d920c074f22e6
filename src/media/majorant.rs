//! Majorants and free-flight sampling against them (pbrt-v4 §11.4.3–11.4.6).
//!
//! Delta tracking (Woodcock et al. 1965; Novák et al. 2014, "Residual ratio tracking for
//! estimating attenuation in participating media") samples tentative collisions from the
//! exponential distribution of a majorant σ_maj ≥ σ_t; at each, the integrator decides between
//! absorption, real scattering and a null collision with σ_n = σ_maj − σ_t. A coarse grid of
//! maxima ([`MajorantGrid`]) walked by a 3D DDA (Amanatides & Woo 1987) keeps σ_maj close to σ_t
//! in heterogeneous media, so few collisions are null.
//!
//! A grid may hold one maximum per cell and wavelength band ([`BANDS`]), for media whose colour
//! varies in space (RGB grids): a path's majorant is then the largest of its four wavelengths'
//! bands, so a blue voxel does not raise the majorant of a path with no blue wavelength to its
//! blue peak. The majorant stays the same at the four wavelengths: one that differs per
//! wavelength is allowed by the hero-wavelength estimators (Miller, Georgiev & Jarosz 2019), but
//! on an RGB grid it raised the colour noise more than it saved in collisions.

use super::medium::{Medium, MediumPoint};
use crate::sampling::Rng;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};
use glam::{UVec3, Vec3, Vec4};

/// Wavelength bands of a spectral majorant grid: [360, 830] nm in equal parts.
pub const BANDS: usize = 8;

/// The index of the band that holds `lambda` [nm] (clamped to the visible range).
#[inline]
pub fn band_of(lambda: f32) -> usize {
    let x = (lambda - LAMBDA_MIN) * (BANDS as f32 / (LAMBDA_MAX - LAMBDA_MIN));
    (x.max(0.0) as usize).min(BANDS - 1)
}

/// The wavelengths [nm] of band `b`, as a closed interval.
pub fn band_range(b: usize) -> (f64, f64) {
    let width = f64::from(LAMBDA_MAX - LAMBDA_MIN) / BANDS as f64;
    (f64::from(LAMBDA_MIN) + width * b as f64, f64::from(LAMBDA_MIN) + width * (b + 1) as f64)
}

/// A stretch of ray [t_min, t_max] over which the majorant is σ_maj.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MajorantSegment {
    /// Start [scene units along the unit direction].
    pub t_min: f32,
    /// End.
    pub t_max: f32,
    /// The majorant on the segment [1/scene unit].
    pub sigma_maj: SampledSpectrum,
}

/// Maximum density over the cells of a regular grid on the unit cube (pbrt-v4 `MajorantGrid`),
/// one per cell or one per cell and wavelength band.
#[derive(Clone, Debug)]
pub struct MajorantGrid {
    /// Cells per axis.
    pub res: UVec3,
    /// Values per cell: 1 (the same at every wavelength) or [`BANDS`].
    pub bands: usize,
    /// Maxima, x fastest, each cell's bands together.
    pub max: Vec<f32>,
}

impl MajorantGrid {
    /// One maximum per cell, x fastest.
    pub fn scalar(res: UVec3, max: Vec<f32>) -> Self {
        Self { res, bands: 1, max }
    }

    /// The index of cell `c`'s first value.
    #[inline]
    fn first(&self, c: UVec3) -> usize {
        ((c.z * self.res.y + c.y) * self.res.x + c.x) as usize * self.bands
    }

    /// The maximum in cell `c` (its first band's).
    #[inline]
    pub fn at(&self, c: UVec3) -> f32 {
        self.max[self.first(c)]
    }
}

/// The segments of one ray: one for a homogeneous medium, or the cells of a majorant grid
/// crossed by a DDA.
#[derive(Clone, Debug)]
pub enum MajorantSegments<'g> {
    /// At most one segment left.
    Single(Option<MajorantSegment>),
    /// Cells of a majorant grid.
    Dda(Dda<'g>),
}

impl MajorantSegments<'_> {
    /// One segment with a constant majorant (none when it is empty).
    pub fn single(t_min: f32, t_max: f32, sigma_maj: SampledSpectrum) -> Self {
        Self::Single((t_max > t_min).then_some(MajorantSegment { t_min, t_max, sigma_maj }))
    }

    /// No segment: the ray misses the medium's bounds.
    pub fn none() -> Self {
        Self::Single(None)
    }
}

impl Iterator for MajorantSegments<'_> {
    type Item = MajorantSegment;

    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            Self::Single(s) => s.take(),
            Self::Dda(d) => d.next(),
        }
    }
}

/// A 3D DDA over a [`MajorantGrid`] in its unit-cube space (pbrt-v4 `DDAMajorantIterator`).
#[derive(Clone, Debug)]
pub struct Dda<'g> {
    grid: &'g MajorantGrid,
    /// σ_t per unit density.
    sigma_t: SampledSpectrum,
    /// The bands of the path's wavelengths (all 0 for a grid of one value per cell).
    band: [usize; 4],
    t_min: f32,
    t_max: f32,
    next_crossing: [f32; 3],
    delta: [f32; 3],
    step: [i32; 3],
    limit: [i32; 3],
    voxel: [i32; 3],
}

impl<'g> Dda<'g> {
    /// The walk along `o + t d` (grid space: the unit cube is the grid) over [t_min, t_max],
    /// already clipped to the cube. A grid with bands needs [`Dda::at_wavelengths`] too.
    pub fn new(grid: &'g MajorantGrid, o: Vec3, d: Vec3, t_min: f32, t_max: f32, sigma_t: SampledSpectrum) -> Self {
        let band = [0; 4];
        let p = o + d * t_min;
        let res = grid.res.as_ivec3().to_array();
        let (mut next_crossing, mut delta, mut step, mut limit, mut voxel) =
            ([0.0; 3], [0.0; 3], [0; 3], [0; 3], [0; 3]);
        for a in 0..3 {
            let n = res[a] as f32;
            voxel[a] = ((p[a] * n) as i32).clamp(0, res[a] - 1);
            delta[a] = 1.0 / (d[a].abs() * n);
            if d[a] == 0.0 {
                next_crossing[a] = f32::INFINITY;
                step[a] = 1;
                limit[a] = res[a];
                delta[a] = f32::INFINITY;
            } else if d[a] > 0.0 {
                next_crossing[a] = t_min + ((voxel[a] + 1) as f32 / n - p[a]) / d[a];
                step[a] = 1;
                limit[a] = res[a];
            } else {
                next_crossing[a] = t_min + (voxel[a] as f32 / n - p[a]) / d[a];
                step[a] = -1;
                limit[a] = -1;
            }
        }
        Self { grid, sigma_t, band, t_min, t_max, next_crossing, delta, step, limit, voxel }
    }

    /// The walk for the path's wavelengths `w`: each cell's majorant is the largest of their
    /// bands' maxima.
    pub fn at_wavelengths(self, w: &SampledWavelengths) -> Self {
        Self { band: w.lambda.map(band_of), ..self }
    }
}

impl Iterator for Dda<'_> {
    type Item = MajorantSegment;

    fn next(&mut self) -> Option<MajorantSegment> {
        if self.t_min >= self.t_max {
            return None;
        }
        let nc = self.next_crossing;
        let axis = if nc[0] < nc[1] {
            if nc[0] < nc[2] {
                0
            } else {
                2
            }
        } else if nc[1] < nc[2] {
            1
        } else {
            2
        };
        let t_exit = self.t_max.min(nc[axis]);
        let cell = UVec3::new(self.voxel[0] as u32, self.voxel[1] as u32, self.voxel[2] as u32);
        let i = self.grid.first(cell);
        let max = &self.grid.max;
        let cell_max =
            if self.grid.bands == 1 { max[i] } else { self.band.map(|b| max[i + b]).into_iter().fold(0.0, f32::max) };
        let seg = MajorantSegment { t_min: self.t_min, t_max: t_exit, sigma_maj: self.sigma_t * cell_max };
        self.t_min = t_exit;
        if nc[axis] > self.t_max {
            self.t_min = self.t_max;
        }
        self.voxel[axis] += self.step[axis];
        if self.voxel[axis] == self.limit[axis] {
            self.t_min = self.t_max;
        }
        self.next_crossing[axis] += self.delta[axis];
        Some(seg)
    }
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
fn sample_collisions<'g>(
    segments: MajorantSegments<'g>,
    point_at: impl Fn(Vec3) -> MediumPoint,
    o: Vec3,
    d: Vec3,
    mut u: f32,
    rng: &mut Rng,
    mut collide: impl FnMut(Collision, &mut Rng) -> bool,
) -> SampledSpectrum {
    let mut t_maj = SampledSpectrum::one();
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
    use crate::media::Homogeneous;
    use crate::spectrum::Spectrum;

    #[test]
    fn homogeneous_free_flights_are_exponential_in_the_hero_wavelength_chi2() {
        // In a homogeneous medium σ_maj = σ_t: the first tentative collision has density
        // σ_t,0 exp(−σ_t,0 t) on [0, t_max] at the hero wavelength, and no collision has
        // probability exp(−σ_t,0 t_max).
        let medium = Medium::Homogeneous(Homogeneous {
            sigma_a: Spectrum::piecewise_linear(&[380.0, 780.0], &[0.2, 1.0]).unwrap(),
            sigma_s: Spectrum::piecewise_linear(&[380.0, 780.0], &[1.5, 0.1]).unwrap(),
            scale: 1.0,
            le: Spectrum::constant(0.0),
            g: 0.0,
        });
        let uniform = medium.uniform_point(&SampledWavelengths::sample_uniform(0.37));
        let s0 = (uniform.sigma_a[0] + uniform.sigma_s[0]) as f64;
        let ray = (Vec3::new(0.3, -1.0, 2.0), Vec3::new(0.0, 0.6, 0.8), 1.5f32);
        let escape = (-s0 * ray.2 as f64).exp();
        let p = first_collision_p_value(&medium, ray, |t| 1.0 - (-s0 * t as f64).exp(), escape, 30, 150_000, 11);
        assert!(p > 0.01, "p = {p}");
    }
}
