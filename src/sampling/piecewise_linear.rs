//! A bilinearly interpolated density on [0, 1]² that depends on `N` more parameters, sampled by
//! inverting its marginal (in y) and then its conditional (in x) continuously (Dupuy & Jakob
//! 2018, "An Adaptive Parameterization for Efficient Material Acquisition and Rendering", §5;
//! the `PiecewiseLinear2D` of pbrt-v4 and `Marginal2D` of Mitsuba 3, whose data layout and
//! normalisation this follows so that RGL files mean the same).
//!
//! The data holds values at the vertices of an `nx` × `ny` grid for every combination of the
//! parameters' tabulated values (C order: parameter 0 slowest, then y, then x). Between
//! parameter values every quantity — values, CDFs — is interpolated multilinearly, which, as each
//! slice is normalised on its own, keeps the interpolated density normalised and its CDFs exact.
//!
//! In grid units (X = x(nx − 1)), row j integrates to R_j = Σ_i (v_ij + v_i+1,j)/2; between rows
//! the row integral is linear, (1 − t)R_j + tR_j+1, so the marginal CDF inside a row band is
//! quadratic in t and inverted in closed form; the conditional at that fractional row is the
//! same linear blend of the two rows' CDFs, quadratic inside a column.

use glam::Vec2;

/// Why a table cannot be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TableError {
    /// Fewer than 2 vertices along an axis.
    #[error("a {0} × {1} grid; at least 2 × 2 is required")]
    TooSmall(usize, usize),
    /// Data of the wrong length.
    #[error("{found} values for {expected} (grid × parameter values)")]
    Length {
        /// Values given.
        found: usize,
        /// Values needed.
        expected: usize,
    },
    /// Parameter values empty, not finite or not increasing.
    #[error("parameter {0}'s values must be finite and increasing, and there must be at least one")]
    Parameter(usize),
}

/// A sample (or an inverted point) and the density there (per unit area of [0, 1]²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlSample {
    /// The point.
    pub p: Vec2,
    /// The density at `p` (or, from [`PiecewiseLinear2D::invert`], at the point inverted).
    pub pdf: f32,
}

/// The 2^N slices (and weights) a parameter point interpolates between.
struct Corners {
    slice: [usize; 8],
    weight: [f32; 8],
    n: usize,
}

/// The table. `N` ≤ 3 parameters.
#[derive(Clone, Debug)]
pub struct PiecewiseLinear2D<const N: usize> {
    nx: usize,
    ny: usize,
    params: [Vec<f32>; N],
    /// Slice stride of each parameter.
    strides: [usize; N],
    data: Vec<f32>,
    /// Per slice, per row, the conditional CDF at each vertex (grid units, normalised).
    conditional: Vec<f32>,
    /// Per slice, the marginal CDF at each row.
    marginal: Vec<f32>,
    /// Density per stored value: the number of cells when normalised (the slices then sum to
    /// 1 in grid units), 1 for data kept as given.
    scale: f32,
}

/// The first index i in [0, n − 2] with `pred(i + 1)` false (pbrt-v4's `FindInterval`).
fn find_interval(n: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0usize, n);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if pred(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo.saturating_sub(1).min(n.saturating_sub(2))
}

impl<const N: usize> PiecewiseLinear2D<N> {
    /// A table of `data` on an `nx` × `ny` grid per parameter combination. `normalize` rescales
    /// each slice to integrate to 1; `build_cdf` (which implies it) prepares sampling and
    /// inversion, and then negative values count as 0 and a slice that integrates to 0 becomes
    /// uniform.
    pub fn new(
        data: &[f32],
        nx: usize,
        ny: usize,
        params: [Vec<f32>; N],
        normalize: bool,
        build_cdf: bool,
    ) -> Result<Self, TableError> {
        assert!(N <= 3, "at most 3 parameters");
        if nx < 2 || ny < 2 {
            return Err(TableError::TooSmall(nx, ny));
        }
        let mut strides = [0usize; N];
        let mut slices = 1usize;
        for d in (0..N).rev() {
            let v = &params[d];
            if v.is_empty() || v.iter().any(|x| !x.is_finite()) || v.windows(2).any(|w| w[0] >= w[1]) {
                return Err(TableError::Parameter(d));
            }
            strides[d] = slices;
            slices = slices.saturating_mul(v.len());
        }
        let n = nx * ny;
        let expected = slices.saturating_mul(n);
        if data.len() != expected {
            return Err(TableError::Length { found: data.len(), expected });
        }
        let cells = ((nx - 1) * (ny - 1)) as f32;
        let scale = if normalize || build_cdf { cells } else { 1.0 };
        let (conditional, marginal) = (Vec::new(), Vec::new());
        let mut t = Self { nx, ny, params, strides, data: data.to_vec(), conditional, marginal, scale };
        if build_cdf {
            t.conditional = vec![0.0; expected];
            t.marginal = vec![0.0; slices * ny];
            for s in 0..slices {
                t.build_slice(s);
            }
        } else if normalize {
            for slice in t.data.chunks_exact_mut(n) {
                // In grid units ∫ bilinear = Σ cells (mean of 4 corners).
                let mut sum = 0.0f64;
                for y in 0..ny - 1 {
                    for x in 0..nx - 1 {
                        let i = y * nx + x;
                        sum += 0.25 * (slice[i] + slice[i + 1] + slice[i + nx] + slice[i + nx + 1]) as f64;
                    }
                }
                slice.iter_mut().for_each(|v| *v = (*v as f64 / sum) as f32);
            }
        }
        Ok(t)
    }

    /// Conditional and marginal CDFs of slice `s`, normalised with its data.
    fn build_slice(&mut self, s: usize) {
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let d = &mut self.data[s * n..(s + 1) * n];
        d.iter_mut().for_each(|v| *v = if v.is_finite() { v.max(0.0) } else { 0.0 });
        let mut total = 0.0f64;
        let mut prev_row = 0.0f64;
        let mut marginal = vec![0.0f64; ny];
        let mut conditional = vec![0.0f64; n];
        for y in 0..ny {
            let mut sum = 0.0f64;
            for x in 0..nx - 1 {
                sum += 0.5 * (d[y * nx + x] as f64 + d[y * nx + x + 1] as f64);
                conditional[y * nx + x + 1] = sum;
            }
            if y > 0 {
                total += 0.5 * (prev_row + sum);
                marginal[y] = total;
            }
            prev_row = sum;
        }
        if !(total > 0.0 && total.is_finite()) {
            // No information: uniform.
            d.iter_mut().for_each(|v| *v = 1.0);
            return self.build_slice_uniform(s);
        }
        let inv = 1.0 / total;
        d.iter_mut().for_each(|v| *v = (*v as f64 * inv) as f32);
        for (o, c) in self.conditional[s * n..(s + 1) * n].iter_mut().zip(&conditional) {
            *o = (c * inv) as f32;
        }
        for (o, m) in self.marginal[s * ny..(s + 1) * ny].iter_mut().zip(&marginal) {
            *o = (m * inv) as f32;
        }
    }

    fn build_slice_uniform(&mut self, s: usize) {
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let v = 1.0 / ((nx - 1) * (ny - 1)) as f32;
        self.data[s * n..(s + 1) * n].iter_mut().for_each(|d| *d = v);
        for y in 0..ny {
            for x in 0..nx {
                self.conditional[s * n + y * nx + x] = x as f32 * v;
            }
            self.marginal[s * ny + y] = y as f32 / (ny - 1) as f32;
        }
    }

    /// Grid resolution (nx, ny).
    pub fn resolution(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The slices around `param` and their weights (clamped to the tabulated range).
    fn corners(&self, param: &[f32; N]) -> Corners {
        let mut c = Corners { slice: [0; 8], weight: [0.0; 8], n: 1 };
        c.weight[0] = 1.0;
        for (d, (v, &p)) in self.params.iter().zip(param).enumerate() {
            if v.len() == 1 {
                continue;
            }
            let p = if p.is_nan() { v[0] } else { p };
            let i = find_interval(v.len(), |k| v[k] <= p);
            let w1 = ((p - v[i]) / (v[i + 1] - v[i])).clamp(0.0, 1.0);
            for k in 0..c.n {
                c.slice[k + c.n] = c.slice[k] + (i + 1) * self.strides[d];
                c.weight[k + c.n] = c.weight[k] * w1;
                c.slice[k] += i * self.strides[d];
                c.weight[k] *= 1.0 - w1;
            }
            c.n *= 2;
        }
        c
    }

    /// Σ over corner slices of weight × `table[slice × len + index]`.
    #[inline]
    fn lookup(table: &[f32], c: &Corners, len: usize, index: usize) -> f32 {
        (0..c.n).map(|k| c.weight[k] * table[c.slice[k] * len + index]).sum()
    }

    /// Bilinear interpolation at `p` ∈ [0, 1]² (clamped): the normalised density, or the data
    /// as given when the table was built without normalisation.
    pub fn eval(&self, p: Vec2, param: &[f32; N]) -> f32 {
        let c = self.corners(param);
        let n = self.nx * self.ny;
        let (i, w) = self.cell(p);
        let v = |k: usize| Self::lookup(&self.data, &c, n, k);
        let (v00, v10, v01, v11) = (v(i), v(i + 1), v(i + self.nx), v(i + self.nx + 1));
        let r = (1.0 - w.y) * ((1.0 - w.x) * v00 + w.x * v10) + w.y * ((1.0 - w.x) * v01 + w.x * v11);
        r * self.scale
    }

    /// The vertex index of the cell holding `p` and the position inside it.
    fn cell(&self, p: Vec2) -> (usize, Vec2) {
        let g = Vec2::new(
            if p.x.is_nan() { 0.0 } else { p.x.clamp(0.0, 1.0) } * (self.nx - 1) as f32,
            if p.y.is_nan() { 0.0 } else { p.y.clamp(0.0, 1.0) } * (self.ny - 1) as f32,
        );
        let (cx, cy) = ((g.x as usize).min(self.nx - 2), (g.y as usize).min(self.ny - 2));
        (cy * self.nx + cx, g - Vec2::new(cx as f32, cy as f32))
    }

    /// Warps `u` ∈ [0, 1]² to the density (y by the marginal, then x by the conditional).
    /// Needs a table built with `build_cdf`.
    pub fn sample(&self, u: Vec2, param: &[f32; N]) -> PlSample {
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let c = self.corners(param);
        let mut u = u.clamp(Vec2::splat(f32::EPSILON), Vec2::splat(1.0 - f32::EPSILON));
        if u.is_nan() {
            u = Vec2::splat(0.5);
        }
        // Row band: the marginal CDF, then the quadratic inside it.
        let marginal = |j: usize| Self::lookup(&self.marginal, &c, ny, j);
        let row = find_interval(ny, |j| marginal(j) < u.y);
        let dy = u.y - marginal(row);
        let cond = |k: usize| Self::lookup(&self.conditional, &c, n, k);
        let (r0, r1) = (cond(row * nx + nx - 1), cond((row + 1) * nx + nx - 1));
        let t = solve_linear_density(r0, r1, dy);
        // Column: the conditional at the fractional row, then the quadratic inside the cell.
        let blend = |k: usize| (1.0 - t) * cond(row * nx + k) + t * cond((row + 1) * nx + k);
        let target = u.x * ((1.0 - t) * r0 + t * r1);
        let col = find_interval(nx, |k| blend(k) < target);
        let dx = target - blend(col);
        let v = |k: usize| Self::lookup(&self.data, &c, n, k);
        let i = row * nx + col;
        let c0 = (1.0 - t) * v(i) + t * v(i + nx);
        let c1 = (1.0 - t) * v(i + 1) + t * v(i + nx + 1);
        let s = solve_linear_density(c0, c1, dx);
        let p = Vec2::new((col as f32 + s) / (nx - 1) as f32, (row as f32 + t) / (ny - 1) as f32);
        PlSample { p, pdf: ((1.0 - s) * c0 + s * c1) * self.scale }
    }

    /// The inverse of [`Self::sample`]: the `u` that maps to `p`, with the density at `p`.
    pub fn invert(&self, p: Vec2, param: &[f32; N]) -> PlSample {
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let c = self.corners(param);
        let (i, w) = self.cell(p);
        let row = i / nx;
        let v = |k: usize| Self::lookup(&self.data, &c, n, k);
        let c0 = (1.0 - w.y) * v(i) + w.y * v(i + nx);
        let c1 = (1.0 - w.y) * v(i + 1) + w.y * v(i + nx + 1);
        let pdf = ((1.0 - w.x) * c0 + w.x * c1) * self.scale;
        let cond = |k: usize| Self::lookup(&self.conditional, &c, n, k);
        // x: the CDF up to the column at this fractional row, plus the part of the cell.
        let x = w.x * (c0 + 0.5 * w.x * (c1 - c0)) + (1.0 - w.y) * cond(i) + w.y * cond(i + nx);
        let (r0, r1) = (cond(row * nx + nx - 1), cond((row + 1) * nx + nx - 1));
        let row_total = (1.0 - w.y) * r0 + w.y * r1;
        let ux = if row_total > 0.0 { x / row_total } else { 0.0 };
        let uy = w.y * (r0 + 0.5 * w.y * (r1 - r0)) + Self::lookup(&self.marginal, &c, ny, row);
        PlSample { p: Vec2::new(ux, uy), pdf }
    }
}

/// The t ∈ [0, 1] with ∫₀ᵗ ((1 − s)a + s b) ds = `area` for a linear density from a to b:
/// a t + (b − a) t²/2 = area, as t = 2 area / (a + √(a² + 2 area (b − a))), the root in a form
/// that does not cancel when a ≈ b (pbrt-v4's (a − √…)/(a − b) loses digits there).
#[inline]
fn solve_linear_density(a: f32, b: f32, area: f32) -> f32 {
    let t = 2.0 * area / (a + (a * a + 2.0 * area * (b - a)).max(0.0).sqrt());
    if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::{Chi2Test, Domain};
    use crate::sampling::Rng;
    use glam::Vec3;

    /// A lumpy table: 5 × 4 values for each of 3 × 2 parameter values, none alike.
    fn table() -> PiecewiseLinear2D<2> {
        let mut rng = Rng::new(3, 4);
        let data: Vec<f32> = (0..3 * 2 * 5 * 4).map(|_| 0.05 + rng.uniform() * rng.uniform() * 4.0).collect();
        PiecewiseLinear2D::new(&data, 5, 4, [vec![0.0, 1.0, 3.0], vec![-1.0, 2.0]], true, true).unwrap()
    }

    /// The density by its definition: the bilinear interpolant of each corner slice's data,
    /// normalised by brute-force midpoint quadrature, then blended — independent of the CDFs.
    fn reference_pdf(raw: &[f32], nx: usize, ny: usize, slices: &[(usize, f32)], p: Vec2) -> f64 {
        let bilinear = |s: usize, p: Vec2| {
            let g = Vec2::new(p.x * (nx - 1) as f32, p.y * (ny - 1) as f32);
            let (cx, cy) = ((g.x as usize).min(nx - 2), (g.y as usize).min(ny - 2));
            let (fx, fy) = (g.x as f64 - cx as f64, g.y as f64 - cy as f64);
            let at = |x: usize, y: usize| raw[s * nx * ny + y * nx + x] as f64;
            (1.0 - fy) * ((1.0 - fx) * at(cx, cy) + fx * at(cx + 1, cy))
                + fy * ((1.0 - fx) * at(cx, cy + 1) + fx * at(cx + 1, cy + 1))
        };
        let m = 400;
        slices
            .iter()
            .map(|&(s, w)| {
                let mut integral = 0.0;
                for j in 0..m {
                    for i in 0..m {
                        let q = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                        integral += bilinear(s, q);
                    }
                }
                w as f64 * bilinear(s, p) / (integral / (m * m) as f64)
            })
            .sum()
    }

    #[test]
    fn eval_is_the_blend_of_normalised_bilinear_slices() {
        let mut rng = Rng::new(3, 4);
        let raw: Vec<f32> = (0..3 * 2 * 5 * 4).map(|_| 0.05 + rng.uniform() * rng.uniform() * 4.0).collect();
        let t = table();
        // Parameters (2.0, 0.5): 1/2 of the way from 1 to 3, 1/2 from −1 to 2. Slices are
        // index0 × 2 + index1.
        let slices = [(2, 0.25), (3, 0.25), (4, 0.25), (5, 0.25)];
        for p in [Vec2::new(0.1, 0.2), Vec2::new(0.77, 0.9), Vec2::new(0.5, 0.0)] {
            let (got, want) = (t.eval(p, &[2.0, 0.5]), reference_pdf(&raw, 5, 4, &slices, p));
            assert!((got as f64 - want).abs() < 1e-4 * want, "{p}: {got} vs {want}");
        }
        // Unnormalised, eval is the data itself at a vertex.
        let u = PiecewiseLinear2D::<0>::new(&raw[..20], 5, 4, [], false, false).unwrap();
        assert_eq!(u.eval(Vec2::new(0.25, 1.0 / 3.0), &[]), raw[5 + 1]);
    }

    #[test]
    fn sample_matches_its_density_chi2() {
        let t = table();
        for param in [[0.0f32, -1.0], [2.0, 0.5], [2.9, 1.7], [5.0, -3.0]] {
            let test = Chi2Test {
                domain: Domain::Plane { min: Vec2::ZERO, max: Vec2::ONE },
                theta_res: 40,
                phi_res: 40,
                sample_count: 200_000,
                test_count: 4,
                ..Chi2Test::default()
            };
            let r = test.run(
                |_, u| {
                    let s = t.sample(u, &param);
                    Some(Vec3::new(s.p.x, s.p.y, 0.0))
                },
                |w| t.eval(w.truncate(), &param),
            );
            assert!(r.passed, "{param:?}: {r}");
        }
    }

    #[test]
    fn invert_undoes_sample_and_reports_the_same_pdf() {
        let t = table();
        let mut rng = Rng::new(9, 1);
        let mut worst = 0.0f32;
        for k in 0..20_000 {
            let param = [rng.uniform() * 4.0 - 0.5, rng.uniform() * 4.0 - 1.5];
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let s = t.sample(u, &param);
            let back = t.invert(s.p, &param);
            worst = worst.max((back.p - u).abs().max_element());
            assert!((back.pdf - s.pdf).abs() <= 1e-4 * s.pdf, "{k}: {} vs {}", back.pdf, s.pdf);
            assert!((t.eval(s.p, &param) - s.pdf).abs() <= 1e-4 * s.pdf);
        }
        assert!(worst < 2e-5, "inverse(sample(u)) − u up to {worst}");
    }

    #[test]
    fn bad_tables_are_errors_and_zero_slices_uniform() {
        let e = |r: Result<PiecewiseLinear2D<1>, TableError>| r.err();
        assert_eq!(
            e(PiecewiseLinear2D::new(&[1.0; 4], 1, 4, [vec![0.0]], true, true)),
            Some(TableError::TooSmall(1, 4))
        );
        assert_eq!(
            e(PiecewiseLinear2D::new(&[1.0; 7], 2, 2, [vec![0.0, 1.0]], true, true)),
            Some(TableError::Length { found: 7, expected: 8 })
        );
        assert_eq!(
            e(PiecewiseLinear2D::new(&[1.0; 8], 2, 2, [vec![1.0, 0.0]], true, true)),
            Some(TableError::Parameter(0))
        );
        assert_eq!(e(PiecewiseLinear2D::new(&[1.0; 4], 2, 2, [vec![]], true, true)), Some(TableError::Parameter(0)));
        let z = PiecewiseLinear2D::<0>::new(&[0.0, -1.0, f32::NAN, 0.0], 2, 2, [], true, true).unwrap();
        let s = z.sample(Vec2::new(0.3, 0.6), &[]);
        assert!((s.p - Vec2::new(0.3, 0.6)).length() < 1e-6 && (s.pdf - 1.0).abs() < 1e-6, "{s:?}");
    }
}
