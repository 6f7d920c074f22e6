//! A medium whose coefficients are σ_a and σ_s times a density sampled on a regular grid over a
//! box (pbrt-v4 `GridMedium`, the scene format's "uniformgrid"): density d(p) is the trilinear
//! interpolation of the samples, which sit at cell centres, and is 0 outside the box.

use super::majorant::{Dda, MajorantGrid, MajorantSegments};
use super::medium::MediumPoint;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{IVec3, Mat4, UVec3, Vec3};

/// Samples of a scalar field on the unit cube, x fastest (pbrt-v4 `SampledGrid`).
#[derive(Clone, Debug)]
pub struct DensityGrid {
    /// Samples per axis.
    pub n: UVec3,
    /// The samples.
    pub values: Vec<f32>,
}

impl DensityGrid {
    /// A grid of `n` samples; `None` when the count does not match or an axis is empty.
    pub fn new(n: UVec3, values: Vec<f32>) -> Option<Self> {
        let count = n.x as u64 * n.y as u64 * n.z as u64;
        (count > 0 && values.len() as u64 == count).then_some(Self { n, values })
    }

    /// The sample at integer coordinates, 0 outside the grid.
    #[inline]
    fn sample(&self, c: IVec3) -> f32 {
        let n = self.n.as_ivec3();
        if c.cmplt(IVec3::ZERO).any() || c.cmpge(n).any() {
            return 0.0;
        }
        self.values[((c.z * n.y + c.y) * n.x + c.x) as usize]
    }

    /// The trilinear interpolation at `p` in the unit cube (samples at cell centres).
    pub fn lookup(&self, p: Vec3) -> f32 {
        let ps = p * self.n.as_vec3() - Vec3::splat(0.5);
        let base = ps.floor();
        let f = ps - base;
        let c = base.as_ivec3();
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let s = |dx, dy, dz| self.sample(c + IVec3::new(dx, dy, dz));
        let x00 = lerp(s(0, 0, 0), s(1, 0, 0), f.x);
        let x10 = lerp(s(0, 1, 0), s(1, 1, 0), f.x);
        let x01 = lerp(s(0, 0, 1), s(1, 0, 1), f.x);
        let x11 = lerp(s(0, 1, 1), s(1, 1, 1), f.x);
        lerp(lerp(x00, x10, f.y), lerp(x01, x11, f.y), f.z)
    }

    /// The largest value [`Self::lookup`] takes over the box [lo, hi] of the unit cube: the
    /// maximum of every sample whose trilinear support overlaps it.
    pub fn max_over(&self, lo: Vec3, hi: Vec3) -> f32 {
        let n = self.n.as_ivec3();
        let a = (lo * self.n.as_vec3() - Vec3::splat(0.5)).floor().as_ivec3().max(IVec3::ZERO);
        let b = ((hi * self.n.as_vec3() - Vec3::splat(0.5)).floor().as_ivec3() + IVec3::ONE).min(n - IVec3::ONE);
        let mut m = 0.0f32;
        for z in a.z..=b.z {
            for y in a.y..=b.y {
                for x in a.x..=b.x {
                    m = m.max(self.sample(IVec3::new(x, y, z)));
                }
            }
        }
        m
    }

    /// The majorant grid of `res` cells over the unit cube.
    pub fn majorants(&self, res: UVec3) -> MajorantGrid {
        let mut max = Vec::with_capacity((res.x * res.y * res.z) as usize);
        for z in 0..res.z {
            for y in 0..res.y {
                for x in 0..res.x {
                    let lo = UVec3::new(x, y, z).as_vec3() / res.as_vec3();
                    let hi = (UVec3::new(x, y, z) + UVec3::ONE).as_vec3() / res.as_vec3();
                    max.push(self.max_over(lo, hi));
                }
            }
        }
        MajorantGrid { res, max }
    }
}

/// Cells per axis of the majorant grid (pbrt-v4's 16³).
pub const MAJORANT_RES: u32 = 16;

/// A density-grid medium.
#[derive(Clone, Debug)]
pub struct GridMedium {
    /// Unit-cube (grid) space from world space: the medium's transform, then p0–p1 to [0,1]³.
    grid_from_world: Mat4,
    density: DensityGrid,
    majorants: MajorantGrid,
    /// σ_a per unit density, times the scale [1/scene unit].
    sigma_a: Spectrum,
    /// σ_s per unit density, times the scale [1/scene unit].
    sigma_s: Spectrum,
    scale: f32,
    /// Emitted radiance where the density is 1, scale included (emission σ_a·L_e follows the
    /// density through σ_a).
    pub le: Spectrum,
    g: f32,
}

impl GridMedium {
    /// The medium over the box [p0, p1] of medium space, placed by `world_from_medium`; `None`
    /// when the box is empty or the transform is singular.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        world_from_medium: Mat4,
        p0: Vec3,
        p1: Vec3,
        density: DensityGrid,
        sigma_a: Spectrum,
        sigma_s: Spectrum,
        scale: f32,
        le: Spectrum,
        g: f32,
    ) -> Option<Self> {
        let (lo, hi) = (p0.min(p1), p0.max(p1));
        let size = hi - lo;
        let det = world_from_medium.determinant();
        if size.cmple(Vec3::ZERO).any() || det == 0.0 || !det.is_finite() {
            return None;
        }
        let grid_from_medium = Mat4::from_scale(1.0 / size) * Mat4::from_translation(-lo);
        let majorants = density.majorants(UVec3::splat(MAJORANT_RES));
        Some(Self {
            grid_from_world: grid_from_medium * world_from_medium.inverse(),
            density,
            majorants,
            sigma_a,
            sigma_s,
            scale,
            le,
            g,
        })
    }

    /// σ_a, σ_s (scale included) and L_e at unit density.
    pub fn unit_point(&self, w: &SampledWavelengths) -> MediumPoint {
        MediumPoint {
            sigma_a: self.sigma_a.sample(w) * self.scale,
            sigma_s: self.sigma_s.sample(w) * self.scale,
            le: self.le.sample(w),
            g: self.g,
        }
    }

    /// The coefficients at world-space `p`.
    pub fn point(&self, p: Vec3, w: &SampledWavelengths) -> MediumPoint {
        let unit = self.unit_point(w);
        let d = self.density.lookup(self.grid_from_world.transform_point3(p));
        MediumPoint { sigma_a: unit.sigma_a * d, sigma_s: unit.sigma_s * d, ..unit }
    }

    /// The density at world-space `p`.
    pub fn density_at(&self, p: Vec3) -> f32 {
        self.density.lookup(self.grid_from_world.transform_point3(p))
    }

    /// The majorant grid's cells along `o + t d`, t in [0, t_max], clipped to the box.
    /// `sigma_t` is σ_t at unit density.
    pub fn majorant_segments(&self, o: Vec3, d: Vec3, t_max: f32, sigma_t: SampledSpectrum) -> MajorantSegments<'_> {
        let go = self.grid_from_world.transform_point3(o);
        let gd = self.grid_from_world.transform_vector3(d);
        let (mut t0, mut t1) = (0.0f32, t_max);
        for a in 0..3 {
            let inv = 1.0 / gd[a];
            let (mut near, mut far) = ((0.0 - go[a]) * inv, (1.0 - go[a]) * inv);
            if near > far {
                std::mem::swap(&mut near, &mut far);
            }
            // NaN (a direction parallel to a face, origin on it) leaves the bounds as they are.
            if near > t0 {
                t0 = near;
            }
            if far < t1 {
                t1 = far;
            }
            if t0 > t1 {
                return MajorantSegments::none();
            }
        }
        MajorantSegments::Dda(Dda::new(&self.majorants, go, gd, t0, t1, sigma_t))
    }
}
