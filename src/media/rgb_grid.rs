//! A medium whose σ_a and σ_s are RGB colours sampled on a grid over a box (pbrt-v4
//! `RGBGridMedium`, the scene format's "rgbgrid"): each voxel's RGB is an unbounded spectrum
//! (Jakob & Hanika 2019), and the coefficients at a point are the trilinear interpolation of the
//! eight neighbouring voxels' spectra at the path's wavelengths, times `scale`. A coefficient
//! given no grid is 1 everywhere (times `scale`), as in pbrt-v4. An optional `Le` grid of RGB
//! illuminant spectra (the colour space's white times each voxel's colour) emits
//! L_e(p) = `Lescale` · trilinear(Le)(p), unscaled by `scale` and not normalised, as pbrt-v4's.

use super::coefficients::MediumPoint;
use super::grid::{clip_to_unit_cube, interior_rows, lattice_point, unit_cube_from_world, DensityGrid, MAJORANT_RES};
use super::majorant::{band_range, Dda, MajorantGrid, MajorantSegments, BANDS};
use crate::spectrum::{normalised_wavelengths, SampledSpectrum, SampledWavelengths, ScaledSigmoid, Spectrum};
use glam::{IVec3, Mat4, UVec3, Vec3, Vec4};

/// Spectra on the unit cube's sample lattice (cell centres), x fastest.
#[derive(Clone, Debug)]
pub struct SpectrumGrid {
    /// Samples per axis.
    n: UVec3,
    /// One spectrum per sample.
    values: Vec<Spectrum>,
    /// When every sample is a sigmoid spectrum (or a constant, σ(0) = ½ times twice it): each
    /// in single precision, evaluated four wavelengths at a time without dispatch.
    sigmoids: Option<Vec<ScaledSigmoid>>,
}

impl SpectrumGrid {
    /// The grid of `n.x · n.y · n.z` spectra `values`, x fastest; `None` when the counts differ.
    pub fn new(n: UVec3, values: Vec<Spectrum>) -> Option<Self> {
        if values.len() as u64 != u64::from(n.x) * u64::from(n.y) * u64::from(n.z) || values.is_empty() {
            return None;
        }
        let packed = |s: &Spectrum| match s {
            Spectrum::Sigmoid { poly, scale } => Some(ScaledSigmoid { c: poly.c.map(|c| c as f32), scale: *scale }),
            Spectrum::Constant(v) => Some(ScaledSigmoid { c: [0.0; 3], scale: 2.0 * v }),
            _ => None,
        };
        let sigmoids = values.iter().map(packed).collect();
        Some(Self { n, values, sigmoids })
    }

    /// Trilinear interpolation at `p`, a point of the unit cube (which the caller has checked;
    /// NaN coordinates give NaN), 0 outside the lattice.
    fn lookup(&self, p: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        let n = self.n.as_ivec3();
        let (c0, f) = lattice_point(self.n, p);
        let x = normalised_wavelengths(w.lambda);
        let (wx, wy, wz) = ([1.0 - f.x, f.x], [1.0 - f.y, f.y], [1.0 - f.z, f.z]);
        let mut sum = Vec4::ZERO;
        if let Some(rows) = interior_rows(n, c0) {
            // Each row's pair taken once, as an array.
            let weights = [wz[0] * wy[0], wz[0] * wy[1], wz[1] * wy[0], wz[1] * wy[1]];
            match &self.sigmoids {
                Some(s) => {
                    for (row, weight) in rows.into_iter().zip(weights) {
                        let pair: &[ScaledSigmoid; 2] = s[row..row + 2].try_into().expect("a pair");
                        sum += weight * (wx[0] * pair[0].sample(x) + wx[1] * pair[1].sample(x));
                    }
                }
                None => {
                    for (row, weight) in rows.into_iter().zip(weights) {
                        let pair: &[Spectrum; 2] = self.values[row..row + 2].try_into().expect("a pair");
                        sum += weight * (wx[0] * pair[0].sample(w).0 + wx[1] * pair[1].sample(w).0);
                    }
                }
            }
            return SampledSpectrum(sum);
        }
        let value = |i: usize| match &self.sigmoids {
            Some(s) => s[i].sample(x),
            None => self.values[i].sample(w).0,
        };
        for corner in 0..8 {
            let o = IVec3::new(corner & 1, (corner >> 1) & 1, corner >> 2);
            let c = c0 + o;
            if c.cmplt(IVec3::ZERO).any() || c.cmpge(n).any() {
                continue;
            }
            let weight = wx[o.x as usize] * wy[o.y as usize] * wz[o.z as usize];
            if weight > 0.0 {
                sum += weight * value(((c.z * n.y + c.y) * n.x + c.x) as usize);
            }
        }
        SampledSpectrum(sum)
    }

    /// Each sample's largest value over the wavelengths [lo, hi] nm, as a scalar grid, raised by
    /// 10⁻⁵ of itself so that it bounds the single-precision evaluation too.
    fn maxima_over(&self, (lo, hi): (f64, f64)) -> DensityGrid {
        let m = self.values.iter().map(|s| s.max_value_over(lo, hi).max(0.0) as f32 * (1.0 + 1e-5)).collect();
        DensityGrid::new(self.n, m).expect("same shape")
    }
}

/// An RGB-grid medium.
#[derive(Clone, Debug)]
pub struct RgbGridMedium {
    grid_from_world: Mat4,
    sigma_a: Option<SpectrumGrid>,
    sigma_s: Option<SpectrumGrid>,
    scale: f32,
    g: f32,
    /// The emission grid [W/(sr·m²·nm) per unit of its RGB] and its `Lescale`.
    le: Option<(SpectrumGrid, f32)>,
    /// Per-cell and per-band bound on max σ_a + max σ_s (before `scale`).
    majorants: MajorantGrid,
}

impl RgbGridMedium {
    /// The medium over [p0, p1] of medium space placed by `world_from_medium`; a missing grid
    /// is 1. `None` when the box is empty, the transform singular or both grids are missing.
    pub fn new(
        world_from_medium: Mat4,
        p0: Vec3,
        p1: Vec3,
        sigma_a: Option<SpectrumGrid>,
        sigma_s: Option<SpectrumGrid>,
        scale: f32,
        g: f32,
    ) -> Option<Self> {
        let grid_from_world = unit_cube_from_world(world_from_medium, p0, p1)?;
        let res = UVec3::splat(MAJORANT_RES);
        if sigma_a.is_none() && sigma_s.is_none() {
            return None;
        }
        // The voxels' colours differ, so σ_t's largest value differs per wavelength band: one
        // bound per band lets a path's majorant follow its wavelengths.
        let cells = (res.x * res.y * res.z) as usize;
        let cell_maxima = |g: &Option<SpectrumGrid>, band| {
            g.as_ref().map_or(vec![1.0; cells], |g| g.maxima_over(band_range(band)).majorants(res).max)
        };
        let per_band: Vec<Vec<f32>> = (0..BANDS)
            .map(|b| cell_maxima(&sigma_a, b).iter().zip(cell_maxima(&sigma_s, b)).map(|(a, s)| a + s).collect())
            .collect();
        let max = (0..cells).flat_map(|c| per_band.iter().map(move |m| m[c])).collect();
        let majorants = MajorantGrid { res, bands: BANDS, max };
        Some(Self { grid_from_world, sigma_a, sigma_s, scale, g, le: None, majorants })
    }

    /// True when the medium has an emission grid.
    pub fn emits(&self) -> bool {
        self.le.is_some()
    }

    /// The medium emitting `le_scale` times the trilinear interpolation of `le`.
    pub fn with_emission(self, le: SpectrumGrid, le_scale: f32) -> Self {
        Self { le: (le_scale > 0.0).then_some((le, le_scale)), ..self }
    }

    /// The coefficients at world-space `p`.
    pub fn point(&self, p: Vec3, w: &SampledWavelengths) -> MediumPoint {
        let q = self.grid_from_world.transform_point3(p);
        if q.cmplt(Vec3::ZERO).any() || q.cmpgt(Vec3::ONE).any() {
            let zero = SampledSpectrum::zero();
            return MediumPoint { sigma_a: zero, sigma_s: zero, le: zero, g: self.g };
        }
        let at = |g: &Option<SpectrumGrid>| g.as_ref().map_or(SampledSpectrum::one(), |g| g.lookup(q, w)) * self.scale;
        let le = self.le.as_ref().map_or(SampledSpectrum::zero(), |(le, k)| le.lookup(q, w) * *k);
        MediumPoint { sigma_a: at(&self.sigma_a), sigma_s: at(&self.sigma_s), le, g: self.g }
    }

    /// The majorant grid's cells along `o + t d`, t in [0, t_max], clipped to the box, at the
    /// wavelengths `w`.
    pub fn majorant_segments(&self, o: Vec3, d: Vec3, t_max: f32, w: &SampledWavelengths) -> MajorantSegments<'_> {
        let (go, gd) = (self.grid_from_world.transform_point3(o), self.grid_from_world.transform_vector3(d));
        match clip_to_unit_cube(go, gd, t_max) {
            Some((t0, t1)) => {
                let scale = SampledSpectrum::splat(self.scale);
                MajorantSegments::Dda(Dda::new(&self.majorants, go, gd, t0, t1, scale).at_wavelengths(w))
            }
            None => MajorantSegments::none(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use crate::spectrum::SigmoidPolynomial;

    /// A grid of strongly coloured sigmoid spectra (peaks at either end of the spectrum or
    /// inside it), with some empty voxels.
    fn colourful(rng: &mut Rng, n: UVec3) -> SpectrumGrid {
        let values = (0..n.x * n.y * n.z)
            .map(|_| {
                if rng.uniform() < 0.2 {
                    return Spectrum::constant(0.0);
                }
                let c = [(rng.uniform() - 0.5) * 16.0, (rng.uniform() - 0.5) * 12.0, (rng.uniform() - 0.5) * 3.0];
                Spectrum::Sigmoid { poly: SigmoidPolynomial { c: c.map(f64::from) }, scale: 3.0 * rng.uniform() }
            })
            .collect();
        SpectrumGrid::new(n, values).unwrap()
    }

    #[test]
    fn the_majorant_bounds_sigma_t_at_each_wavelength_and_follows_the_band() {
        // Every point of every DDA segment: σ_t ≤ σ_maj at each of the four wavelengths. All
        // four in one band make the bound that band's alone, so a wrong band is caught; and
        // that bound must be tighter than the whole spectrum's somewhere.
        let mut rng = Rng::new(7, 1);
        let n = UVec3::new(5, 4, 6);
        let world_from_medium = Mat4::from_translation(Vec3::new(0.2, -0.1, 0.3)) * Mat4::from_rotation_x(0.5);
        let (a, s) = (colourful(&mut rng, n), colourful(&mut rng, n));
        let medium =
            RgbGridMedium::new(world_from_medium, Vec3::ZERO, Vec3::new(1.0, 2.0, 1.5), Some(a), Some(s), 2.0, 0.0)
                .unwrap();
        let (mut checked, mut tighter) = (0, 0);
        for _ in 0..400 {
            let o = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0 - Vec3::splat(1.5);
            let d = (Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3::splat(0.5)).normalize();
            let one_band = rng.uniform() < 0.5;
            let lambda = if one_band {
                [360.0 + 470.0 * rng.uniform(); 4]
            } else {
                std::array::from_fn(|_| 360.0 + 470.0 * rng.uniform())
            };
            let w = SampledWavelengths { lambda, pdf: [1.0 / 470.0; 4] };
            // The cell's bound over the whole spectrum, at a point of the segment.
            let whole = |p: Vec3| {
                let res = medium.majorants.res;
                let c = (medium.grid_from_world.transform_point3(p) * res.as_vec3()).as_uvec3().min(res - UVec3::ONE);
                let first = ((c.z * res.y + c.y) * res.x + c.x) as usize * BANDS;
                medium.majorants.max[first..first + BANDS].iter().fold(0.0f32, |m, &v| m.max(v)) * medium.scale
            };
            for seg in medium.majorant_segments(o, d, 10.0, &w) {
                for k in 1..8 {
                    let t = seg.t_min + (seg.t_max - seg.t_min) * k as f32 / 8.0;
                    let mp = medium.point(o + d * t, &w);
                    let sigma_t = mp.sigma_a + mp.sigma_s;
                    for i in 0..4 {
                        assert!(
                            sigma_t[i] <= seg.sigma_maj[i],
                            "λ {}: σ_t {} > σ_maj {}",
                            lambda[i],
                            sigma_t[i],
                            seg.sigma_maj[i]
                        );
                    }
                    checked += 1;
                }
                let mid = o + d * (0.5 * (seg.t_min + seg.t_max));
                tighter += usize::from(one_band && seg.sigma_maj[0] < 0.9 * whole(mid));
            }
        }
        assert!(checked > 2000 && tighter > 100, "{checked} points, {tighter} tighter segments");
    }
}
