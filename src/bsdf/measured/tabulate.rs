//! Tabulates an analytic isotropic BRDF into the fields of an RGL `.bsdf` file (Dupuy & Jakob
//! 2018, §4–5), from the model's formulas alone: D, σ and f are evaluated in f64, and the
//! visible normals' warp that places the `spectra` samples is inverted numerically on a fine
//! grid (its own quadrature, not [`crate::sampling::piecewise_linear`]). What prism's reader
//! then does with the file is checked against the same formulas (`bsdf/tests/measured.rs`,
//! `tests/suite/measured.rs`).

use super::tensor_file::{Field, TensorFile};
use glam::DVec3;
use std::f64::consts::PI;

/// An isotropic BRDF with a microfacet distribution: what the file tabulates.
pub trait AnalyticBrdf {
    /// D(θ_m) [1/sr] of the normals' distribution, from cos θ_m.
    fn ndf(&self, cos_theta: f64) -> f64;
    /// σ(ω) = ∫ D(ω_m) ⟨ω·ω_m⟩ dω_m, from cos θ.
    fn sigma(&self, cos_theta: f64) -> f64;
    /// f(ω₁, ω₂) [1/sr] at wavelength `lambda` [nm], both directions above the surface.
    fn f(&self, w1: DVec3, w2: DVec3, lambda: f64) -> f64;
}

/// A quantity linear in wavelength: (value at 360 nm, value at 830 nm).
pub type Linear = (f64, f64);

fn at(l: Linear, lambda: f64) -> f64 {
    l.0 + (l.1 - l.0) * (lambda - 360.0) / (830.0 - 360.0)
}

/// GGX (Trowbridge–Reitz) D for roughness α.
pub fn ggx_d(alpha: f64, cos_theta: f64) -> f64 {
    let a2 = alpha * alpha;
    let c2 = cos_theta * cos_theta;
    a2 / (PI * (c2 * (a2 - 1.0) + 1.0).powi(2))
}

/// Smith's Λ of GGX (Heitz 2014, eq. 86), from cos θ.
pub fn ggx_lambda(alpha: f64, cos_theta: f64) -> f64 {
    let c2 = cos_theta * cos_theta;
    let tan2 = (1.0 - c2).max(0.0) / c2;
    0.5 * ((1.0 + alpha * alpha * tan2).sqrt() - 1.0)
}

/// σ(ω) of GGX: cos θ (1 + Λ) = (cos θ + √(cos²θ + α² sin²θ)) / 2.
pub fn ggx_sigma(alpha: f64, cos_theta: f64) -> f64 {
    let c2 = cos_theta * cos_theta;
    0.5 * (cos_theta + (c2 + alpha * alpha * (1.0 - c2).max(0.0)).sqrt())
}

/// Fresnel reflectance of a conductor η + ik at cos θ (the complex Fresnel equations).
pub fn fresnel_conductor(cos_i: f64, eta: f64, k: f64) -> f64 {
    #[derive(Clone, Copy)]
    struct C(f64, f64);
    let mul = |a: C, b: C| C(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let div = |a: C, b: C| {
        let d = b.0 * b.0 + b.1 * b.1;
        C((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
    };
    let sqrt = |a: C| {
        let r = (a.0 * a.0 + a.1 * a.1).sqrt();
        let re = ((r + a.0) / 2.0).sqrt();
        let im = ((r - a.0) / 2.0).max(0.0).sqrt().copysign(a.1);
        C(re, im)
    };
    let n = C(eta, k);
    let sin2_i = 1.0 - cos_i * cos_i;
    let sin2_t = div(C(sin2_i, 0.0), mul(n, n));
    let cos_t = sqrt(C(1.0 - sin2_t.0, -sin2_t.1));
    let ci = C(cos_i, 0.0);
    let n_ct = mul(n, cos_t);
    let n_ci = mul(n, ci);
    let rs = div(C(ci.0 - n_ct.0, -n_ct.1), C(ci.0 + n_ct.0, n_ct.1));
    let rp = div(C(n_ci.0 - cos_t.0, n_ci.1 - cos_t.1), C(n_ci.0 + cos_t.0, n_ci.1 + cos_t.1));
    0.5 * (rs.0 * rs.0 + rs.1 * rs.1 + rp.0 * rp.0 + rp.1 * rp.1)
}

/// A rough conductor: GGX α, complex index η + ik linear in λ, height-correlated Smith G₂.
#[derive(Clone, Copy, Debug)]
pub struct GgxConductor {
    /// Roughness α.
    pub alpha: f64,
    /// η at 360 and 830 nm.
    pub eta: Linear,
    /// k at 360 and 830 nm.
    pub k: Linear,
}

impl AnalyticBrdf for GgxConductor {
    fn ndf(&self, c: f64) -> f64 {
        ggx_d(self.alpha, c)
    }
    fn sigma(&self, c: f64) -> f64 {
        ggx_sigma(self.alpha, c)
    }
    fn f(&self, w1: DVec3, w2: DVec3, lambda: f64) -> f64 {
        let m = (w1 + w2).normalize();
        let g2 = 1.0 / (1.0 + ggx_lambda(self.alpha, w1.z) + ggx_lambda(self.alpha, w2.z));
        let fr = fresnel_conductor(w1.dot(m).abs(), at(self.eta, lambda), at(self.k, lambda));
        fr * ggx_d(self.alpha, m.z) * g2 / (4.0 * w1.z * w2.z)
    }
}

/// A Lambertian surface ρ(λ)/π, tabulated over the GGX α = 1 distribution (D = 1/π,
/// σ = (1 + cos θ)/2), whose visible normals then spread the samples over the hemisphere.
#[derive(Clone, Copy, Debug)]
pub struct Lambertian {
    /// ρ at 360 and 830 nm.
    pub rho: Linear,
}

impl AnalyticBrdf for Lambertian {
    fn ndf(&self, c: f64) -> f64 {
        ggx_d(1.0, c)
    }
    fn sigma(&self, c: f64) -> f64 {
        ggx_sigma(1.0, c)
    }
    fn f(&self, _: DVec3, _: DVec3, lambda: f64) -> f64 {
        at(self.rho, lambda) / PI
    }
}

/// Where the file samples the model.
#[derive(Clone, Debug)]
pub struct Grid {
    /// Incident zenith angles [rad], increasing.
    pub theta_i: Vec<f32>,
    /// Wavelengths [nm], increasing.
    pub wavelengths: Vec<f32>,
    /// Vertices per axis of `ndf` and `sigma`.
    pub ndf_res: usize,
    /// Vertices per axis of `vndf`, `luminance` and `spectra`.
    pub sample_res: usize,
    /// Cells per axis of the quadrature that inverts the warp.
    pub warp_res: usize,
}

impl Grid {
    /// `n_theta` incident angles evenly spaced in θ over [0°, 89°], wavelengths every
    /// `dlambda` nm over [360, 830], and the given resolutions.
    pub fn regular(n_theta: usize, dlambda: f32, ndf_res: usize, sample_res: usize) -> Self {
        let theta_i = (0..n_theta).map(|k| (89.0f32 * k as f32 / (n_theta - 1) as f32).to_radians()).collect();
        let n_lambda = ((830.0 - 360.0) / dlambda).round() as usize + 1;
        let wavelengths = (0..n_lambda).map(|k| 360.0 + (830.0 - 360.0) * k as f32 / (n_lambda - 1) as f32).collect();
        Self { theta_i, wavelengths, ndf_res, sample_res, warp_res: 1024 }
    }
}

/// The direction at (u_θ, u_φ): θ = u_θ² π/2, φ = (2u_φ − 1)π.
fn dir_of_u(x: f64, y: f64) -> DVec3 {
    let (theta, phi) = (x * x * PI / 2.0, (2.0 * y - 1.0) * PI);
    DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
}

/// The visible normals' density in (u_θ, u_φ) seen from `w1`: D_ω₁(ω_m) × 2π² u_θ sin θ_m.
fn vndf_u<B: AnalyticBrdf>(b: &B, w1: DVec3, sigma1: f64, x: f64, y: f64) -> f64 {
    let m = dir_of_u(x, y);
    let sin_m = (m.x * m.x + m.y * m.y).sqrt();
    b.ndf(m.z) * w1.dot(m).max(0.0) / sigma1 * 2.0 * PI * PI * x * sin_m
}

/// Trapezoid cumulative integral of `values` on [0, 1] (normalised to end at 1).
fn cumulative(values: &[f64]) -> Vec<f64> {
    let h = 1.0 / (values.len() - 1) as f64;
    let mut c = vec![0.0; values.len()];
    for i in 1..values.len() {
        c[i] = c[i - 1] + 0.5 * h * (values[i - 1] + values[i]);
    }
    let total = c[values.len() - 1];
    c.iter_mut().for_each(|v| *v /= total);
    c
}

/// The x ∈ [0, 1] where the cumulative `c` (on a regular grid) reaches `target`, linearly.
fn invert_cumulative(c: &[f64], target: f64) -> f64 {
    let i = c.partition_point(|&v| v < target).clamp(1, c.len() - 1);
    let (a, b) = (c[i - 1], c[i]);
    let t = if b > a { ((target - a) / (b - a)).clamp(0.0, 1.0) } else { 0.0 };
    (i as f64 - 1.0 + t) / (c.len() - 1) as f64
}

/// The half vector's (u_θ, u_φ) at each sample-space vertex: y by the marginal, then x by the
/// conditional of the analytic visible-normal density (pbrt-v4's order).
fn warp_points<B: AnalyticBrdf>(b: &B, w1: DVec3, n: usize, k: usize) -> Vec<(f64, f64)> {
    let sigma1 = b.sigma(w1.z);
    let grid = |i: usize| i as f64 / k as f64;
    let row_integral = |y: f64| -> Vec<f64> { (0..=k).map(|i| vndf_u(b, w1, sigma1, grid(i), y)).collect() };
    let marginal: Vec<f64> = (0..=k)
        .map(|j| {
            let r = row_integral(grid(j));
            r.windows(2).map(|w| 0.5 * (w[0] + w[1])).sum::<f64>()
        })
        .collect();
    let marginal = cumulative(&marginal);
    let mut points = vec![(0.0, 0.0); n * n];
    for j in 0..n {
        let y = invert_cumulative(&marginal, j as f64 / (n - 1) as f64);
        let conditional = cumulative(&row_integral(y));
        for i in 0..n {
            points[j * n + i] = (invert_cumulative(&conditional, i as f64 / (n - 1) as f64), y);
        }
    }
    points
}

/// The tensor file of `brdf` sampled on `grid` (isotropic: φ_i = [0]; `jacobian` = 1).
pub fn tabulate<B: AnalyticBrdf + Sync>(brdf: &B, grid: &Grid, description: &str) -> TensorFile {
    use rayon::prelude::*;
    let (nd, ns) = (grid.ndf_res, grid.sample_res);
    let vertex = |i: usize, n: usize| i as f64 / (n - 1) as f64;
    let over_u = |g: &dyn Fn(f64) -> f64| -> Vec<f32> {
        (0..nd * nd).map(|k| g(dir_of_u(vertex(k % nd, nd), vertex(k / nd, nd)).z) as f32).collect()
    };
    let ndf = over_u(&|c| brdf.ndf(c));
    let sigma = over_u(&|c| brdf.sigma(c));
    let per_theta: Vec<[Vec<f32>; 3]> = grid
        .theta_i
        .par_iter()
        .map(|&t| {
            let w1 = DVec3::new((t as f64).sin(), 0.0, (t as f64).cos());
            let sigma1 = brdf.sigma(w1.z);
            let vndf: Vec<f32> =
                (0..ns * ns).map(|k| vndf_u(brdf, w1, sigma1, vertex(k % ns, ns), vertex(k / ns, ns)) as f32).collect();
            let points = warp_points(brdf, w1, ns, grid.warp_res);
            let mut spectra = vec![0f32; grid.wavelengths.len() * ns * ns];
            let mut luminance = vec![0f32; ns * ns];
            for (k, &(x, y)) in points.iter().enumerate() {
                let m = dir_of_u(x, y);
                let w2 = 2.0 * w1.dot(m) * m - w1;
                if w2.z <= 0.0 {
                    continue;
                }
                // R = f · 4σ(ω₁) cos θ₂ / D(ω_m).
                let scale = 4.0 * sigma1 * w2.z / brdf.ndf(m.z);
                for (l, &lambda) in grid.wavelengths.iter().enumerate() {
                    let r = (brdf.f(w1, w2, lambda as f64) * scale) as f32;
                    spectra[l * ns * ns + k] = r;
                    luminance[k] += r / grid.wavelengths.len() as f32;
                }
            }
            [vndf, luminance, spectra]
        })
        .collect();
    let cat = |k: usize| -> Vec<f32> { per_theta.iter().flat_map(|p| p[k].iter().copied()).collect() };
    let nt = grid.theta_i.len();
    let nl = grid.wavelengths.len();
    let mut t = TensorFile::default();
    let mut put = |name: &str, f: Field| {
        t.fields.insert(name.into(), f);
    };
    put("theta_i", Field::f32(vec![nt], &grid.theta_i));
    put("phi_i", Field::f32(vec![1], &[0.0]));
    put("wavelengths", Field::f32(vec![nl], &grid.wavelengths));
    put("ndf", Field::f32(vec![nd, nd], &ndf));
    put("sigma", Field::f32(vec![nd, nd], &sigma));
    put("vndf", Field::f32(vec![1, nt, ns, ns], &cat(0)));
    put("luminance", Field::f32(vec![1, nt, ns, ns], &cat(1)));
    put("spectra", Field::f32(vec![1, nt, nl, ns, ns], &cat(2)));
    put("jacobian", Field::u8(vec![1], &[1]));
    put("description", Field::u8(vec![description.len()], description.as_bytes()));
    t
}
