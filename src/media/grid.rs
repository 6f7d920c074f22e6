//! A medium whose coefficients are σ_a and σ_s times a density sampled on a regular grid over a
//! box (pbrt-v4 `GridMedium`, the scene format's "uniformgrid"): density d(p) is the trilinear
//! interpolation of the samples, which sit at cell centres, and is 0 outside the box.

use super::coefficients::{Homogeneous, MediumPoint};
use super::majorant::{Dda, MajorantGrid, MajorantSegments};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{IVec3, Mat4, UVec3, Vec3};

/// ⌊x⌋ of a lattice coordinate of a point in the unit cube (−½ ≤ x < 2³¹): truncation, one
/// less where it rounded up. NaN gives 0 (and NaN interpolation weights, as
/// [`crate::math::floor`]'s NaN would).
#[inline]
fn lattice_floor(x: f32) -> f32 {
    let t = x as i32 as f32;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// Where `p`, a point of the unit cube, falls on a lattice of `n` samples per axis at cell
/// centres: the lower corner sample of its trilinear neighbourhood and the offsets from it.
#[inline]
pub(super) fn lattice_point(n: UVec3, p: Vec3) -> (IVec3, Vec3) {
    let ps = p * n.as_vec3() - Vec3::splat(0.5);
    let base = ps.map(lattice_floor);
    (base.as_ivec3(), ps - base)
}

/// The first sample of each of the four rows of two (x fastest; y, then z) that hold the eight
/// neighbours of lower corner `c` on a lattice of `n` samples, when all eight are in it (the
/// common case).
#[inline]
pub(super) fn interior_rows(n: IVec3, c: IVec3) -> Option<[usize; 4]> {
    if !(c.cmpge(IVec3::ZERO).all() && (c + IVec3::ONE).cmplt(n).all()) {
        return None;
    }
    let i0 = ((c.z * n.y + c.y) * n.x + c.x) as usize;
    let (sy, sz) = (n.x as usize, (n.x * n.y) as usize);
    Some([i0, i0 + sy, i0 + sz, i0 + sz + sy])
}

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

    /// The trilinear interpolation at `p` in the unit cube (samples at cell centres); 0 outside
    /// the cube, where the medium ends.
    pub fn lookup(&self, p: Vec3) -> f32 {
        if p.cmplt(Vec3::ZERO).any() || p.cmpgt(Vec3::ONE).any() {
            return 0.0;
        }
        let (c, f) = lattice_point(self.n, p);
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let [x00, x10, x01, x11] = if let Some(rows) = interior_rows(self.n.as_ivec3(), c) {
            // Each row's pair taken once, as an array.
            rows.map(|row| {
                let pair: &[f32; 2] = self.values[row..row + 2].try_into().expect("a pair");
                lerp(pair[0], pair[1], f.x)
            })
        } else {
            let s = |dx, dy, dz| self.sample(c + IVec3::new(dx, dy, dz));
            [
                lerp(s(0, 0, 0), s(1, 0, 0), f.x),
                lerp(s(0, 1, 0), s(1, 1, 0), f.x),
                lerp(s(0, 0, 1), s(1, 0, 1), f.x),
                lerp(s(0, 1, 1), s(1, 1, 1), f.x),
            ]
        };
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
        MajorantGrid::scalar(res, max)
    }
}

/// What a density grid emits (pbrt-v4 `GridMedium::Le`): L_e(p) = s(p) · L(p), with s the
/// `Lescale` grid (one sample unless given per voxel; the luminance normalisation of `Le` folded
/// in) and L either the `Le` spectrum or a blackbody at the `temperature` grid's value.
#[derive(Clone, Debug)]
pub struct GridEmission {
    /// The scale grid s.
    pub scale: DensityGrid,
    /// The emitted spectrum.
    pub source: EmissionSource,
}

/// The spectrum a density grid emits.
#[derive(Clone, Debug)]
pub enum EmissionSource {
    /// The same spectrum everywhere.
    Spectrum(Spectrum),
    /// A normalised blackbody at (T(p) − `offset`) · `scale` kelvin, where that exceeds 100 K.
    Temperature {
        /// Temperatures at the density grid's samples [K, before offset and scale].
        grid: DensityGrid,
        /// Subtracted from T.
        offset: f32,
        /// Multiplies T − offset.
        scale: f32,
    },
}

impl GridEmission {
    /// L_e at unit-cube point `q`.
    fn at(&self, q: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        let s = self.scale.lookup(q);
        if s <= 0.0 {
            return SampledSpectrum::zero();
        }
        match &self.source {
            EmissionSource::Spectrum(le) => le.sample(w) * s,
            EmissionSource::Temperature { grid, offset, scale } => {
                let t = (grid.lookup(q) - offset) * scale;
                if t > 100.0 {
                    Spectrum::blackbody(t).sample(w) * s
                } else {
                    SampledSpectrum::zero()
                }
            }
        }
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
    /// The coefficients at unit density (emission σ_a·L_e follows the density through σ_a).
    pub coefficients: Homogeneous,
    /// Emission, if any.
    pub emission: Option<GridEmission>,
}

impl GridMedium {
    /// The medium over the box [p0, p1] of medium space, placed by `world_from_medium`, with
    /// `coefficients` where the density is 1; `None` when the box is empty or the transform is
    /// singular.
    pub fn new(
        world_from_medium: Mat4,
        p0: Vec3,
        p1: Vec3,
        density: DensityGrid,
        coefficients: Homogeneous,
    ) -> Option<Self> {
        let grid_from_world = unit_cube_from_world(world_from_medium, p0, p1)?;
        let majorants = density.majorants(UVec3::splat(MAJORANT_RES));
        Some(Self { grid_from_world, density, majorants, coefficients, emission: None })
    }

    /// σ_a, σ_s (scale included) and L_e at unit density.
    pub fn unit_point(&self, w: &SampledWavelengths) -> MediumPoint {
        self.coefficients.point(w)
    }

    /// The coefficients at world-space `p`.
    pub fn point(&self, p: Vec3, w: &SampledWavelengths) -> MediumPoint {
        self.point_given(p, &self.unit_point(w), w)
    }

    /// [`GridMedium::point`] given the coefficients at unit density `unit` at `w` (evaluated
    /// once per ray by the caller).
    pub fn point_given(&self, p: Vec3, unit: &MediumPoint, w: &SampledWavelengths) -> MediumPoint {
        let q = self.grid_from_world.transform_point3(p);
        let d = self.density.lookup(q);
        let le = self.emission.as_ref().map_or(unit.le, |e| e.at(q, w));
        MediumPoint { sigma_a: unit.sigma_a * d, sigma_s: unit.sigma_s * d, le, g: unit.g }
    }

    /// The density at world-space `p`.
    pub fn density_at(&self, p: Vec3) -> f32 {
        self.density.lookup(self.grid_from_world.transform_point3(p))
    }

    /// The majorant grid's cells along `o + t d`, t in [0, t_max], clipped to the box.
    /// `sigma_t` is σ_t at unit density.
    pub fn majorant_segments(&self, o: Vec3, d: Vec3, t_max: f32, sigma_t: SampledSpectrum) -> MajorantSegments<'_> {
        let (go, gd) = (self.grid_from_world.transform_point3(o), self.grid_from_world.transform_vector3(d));
        match clip_to_unit_cube(go, gd, t_max) {
            Some((t0, t1)) => MajorantSegments::Dda(Dda::new(&self.majorants, go, gd, t0, t1, sigma_t)),
            None => MajorantSegments::none(),
        }
    }
}

/// Unit-cube space from world space for a box [p0, p1] of medium space placed by
/// `world_from_medium`; `None` when the box is empty or the transform singular.
pub fn unit_cube_from_world(world_from_medium: Mat4, p0: Vec3, p1: Vec3) -> Option<Mat4> {
    let (lo, hi) = (p0.min(p1), p0.max(p1));
    let size = hi - lo;
    let det = world_from_medium.determinant();
    if size.cmple(Vec3::ZERO).any() || det == 0.0 || !det.is_finite() {
        return None;
    }
    Some(Mat4::from_scale(1.0 / size) * Mat4::from_translation(-lo) * world_from_medium.inverse())
}

/// The parameter range [t0, t1] ⊆ [0, t_max] of `o + t d` inside the unit cube (slab test).
pub fn clip_to_unit_cube(o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, f32)> {
    let (mut t0, mut t1) = (0.0f32, t_max);
    for a in 0..3 {
        let inv = 1.0 / d[a];
        let (mut near, mut far) = ((0.0 - o[a]) * inv, (1.0 - o[a]) * inv);
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
            return None;
        }
    }
    Some((t0, t1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::media::delta_tracking::first_collision_p_value;
    use crate::media::Medium;
    use crate::sampling::Rng;
    use crate::spectrum::Spectrum;

    /// A grid medium over the unit cube, rotated and moved, with a random density.
    fn random_grid(seed: u64, amplitude: f32) -> GridMedium {
        let mut rng = Rng::new(seed, 0);
        let n = UVec3::new(7, 5, 9);
        let values = (0..n.x * n.y * n.z).map(|_| amplitude * (rng.uniform() * 3.0).powi(2)).collect();
        let world_from_medium = Mat4::from_translation(Vec3::new(0.3, -0.2, 0.1))
            * Mat4::from_rotation_y(0.4)
            * Mat4::from_scale(Vec3::new(1.5, 1.0, 0.8));
        let density = DensityGrid::new(n, values).unwrap();
        let coefficients = Homogeneous {
            sigma_a: Spectrum::constant(0.3),
            sigma_s: Spectrum::constant(0.9),
            scale: 1.0,
            le: Spectrum::constant(0.0),
            g: 0.0,
        };
        GridMedium::new(world_from_medium, Vec3::splat(-0.5), Vec3::splat(0.5), density, coefficients).unwrap()
    }

    /// The majorant at world point `p`, by looking up the cell that contains it.
    fn majorant_at(g: &GridMedium, p: Vec3) -> f32 {
        let q = g.grid_from_world.transform_point3(p);
        if q.cmplt(Vec3::ZERO).any() || q.cmpge(Vec3::ONE).any() {
            return 0.0;
        }
        let c = (q * g.majorants.res.as_vec3()).as_uvec3().min(g.majorants.res - UVec3::ONE);
        g.majorants.at(c)
    }

    #[test]
    fn grid_emission_follows_the_scale_grid_and_the_temperature() {
        // At the box centre a one-sample scale grid is exactly its sample; toward a face it
        // falls off linearly to half (the sample's trilinear support), as pbrt-v4's grid does.
        let mut g = random_grid(7, 1.0);
        let one = |v: f32| DensityGrid::new(UVec3::ONE, vec![v]).unwrap();
        let le = Spectrum::constant(3.0);
        g.emission = Some(GridEmission { scale: one(0.5), source: EmissionSource::Spectrum(le) });
        let w = SampledWavelengths::sample_uniform(0.2);
        let world = |q: Vec3| g.grid_from_world.inverse().transform_point3(q);
        assert!((g.point(world(Vec3::splat(0.5)), &w).le[0] - 1.5).abs() < 1e-5);
        assert!((g.point(world(Vec3::new(0.25, 0.5, 0.5)), &w).le[0] - 1.5 * 0.75).abs() < 1e-5);
        let source = EmissionSource::Temperature { grid: one(2100.0), offset: 100.0, scale: 1.5 };
        g.emission = Some(GridEmission { scale: one(2.0), source });
        let expect = Spectrum::blackbody(3000.0).sample(&w) * 2.0;
        let got = g.point(world(Vec3::splat(0.5)), &w).le;
        assert!((got - expect).max_value().abs() < 1e-4 * expect.max_value(), "{got:?} vs {expect:?}");
        let cold = EmissionSource::Temperature { grid: one(150.0), offset: 100.0, scale: 1.0 };
        g.emission = Some(GridEmission { scale: one(2.0), source: cold });
        assert!(g.point(world(Vec3::splat(0.5)), &w).le.is_black(), "50 K emits nothing");
    }

    #[test]
    fn majorants_bound_the_density_everywhere() {
        let g = random_grid(1, 1.0);
        let mut rng = Rng::new(2, 0);
        for _ in 0..20_000 {
            let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 3.0 - Vec3::splat(1.5);
            let d = g.density_at(p);
            assert!(d <= majorant_at(&g, p) * (1.0 + 1e-5) + 1e-6, "density {d} above its majorant at {p}");
        }
    }

    #[test]
    fn dda_segments_are_the_cells_along_the_ray() {
        // Each segment's majorant must be the majorant grid's value at every point inside it.
        let g = random_grid(3, 1.0);
        let mut rng = Rng::new(4, 0);
        for _ in 0..200 {
            let o = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0 - Vec3::splat(2.0);
            let d = (Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3::splat(0.5)).normalize();
            let mut last = 0.0f32;
            let mut covered = 0.0f32;
            for seg in g.majorant_segments(o, d, 10.0, SampledSpectrum::one()) {
                assert!(seg.t_min >= last - 1e-5 && seg.t_max >= seg.t_min, "segments out of order");
                last = seg.t_max;
                covered += seg.t_max - seg.t_min;
                for k in 1..8 {
                    let t = seg.t_min + (seg.t_max - seg.t_min) * k as f32 / 8.0;
                    if seg.t_max - seg.t_min < 1e-4 {
                        continue;
                    }
                    assert_eq!(
                        seg.sigma_maj[0],
                        majorant_at(&g, o + d * t),
                        "t = {t} in [{}, {}]",
                        seg.t_min,
                        seg.t_max
                    );
                }
            }
            // Brute force: the length of the ray inside the box.
            let inside = (0..20_000)
                .filter(|&i| {
                    let q = g.grid_from_world.transform_point3(o + d * (10.0 * (i as f32 + 0.5) / 20_000.0));
                    q.cmpge(Vec3::ZERO).all() && q.cmplt(Vec3::ONE).all()
                })
                .count() as f32
                * 10.0
                / 20_000.0;
            assert!((covered - inside).abs() < 2e-3 * 10.0, "covered {covered} vs inside {inside}");
        }
    }

    #[test]
    fn first_collisions_follow_the_majorant_chi2() {
        // The first tentative collision has CDF F(t) = 1 − exp(−∫_0^t σ_maj); F is found by
        // integrating the cell lookup along the ray, not from the DDA's segments.
        let g = random_grid(5, 0.12);
        let (o, d, t_max) = (Vec3::new(-1.5, 0.1, -0.2), Vec3::new(1.0, 0.05, 0.1).normalize(), 4.0f32);
        let sigma_t = 1.2f64; // σ_a + σ_s at unit density
        let steps = 200_000;
        let dt = t_max as f64 / steps as f64;
        let mut tau = Vec::with_capacity(steps + 1);
        tau.push(0.0f64);
        for i in 0..steps {
            let t = (i as f64 + 0.5) * dt;
            let last = *tau.last().unwrap();
            tau.push(last + sigma_t * majorant_at(&g, o + d * t as f32) as f64 * dt);
        }
        let cdf = |t: f32| {
            let x = (t as f64 / dt).clamp(0.0, steps as f64);
            let i = (x as usize).min(steps - 1);
            let tt = tau[i] + (tau[i + 1] - tau[i]) * (x - i as f64);
            1.0 - (-tt).exp()
        };
        let escape = (-tau[steps]).exp();
        assert!(escape > 0.05 && escape < 0.9, "the test ray should both collide and escape often: {escape}");
        let medium = Medium::Grid(Box::new(g));
        let p = first_collision_p_value(&medium, (o, d, t_max), cdf, escape, 40, 200_000, 6);
        assert!(p > 0.01, "p = {p}");
    }
}
