//! Projection of a measured SPD onto a finite basis (the L² best approximation):
//! minimise ∫ (F − Σ βᵢBᵢ)² dλ ⇒ A β = b with A_ij = ∫ BᵢBⱼ, bᵢ = ∫ BᵢF. For boxes A is
//! diagonal; for hats it is tridiagonal and solved by the Thomas algorithm. A cheaper
//! shortcut replaces the solve by box averages βᵢ = (1/|Iᵢ|) ∫_{Iᵢ} F around each node.

use super::cie::for_each_node;
use super::spd::Spectrum;

/// Which basis functions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// N boxes of width h = (b − a)/N.
    Constant,
    /// N hats on nodes a + i·h, h = (b − a)/(N − 1) (half hats at the ends).
    Linear,
}

/// How the coefficients are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fit {
    /// The L² optimum, A β = b.
    Exact,
    /// Box averages of F around each node (no linear solve).
    Average,
}

/// Coefficients of a projection and how well they reproduce F.
#[derive(Clone, Debug)]
pub struct Projection {
    /// Basis used.
    pub basis: Basis,
    /// Fit used.
    pub fit: Fit,
    /// Domain [nm].
    pub range: (f64, f64),
    /// One coefficient per basis function.
    pub coeffs: Vec<f64>,
    /// ‖F − Σ βᵢBᵢ‖₂ over the domain [units of F · nm^½].
    pub l2_error: f64,
    /// `l2_error` / ‖F‖₂.
    pub relative_error: f64,
}

/// Errors of [`project`].
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ProjectionError {
    /// Too few basis functions for the basis.
    #[error("need at least {min} basis functions for this basis, got {got}")]
    TooFewBins {
        /// Minimum.
        min: usize,
        /// Given.
        got: usize,
    },
    /// Domain empty or not finite.
    #[error("invalid range {0}..{1} nm")]
    BadRange(f64, f64),
}

impl Projection {
    /// Spacing between nodes (box width or hat half-width) [nm].
    pub fn spacing(&self) -> f64 {
        let n = self.coeffs.len();
        let (a, b) = self.range;
        match self.basis {
            Basis::Constant => (b - a) / n as f64,
            Basis::Linear => (b - a) / (n - 1) as f64,
        }
    }

    /// The approximation Σ βᵢBᵢ as a spectrum.
    pub fn to_spectrum(&self) -> Spectrum {
        let (a, h) = (self.range.0, self.spacing());
        let n = self.coeffs.len();
        match self.basis {
            Basis::Constant => {
                let edges = (0..=n).map(|i| a + h * i as f64).collect();
                Spectrum::piecewise_constant(edges, self.coeffs.clone())
            }
            Basis::Linear => {
                let nodes = (0..n).map(|i| a + h * i as f64).collect();
                Spectrum::piecewise_linear_f64(nodes, self.coeffs.clone())
            }
        }
        .expect("projection grids are well formed")
    }
}

/// ∫ₗᵒʰⁱ f, exactly for piecewise polynomials of degree ≤ 5 between `knots` and integer nm.
fn integrate(lo: f64, hi: f64, knots: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    let mut s = 0.0;
    for_each_node(lo, hi, knots, |l, w| s += f(l) * w);
    s
}

/// Solves a tridiagonal system (sub-diagonal `a`, diagonal `d`, super-diagonal `c`, right
/// side `r`) by the Thomas algorithm; the hat Gram matrix is diagonally dominant, so no
/// pivoting is needed.
pub fn solve_tridiagonal(a: &[f64], d: &[f64], c: &[f64], r: &[f64]) -> Vec<f64> {
    let n = d.len();
    let mut cp = vec![0.0; n];
    let mut rp = vec![0.0; n];
    cp[0] = c.first().copied().unwrap_or(0.0) / d[0];
    rp[0] = r[0] / d[0];
    for i in 1..n {
        let m = d[i] - a[i] * cp[i - 1];
        cp[i] = if i < n - 1 { c[i] / m } else { 0.0 };
        rp[i] = (r[i] - a[i] * rp[i - 1]) / m;
    }
    let mut x = vec![0.0; n];
    x[n - 1] = rp[n - 1];
    for i in (0..n - 1).rev() {
        x[i] = rp[i] - cp[i] * x[i + 1];
    }
    x
}

/// Projects `f` onto `n` basis functions over `range` [nm].
pub fn project(
    f: &Spectrum,
    basis: Basis,
    fit: Fit,
    n: usize,
    range: (f64, f64),
) -> Result<Projection, ProjectionError> {
    let (lo, hi) = range;
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(ProjectionError::BadRange(lo, hi));
    }
    let min = if basis == Basis::Linear { 2 } else { 1 };
    if n < min {
        return Err(ProjectionError::TooFewBins { min, got: n });
    }
    let fk = f.knots();
    let fe = |l: f64| f.eval_f64(l);
    let coeffs = match basis {
        // Boxes are orthogonal with ∫BᵢBᵢ = h, so the exact solution *is* the box average.
        Basis::Constant => {
            let h = (hi - lo) / n as f64;
            (0..n)
                .map(|i| {
                    let a = lo + h * i as f64;
                    integrate(a, a + h, &fk, fe) / h
                })
                .collect()
        }
        Basis::Linear => {
            let h = (hi - lo) / (n - 1) as f64;
            let node = |i: usize| lo + h * i as f64;
            match fit {
                Fit::Exact => {
                    let hat = |i: usize, l: f64| (1.0 - (l - node(i)).abs() / h).max(0.0);
                    let mut knots = fk.clone();
                    knots.extend((0..n).map(node));
                    let b: Vec<f64> = (0..n)
                        .map(|i| {
                            let a = node(i.saturating_sub(1));
                            let c = node((i + 1).min(n - 1));
                            integrate(a, c, &knots, |l| hat(i, l) * fe(l))
                        })
                        .collect();
                    // Gram matrix of hats: ∫BᵢBᵢ = 2h/3 (h/3 at the ends), ∫BᵢBᵢ₊₁ = h/6.
                    let d: Vec<f64> =
                        (0..n).map(|i| if i == 0 || i == n - 1 { h / 3.0 } else { 2.0 * h / 3.0 }).collect();
                    let off = vec![h / 6.0; n];
                    solve_tridiagonal(&off, &d, &off, &b)
                }
                Fit::Average => (0..n)
                    .map(|i| {
                        let a = (node(i) - h / 2.0).max(lo);
                        let c = (node(i) + h / 2.0).min(hi);
                        integrate(a, c, &fk, fe) / (c - a)
                    })
                    .collect(),
            }
        }
    };
    let mut p = Projection { basis, fit, range, coeffs, l2_error: 0.0, relative_error: 0.0 };
    let approx = p.to_spectrum();
    let mut knots = fk;
    knots.extend(approx.knots());
    let err2 = integrate(lo, hi, &knots, |l| (fe(l) - approx.eval_f64(l)).powi(2));
    let norm2 = integrate(lo, hi, &knots, |l| fe(l).powi(2));
    p.l2_error = err2.sqrt();
    p.relative_error = if norm2 > 0.0 { (err2 / norm2).sqrt() } else { 0.0 };
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thomas_matches_dense_solution() {
        // 4×4 system solved by hand-checkable substitution: A x = r with x = (1, 2, 3, 4).
        let a = [0.0, 1.0, 1.0, 1.0];
        let d = [4.0, 4.0, 4.0, 4.0];
        let c = [1.0, 1.0, 1.0, 0.0];
        let x = [1.0, 2.0, 3.0, 4.0];
        let r: Vec<f64> = (0..4)
            .map(|i| {
                d[i] * x[i] + if i > 0 { a[i] * x[i - 1] } else { 0.0 } + if i < 3 { c[i] * x[i + 1] } else { 0.0 }
            })
            .collect();
        let got = solve_tridiagonal(&a, &d, &c, &r);
        for i in 0..4 {
            assert!((got[i] - x[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn functions_in_the_span_are_reproduced_exactly() {
        // A piecewise-linear F on the hat nodes is in the span: exact fit has zero error.
        let n = 11;
        let h = 47.0;
        let l: Vec<f64> = (0..n).map(|i| 360.0 + h * i as f64).collect();
        let v: Vec<f64> = (0..n).map(|i| ((i * 7) % 5) as f64 + 0.5).collect();
        let f = Spectrum::piecewise_linear_f64(l, v.clone()).unwrap();
        let p = project(&f, Basis::Linear, Fit::Exact, n, (360.0, 830.0)).unwrap();
        assert!(p.l2_error < 1e-9, "{}", p.l2_error);
        for (a, b) in p.coeffs.iter().zip(&v) {
            assert!((a - b).abs() < 1e-9);
        }
        // ...but the average shortcut smooths it: strictly larger error.
        let q = project(&f, Basis::Linear, Fit::Average, n, (360.0, 830.0)).unwrap();
        assert!(q.l2_error > 1e-2);
    }

    #[test]
    fn exact_fit_is_the_l2_minimum() {
        // Perturbing any coefficient of the exact solution can only increase the error.
        let f = Spectrum::blackbody(3000.0);
        let p = project(&f, Basis::Linear, Fit::Exact, 8, (360.0, 830.0)).unwrap();
        let avg = project(&f, Basis::Linear, Fit::Average, 8, (360.0, 830.0)).unwrap();
        assert!(p.l2_error < avg.l2_error);
        for i in 0..8 {
            for d in [-1e-3, 1e-3] {
                let mut q = p.clone();
                q.coeffs[i] += d;
                let s = q.to_spectrum();
                let err2 = integrate(360.0, 830.0, &[], |l| (f.eval_f64(l) - s.eval_f64(l)).powi(2));
                assert!(err2.sqrt() > p.l2_error, "coefficient {i}");
            }
        }
    }

    #[test]
    fn constant_basis_average_equals_exact() {
        let f = Spectrum::named("stdillum-F11").unwrap();
        let a = project(&f, Basis::Constant, Fit::Exact, 20, (360.0, 830.0)).unwrap();
        let b = project(&f, Basis::Constant, Fit::Average, 20, (360.0, 830.0)).unwrap();
        assert_eq!(a.coeffs, b.coeffs);
        // Box average of a constant is the constant.
        let c = project(&Spectrum::constant(2.0), Basis::Constant, Fit::Exact, 5, (360.0, 830.0)).unwrap();
        assert!(c.coeffs.iter().all(|v| (v - 2.0).abs() < 1e-12) && c.l2_error < 1e-9);
    }

    #[test]
    fn bad_arguments_are_errors() {
        let f = Spectrum::constant(1.0);
        assert!(project(&f, Basis::Linear, Fit::Exact, 1, (360.0, 830.0)).is_err());
        assert!(project(&f, Basis::Constant, Fit::Exact, 0, (360.0, 830.0)).is_err());
        assert!(project(&f, Basis::Constant, Fit::Exact, 4, (830.0, 360.0)).is_err());
    }
}
