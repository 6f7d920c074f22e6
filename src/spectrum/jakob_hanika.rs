//! RGB → spectrum by Jakob & Hanika, "A Low-Dimensional Function Space for Efficient Spectral
//! Upsampling", Computer Graphics Forum 38(2), 2019: a reflectance is
//! S(λ) = σ(c₀x² + c₁x + c₂) with the sigmoid σ(t) = ½ + t / (2√(1 + t²)) (eq. 3) and, here,
//! x = (λ − 360 nm) / 470 nm (a normalised wavelength keeps the 3×3 system well conditioned).
//!
//! The coefficients for a target RGB are found by Newton's method on the three equations
//! RGB(c) = target (the paper's Gauss–Newton with as many residuals as unknowns), where RGB(c)
//! is the colour of S lit by the colour space's white, integrated with the same quadrature as
//! `Spectrum::to_xyz`. A coarse table of coefficients (the paper's 3 × res³ layout, built by
//! continuation from grey outwards) gives the starting point; the per-colour refinement then
//! makes the round trip exact to the optimiser tolerance.

use super::cie::{for_each_node, xyz_bar_f64, CIE_LAMBDA_MAX, CIE_LAMBDA_MIN};
use super::sigmoid::{sigmoid, sigmoid_derivative, SigmoidPolynomial, X_SPAN};
use super::spd::Spectrum;
use glam::{DMat3, DVec3};
use rayon::prelude::*;

/// Bound on |cᵢ| during fitting (normalised-wavelength units).
const MAX_COEFF: f64 = 1e5;

/// Quadrature for RGB(c): RGB = Σₖ Wₖ σ(t(xₖ)), with Wₖ = M_XYZ→RGB x̄ȳz̄(λₖ) I(λₖ) wₖ / ∫ I ȳ.
#[derive(Debug)]
pub(crate) struct SigmoidFitter {
    /// Normalised wavelength of each node.
    x: Vec<f64>,
    /// RGB weight of each node.
    w: Vec<DVec3>,
    /// σ sampled every [`SigmoidFitter::HAT_STEP_NM`] and interpolated linearly, integrated
    /// exactly against the fine weights (for building the table and refining many colours
    /// quickly).
    hat_x: Vec<f64>,
    hat_w: Vec<DVec3>,
}

/// Max abs component of `rgb − target`; infinite if anything is NaN (glam's `max_element`
/// would skip a NaN and let a broken state look good).
fn residual(rgb: DVec3, target: DVec3) -> f64 {
    let d = (rgb - target).abs();
    if d.is_finite() {
        d.max_element()
    } else {
        f64::INFINITY
    }
}

/// The product rule for `intervals` equal intervals of x ∈ [0, 1]: node j's weight is
/// Σₖ wₖ hatⱼ(xₖ) over the fine nodes, hatⱼ the piecewise-linear basis function of node j, so
/// Σⱼ σ(xⱼ) Wⱼ is the fine rule applied to σ's linear interpolant.
fn hat_rule(x: &[f64], w: &[DVec3], intervals: usize) -> (Vec<f64>, Vec<DVec3>) {
    let n = intervals.max(1);
    let nodes = (0..=n).map(|j| j as f64 / n as f64).collect();
    let mut weights = vec![DVec3::ZERO; n + 1];
    for (&xk, &wk) in x.iter().zip(w) {
        let s = (xk * n as f64).clamp(0.0, n as f64);
        let j = (s as usize).min(n - 1);
        let f = s - j as f64;
        weights[j] += wk * (1.0 - f);
        weights[j + 1] += wk * f;
    }
    (nodes, weights)
}

/// Result of one fit.
#[derive(Clone, Copy, Debug)]
pub struct Fit {
    /// The coefficients.
    pub poly: SigmoidPolynomial,
    /// Largest |RGB(c) − target| component at the end.
    pub residual: f64,
}

impl SigmoidFitter {
    /// Target accuracy of a fit (max abs linear RGB).
    pub const TOLERANCE: f64 = 1e-7;

    /// The fitter for colours lit by `illum` and taken to RGB by `xyz_to_rgb`.
    pub(crate) fn new(illum: &Spectrum, xyz_to_rgb: DMat3) -> Self {
        let (mut x, mut w) = (Vec::new(), Vec::new());
        let mut y = 0.0;
        for_each_node(CIE_LAMBDA_MIN, CIE_LAMBDA_MAX, &illum.knots(), |l, wt| {
            let xyz = xyz_bar_f64(l) * (illum.eval_f64(l) * wt);
            y += xyz.y;
            x.push((l - CIE_LAMBDA_MIN) / X_SPAN);
            w.push(xyz_to_rgb * xyz);
        });
        w.iter_mut().for_each(|w| *w /= y);
        let (hat_x, hat_w) = hat_rule(&x, &w, (X_SPAN / Self::HAT_STEP_NM).round() as usize);
        Self { x, w, hat_x, hat_w }
    }

    /// RGB of σ(poly) and its Jacobian with respect to the coefficients.
    fn eval(xs: &[f64], ws: &[DVec3], c: [f64; 3]) -> (DVec3, DMat3) {
        let mut rgb = DVec3::ZERO;
        let (mut j0, mut j1, mut j2) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (&x, &w) in xs.iter().zip(ws) {
            let t = (c[0] * x + c[1]) * x + c[2];
            rgb += w * sigmoid(t);
            let d = w * sigmoid_derivative(t);
            j0 += d * (x * x);
            j1 += d * x;
            j2 += d;
        }
        (rgb, DMat3::from_cols(j0, j1, j2))
    }

    /// Damped Newton iterations from `init` towards RGB(c) = `target`.
    fn newton(xs: &[f64], ws: &[DVec3], target: DVec3, init: [f64; 3], iters: usize, tolerance: f64) -> Fit {
        let mut c = init;
        let (mut rgb, mut jac) = Self::eval(xs, ws, c);
        let mut err = residual(rgb, target);
        let mut stalled = 0;
        for _ in 0..iters {
            if err < tolerance {
                break;
            }
            if jac.determinant().abs() < 1e-300 {
                break;
            }
            let delta = jac.inverse() * (target - rgb);
            if !delta.is_finite() {
                break;
            }
            // Backtrack until the residual decreases (keeps the sigmoid out of saturation).
            let mut step = 1.0;
            let mut improved = false;
            for _ in 0..12 {
                let cand = [c[0] + step * delta.x, c[1] + step * delta.y, c[2] + step * delta.z];
                // |c| ≤ 1e5 already gives sub-nm transitions; larger only chases colours no
                // reflectance reaches and would overflow the f32 table.
                if cand.iter().any(|v| v.abs() > MAX_COEFF) {
                    step *= 0.5;
                    continue;
                }
                let (r2, j2) = Self::eval(xs, ws, cand);
                let e2 = residual(r2, target);
                if e2 < err {
                    // Out-of-gamut targets creep towards the boundary forever: give up
                    // after three steps that gain less than 1 %.
                    stalled = if e2 > 0.99 * err { stalled + 1 } else { 0 };
                    c = cand;
                    rgb = r2;
                    jac = j2;
                    err = e2;
                    improved = true;
                    break;
                }
                step *= 0.5;
            }
            if !improved || stalled >= 3 {
                break;
            }
        }
        Fit { poly: SigmoidPolynomial { c }, residual: err }
    }

    /// Fits σ(poly) to `target` (each component in [0, 1]) starting from `init`; if that
    /// stalls, walks from the grey of the same mean to the target in small steps
    /// (continuation), as the paper does when building its table.
    pub fn fit(&self, target: DVec3, init: SigmoidPolynomial) -> Fit {
        let first = Self::newton(&self.x, &self.w, target, init.c, 50, Self::TOLERANCE);
        if first.residual < Self::TOLERANCE {
            return first;
        }
        let grey = DVec3::splat(target.element_sum() / 3.0);
        let mut c = SigmoidPolynomial::flat(grey.x).c;
        let steps = 16;
        let mut last = first;
        for k in 1..=steps {
            let s = k as f64 / steps as f64;
            last = Self::newton(&self.x, &self.w, grey + (target - grey) * s, c, 50, Self::TOLERANCE);
            c = last.poly.c;
        }
        if last.residual < first.residual {
            last
        } else {
            first
        }
    }

    /// Node spacing of the product rule of [`SigmoidFitter::fit_fast`] [nm].
    pub const HAT_STEP_NM: f64 = 5.0;

    /// Newton from `init` on the product rule (95 nodes instead of the fine rule's ~1400): the
    /// rule replaces σ by its piecewise-linear interpolant, an error of h²/8 · max |σ''| in
    /// each channel, far below the table's for the smooth sigmoids of moderate colours.
    pub fn fit_fast(&self, target: DVec3, init: SigmoidPolynomial) -> Fit {
        Self::newton(&self.hat_x, &self.hat_w, target, init.c, 20, 1e-6)
    }

    /// Newton on the product rule for the table (a starting point only, so a looser tolerance).
    fn fit_coarse(&self, target: DVec3, init: [f64; 3]) -> [f64; 3] {
        Self::newton(&self.hat_x, &self.hat_w, target, init, 15, 1e-5).poly.c
    }
}

/// The Jakob–Hanika coefficient table of one colour space: for each of the 3 choices of the
/// largest RGB component, `res`³ cells over (z = largest component, remapped by a double
/// smoothstep to crowd the dark end; x, y = the other two divided by z).
#[derive(Clone, Debug)]
pub struct RgbToSpectrumTable {
    res: usize,
    /// z value of each z cell.
    z_nodes: Vec<f64>,
    /// Coefficients, laid out [max component][z][y][x].
    coeffs: Vec<[f32; 3]>,
}

fn smoothstep(x: f64) -> f64 {
    x * x * (3.0 - 2.0 * x)
}

impl RgbToSpectrumTable {
    /// Resolution used for the tables built on first use (see docs/colour.md).
    pub const DEFAULT_RES: usize = 16;

    /// Builds the table by continuation along z from z = z[res/5] (pbrt-v4's
    /// `rgb2spec_opt` schedule), in parallel over (component, x, y).
    pub(crate) fn build(fitter: &SigmoidFitter, res: usize) -> Self {
        let res = res.max(3);
        let z_nodes: Vec<f64> = (0..res).map(|i| smoothstep(smoothstep(i as f64 / (res - 1) as f64))).collect();
        let columns: Vec<Vec<[f32; 3]>> = (0..3 * res * res)
            .into_par_iter()
            .map(|k| {
                let l = k / (res * res);
                let yi = (k / res) % res;
                let xi = k % res;
                let x = xi as f64 / (res - 1) as f64;
                let y = yi as f64 / (res - 1) as f64;
                let target = |z: f64| {
                    let mut v = [0.0; 3];
                    v[l] = z;
                    v[(l + 1) % 3] = x * z;
                    v[(l + 2) % 3] = y * z;
                    DVec3::from_array(v)
                };
                let mut col = vec![[0.0f32; 3]; res];
                let start = res / 5;
                let mut c = [0.0; 3];
                for zi in start..res {
                    c = fitter.fit_coarse(target(z_nodes[zi]), c);
                    col[zi] = c.map(|v| v as f32);
                }
                c = col[start].map(|v| v as f64);
                for zi in (0..start).rev() {
                    c = fitter.fit_coarse(target(z_nodes[zi]), c);
                    col[zi] = c.map(|v| v as f32);
                }
                col
            })
            .collect();
        let mut coeffs = vec![[0.0f32; 3]; 3 * res * res * res];
        for (k, col) in columns.into_iter().enumerate() {
            let l = k / (res * res);
            let yi = (k / res) % res;
            let xi = k % res;
            for (zi, c) in col.into_iter().enumerate() {
                coeffs[((l * res + zi) * res + yi) * res + xi] = c;
            }
        }
        Self { res, z_nodes, coeffs }
    }

    /// Resolution per axis.
    pub fn resolution(&self) -> usize {
        self.res
    }

    /// Trilinearly interpolated coefficients for an RGB in [0, 1]³ (the fast path, no
    /// refinement: accuracy in docs/colour.md).
    pub fn lookup(&self, rgb: [f64; 3]) -> SigmoidPolynomial {
        let rgb = rgb.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 });
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return SigmoidPolynomial::flat(rgb[0]);
        }
        let l = if rgb[0] >= rgb[1] && rgb[0] >= rgb[2] {
            0
        } else if rgb[1] >= rgb[2] {
            1
        } else {
            2
        };
        let z = rgb[l];
        let n = (self.res - 1) as f64;
        let x = rgb[(l + 1) % 3] / z * n;
        let y = rgb[(l + 2) % 3] / z * n;
        let zi = self.z_nodes.partition_point(|&v| v <= z).clamp(1, self.res - 1) - 1;
        let xi = (x as usize).min(self.res - 2);
        let yi = (y as usize).min(self.res - 2);
        let dx = x - xi as f64;
        let dy = y - yi as f64;
        let dz = (z - self.z_nodes[zi]) / (self.z_nodes[zi + 1] - self.z_nodes[zi]);
        let mut c = [0.0f64; 3];
        for (oz, wz) in [(0, 1.0 - dz), (1, dz)] {
            for (oy, wy) in [(0, 1.0 - dy), (1, dy)] {
                for (ox, wx) in [(0, 1.0 - dx), (1, dx)] {
                    let idx = ((l * self.res + zi + oz) * self.res + yi + oy) * self.res + xi + ox;
                    let v = self.coeffs[idx];
                    for k in 0..3 {
                        c[k] += wz * wy * wx * v[k] as f64;
                    }
                }
            }
        }
        if c.iter().all(|v| v.is_finite()) {
            SigmoidPolynomial { c }
        } else {
            SigmoidPolynomial::flat((rgb[0] + rgb[1] + rgb[2]) / 3.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{fit_albedo_fast, ColorSpace};

    /// Linear RGB of σ(poly) under the space's white, by the fine rule.
    fn round_trip(poly: SigmoidPolynomial, cs: &ColorSpace) -> DVec3 {
        SigmoidFitter::eval(&cs.fitter().x, &cs.fitter().w, poly.c).0
    }

    #[test]
    fn fast_fit_round_trip_is_close_to_the_full_fit() {
        let cs = ColorSpace::srgb();
        let (mut worst_fast, mut worst_table) = (0.0f64, 0.0f64);
        let n = 9;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let rgb = [i, j, k].map(|v| (v as f64 + 0.5) / n as f64);
                    let target = DVec3::from_array(rgb);
                    let fast = round_trip(fit_albedo_fast(rgb, cs), cs);
                    let table = round_trip(cs.rgb_to_spectrum_table().lookup(rgb), cs);
                    worst_fast = worst_fast.max((fast - target).abs().max_element());
                    worst_table = worst_table.max((table - target).abs().max_element());
                }
            }
        }
        assert!(worst_fast < 1e-3, "fast fit off by {worst_fast} (table {worst_table})");
        assert!(worst_fast < 0.1 * worst_table, "fast {worst_fast} vs table {worst_table}");
    }

    #[test]
    #[ignore = "timing probe: cargo test --no-default-features --lib table_build_time -- --ignored --nocapture"]
    fn table_build_time() {
        for n in ColorSpace::names() {
            let f = ColorSpace::by_name(n).unwrap().fitter();
            let t0 = std::time::Instant::now();
            let _ = RgbToSpectrumTable::build(f, 16);
            println!("{n} res 16: {:?}", t0.elapsed());
        }
    }

    #[test]
    fn sigmoid_limits_and_derivative() {
        assert_eq!(sigmoid(0.0), 0.5);
        assert_eq!(sigmoid(f64::INFINITY), 1.0);
        assert_eq!(sigmoid(f64::NEG_INFINITY), 0.0);
        for t in [-3.0, -0.5, 0.2, 4.0] {
            let h = 1e-6;
            let fd = (sigmoid(t + h) - sigmoid(t - h)) / (2.0 * h);
            assert!((fd - sigmoid_derivative(t)).abs() < 1e-8);
        }
    }

    #[test]
    fn coefficients_in_nm_give_the_same_function() {
        let p = SigmoidPolynomial { c: [3.0, -2.5, 0.4] };
        let n = p.coefficients_nm();
        for l in [380.0, 555.0, 700.0] {
            let t = n[0] * l * l + n[1] * l + n[2];
            assert!((sigmoid(t) - p.eval_f64(l)).abs() < 1e-9);
        }
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let cs = ColorSpace::srgb();
        let f = cs.fitter();
        let c = [1.5, -2.0, 0.3];
        let (_, j) = SigmoidFitter::eval(&f.x, &f.w, c);
        for k in 0..3 {
            let h = 1e-6;
            let mut a = c;
            let mut b = c;
            a[k] += h;
            b[k] -= h;
            let fd = (SigmoidFitter::eval(&f.x, &f.w, a).0 - SigmoidFitter::eval(&f.x, &f.w, b).0) / (2.0 * h);
            assert!((fd - j.col(k)).abs().max_element() < 1e-7, "{k}");
        }
    }
}
