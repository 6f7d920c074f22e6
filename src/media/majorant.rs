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

use crate::spectrum::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};
use glam::{UVec3, Vec3};

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

#[cfg(test)]
mod tests {
    use super::super::delta_tracking::first_collision_p_value;
    use super::*;
    use crate::media::Homogeneous;
    use crate::media::Medium;
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
