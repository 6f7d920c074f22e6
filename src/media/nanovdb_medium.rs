//! pbrt-v4's `NanoVDBMedium`: σ_a and σ_s scaled by a NanoVDB density grid, with optional
//! blackbody emission from a temperature grid.
//!
//! - Density d(p) is the trilinear interpolation of the "density" grid's voxels at p's index
//!   coordinates (the grid's own map, from the medium's space); σ_a(p) = d(p) σ_a, likewise σ_s.
//! - Emission: L_e(p) = `Lescale` · B_norm((T(p) − `temperatureoffset`) · `temperaturescale`),
//!   B_norm the blackbody normalised to a peak of 1, where that temperature exceeds 100 K;
//!   the source term is σ_a(p) L_e(p).
//! - The medium's bounds are the union of the grids' world bounding boxes (the index bounding box
//!   of the active values, its maximum + 1, through the map) in the medium's space.
//! - Majorants: a 64³ grid over the bounds, each cell the largest value any voxel whose trilinear
//!   support (its index ± 1) meets the cell can contribute.

use super::coefficients::{Homogeneous, MediumPoint};
use super::majorant::{Dda, MajorantGrid, MajorantSegments};
use super::nanovdb::grid::Node;
use super::nanovdb::FloatGrid;
use crate::media::grid::{clip_to_unit_cube, unit_cube_from_world};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{IVec3, Mat4, UVec3, Vec3};

/// Cells per axis of the majorant grid (pbrt-v4's 64³ for NanoVDB media).
pub const NANOVDB_MAJORANT_RES: u32 = 64;

/// Blackbody emission from a temperature grid.
#[derive(Clone, Debug)]
pub struct TemperatureEmission {
    /// The temperature grid [K before offset and scale].
    pub grid: FloatGrid,
    /// `Lescale`: multiplies the normalised blackbody.
    pub le_scale: f32,
    /// `temperatureoffset` [K]: subtracted from T.
    pub offset: f32,
    /// `temperaturescale`: multiplies T − offset.
    pub scale: f32,
}

/// A NanoVDB density medium.
#[derive(Clone, Debug)]
pub struct NanoVdbMedium {
    medium_from_world: Mat4,
    /// The bounds' unit cube from world space, the majorant grid's space.
    unit_from_world: Mat4,
    density: FloatGrid,
    majorants: MajorantGrid,
    /// The coefficients at unit density (no emission: that comes from the temperature grid).
    pub coefficients: Homogeneous,
    /// Emission, if the file has a temperature grid.
    pub emission: Option<TemperatureEmission>,
    /// The bounds in medium space [scene units].
    pub bounds: (Vec3, Vec3),
}

impl NanoVdbMedium {
    /// The medium of `density` placed by `world_from_medium`; `None` when its bounds are empty
    /// or the transform singular.
    pub fn new(
        world_from_medium: Mat4,
        density: FloatGrid,
        coefficients: Homogeneous,
        emission: Option<TemperatureEmission>,
    ) -> Option<Self> {
        let bbox = |g: &FloatGrid| (g.world_bbox.0.as_vec3(), g.world_bbox.1.as_vec3());
        let mut bounds = bbox(&density);
        if let Some(e) = &emission {
            let t = bbox(&e.grid);
            if t.0.cmplt(t.1).all() {
                bounds = (bounds.0.min(t.0), bounds.1.max(t.1));
            }
        }
        if !(bounds.0.is_finite() && bounds.1.is_finite()) {
            return None;
        }
        let unit_from_world = unit_cube_from_world(world_from_medium, bounds.0, bounds.1)?;
        let majorants = majorant_grid(&density, bounds, UVec3::splat(NANOVDB_MAJORANT_RES));
        Some(Self {
            medium_from_world: world_from_medium.inverse(),
            unit_from_world,
            density,
            majorants,
            coefficients,
            emission,
            bounds,
        })
    }

    /// The density at world-space `p`.
    #[inline]
    pub fn density_at(&self, p: Vec3) -> f32 {
        let q = self.medium_from_world.transform_point3(p);
        self.density.trilinear(self.density.index_from_world(q))
    }

    /// The coefficients at world-space `p`, from `unit`, those at unit density.
    pub fn point(&self, p: Vec3, unit: &MediumPoint, w: &SampledWavelengths) -> MediumPoint {
        let q = self.medium_from_world.transform_point3(p);
        let d = self.density.trilinear(self.density.index_from_world(q));
        let le = match &self.emission {
            Some(e) => {
                let t = (e.grid.trilinear(e.grid.index_from_world(q)) - e.offset) * e.scale;
                if t > 100.0 {
                    Spectrum::blackbody(t).sample(w) * e.le_scale
                } else {
                    SampledSpectrum::zero()
                }
            }
            None => SampledSpectrum::zero(),
        };
        MediumPoint { sigma_a: unit.sigma_a * d, sigma_s: unit.sigma_s * d, le, g: unit.g }
    }

    /// The majorant grid's cells along `o + t d`, t in [0, t_max], clipped to the bounds;
    /// `sigma_t` is σ_t at unit density.
    pub fn majorant_segments(&self, o: Vec3, d: Vec3, t_max: f32, sigma_t: SampledSpectrum) -> MajorantSegments<'_> {
        let (uo, ud) = (self.unit_from_world.transform_point3(o), self.unit_from_world.transform_vector3(d));
        match clip_to_unit_cube(uo, ud, t_max) {
            Some((t0, t1)) => MajorantSegments::Dda(Dda::new(&self.majorants, uo, ud, t0, t1, sigma_t)),
            None => MajorantSegments::none(),
        }
    }

    /// The majorant at world-space `p` (0 outside the bounds).
    pub fn majorant_at(&self, p: Vec3) -> f32 {
        let u = self.unit_from_world.transform_point3(p);
        if u.cmplt(Vec3::ZERO).any() || u.cmpge(Vec3::ONE).any() {
            return 0.0;
        }
        let res = self.majorants.res;
        self.majorants.at((u * res.as_vec3()).as_uvec3().min(res - UVec3::ONE))
    }
}

/// The majorant grid of `res` cells over `bounds` (medium space): every tile and leaf of the
/// tree raises the cells its values can reach. A voxel at index c enters the trilinear
/// interpolation at index points in (c − 1, c + 1)³, so a region of voxels [o, o + n − 1]
/// reaches the cells that its index box [o − 1, o + n]³, mapped to the medium's space, overlaps.
/// Where no tile or leaf lies the value is the background, the floor of every cell.
fn majorant_grid(grid: &FloatGrid, bounds: (Vec3, Vec3), res: UVec3) -> MajorantGrid {
    let floor = grid.background.max(0.0);
    let mut max = vec![floor; (res.x * res.y * res.z) as usize];
    let (lo, size) = (bounds.0, bounds.1 - bounds.0);
    let n = res.as_vec3();
    let world_from_index = grid.world_from_index();
    // The cell range [a, b] (inclusive) that the index box [c0, c1] overlaps.
    let cells = |c0: Vec3, c1: Vec3| -> Option<(UVec3, UVec3)> {
        let (mut a, mut b) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for k in 0..8 {
            let c = Vec3::new(
                if k & 4 == 0 { c0.x } else { c1.x },
                if k & 2 == 0 { c0.y } else { c1.y },
                if k & 1 == 0 { c0.z } else { c1.z },
            );
            let u = (world_from_index(c) - lo) / size * n;
            (a, b) = (a.min(u), b.max(u));
        }
        if b.cmplt(Vec3::ZERO).any() || a.cmpge(n).any() {
            return None;
        }
        let top = n - Vec3::ONE;
        Some((a.floor().clamp(Vec3::ZERO, top).as_uvec3(), b.floor().clamp(Vec3::ZERO, top).as_uvec3()))
    };
    let mut raise = |(a, b): (UVec3, UVec3), v: f32| {
        for z in a.z..=b.z {
            for y in a.y..=b.y {
                let row = ((z * res.y + y) * res.x) as usize;
                for m in &mut max[row + a.x as usize..=row + b.x as usize] {
                    *m = m.max(v);
                }
            }
        }
    };
    let reach = |o: IVec3, n: i32| (o.as_vec3() - Vec3::ONE, (o + IVec3::splat(n)).as_vec3());
    grid.visit(|o, edge, node| match node {
        Node::Tile(v) => {
            if v > floor {
                let (c0, c1) = reach(o, edge);
                if let Some(r) = cells(c0, c1) {
                    raise(r, v);
                }
            }
        }
        Node::Leaf(values) => {
            let leaf_max = values.iter().cloned().fold(f32::NEG_INFINITY, f32::max);
            if leaf_max <= floor {
                return;
            }
            let (c0, c1) = reach(o, edge);
            let Some(r) = cells(c0, c1) else { return };
            if (r.1 - r.0).cmple(UVec3::ONE).all() {
                // Cells as large as the leaf: its maximum loses little.
                raise(r, leaf_max);
                return;
            }
            for (k, &v) in values.iter().enumerate() {
                if v > floor {
                    let c = o + IVec3::new((k >> 6) as i32, ((k >> 3) & 7) as i32, (k & 7) as i32);
                    let (c0, c1) = reach(c, 1);
                    if let Some(r) = cells(c0, c1) {
                        raise(r, v);
                    }
                }
            }
        }
    });
    MajorantGrid::scalar(res, max)
}
