//! Functions on the unit square with known integrals, against which samplers are tested
//! (the set of pbrt-v4's `function` integrator): discontinuities
//! along, across and around the strata, and a smooth bump.

use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// The functions on [0, 1]² that pbrt-v4's `function` integrator integrates, each ∫f = 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TestFunction {
    /// 2 where x < ½ (a discontinuity along a stratum boundary).
    #[default]
    Step,
    /// 2 where x + y < 1 (a discontinuity across the strata).
    Diagonal,
    /// 4/π inside the disk of radius ½ about (½, ½).
    Disk,
    /// 2 on the odd cells of a 10 × 10 checkerboard.
    Checkerboard,
    /// The checkerboard at 45°: 2 where ⌊10 s⌋ + ⌊10 t⌋ is odd, s = 10 + (x − y)/√2,
    /// t = 10 + (x + y)/√2. Its integral is 1 (clipping the unit square to each cell, in f64);
    /// pbrt-v4, which evaluates it in f32, divides by 1.0000687, its measure of that.
    RotatedCheckerboard,
    /// The product of two normal densities (μ = ½, σ = ¼) in x and y, divided by its mass in
    /// the square, erf(√2)².
    Gaussian,
}

crate::named::name_table!(TestFunction, "function", {
    "step" => TestFunction::Step,
    "diagonal" => TestFunction::Diagonal,
    "disk" => TestFunction::Disk,
    "checkerboard" => TestFunction::Checkerboard,
    "rotatedcheckerboard" => TestFunction::RotatedCheckerboard,
    "gaussian" => TestFunction::Gaussian,
});

/// erf(√2) = P(|Z| < 2) for a standard normal Z: the mass of N(½, ¼²) in [0, 1].
const ERF_SQRT_2: f64 = 0.954_499_736_103_641_6;

impl TestFunction {
    /// f(x, y) for (x, y) in [0, 1)².
    pub fn eval(self, x: f64, y: f64) -> f64 {
        let checker =
            |s: f64, t: f64| if ((s * 10.0).floor() + (t * 10.0).floor()) as i64 & 1 == 1 { 2.0 } else { 0.0 };
        match self {
            TestFunction::Step => 2.0 * f64::from(u8::from(x < 0.5)),
            TestFunction::Diagonal => 2.0 * f64::from(u8::from(x + y < 1.0)),
            TestFunction::Disk => {
                let inside = (x - 0.5).powi(2) + (y - 0.5).powi(2) < 0.25;
                f64::from(u8::from(inside)) * 4.0 / PI
            }
            TestFunction::Checkerboard => checker(x, y),
            TestFunction::RotatedCheckerboard => {
                checker(10.0 + (x - y) * FRAC_1_SQRT_2, 10.0 + (x + y) * FRAC_1_SQRT_2)
            }
            TestFunction::Gaussian => {
                let (mu, sigma) = (0.5, 0.25);
                let normal = |v: f64| (-(v - mu).powi(2) / (2.0 * sigma * sigma)).exp() / (sigma * (2.0 * PI).sqrt());
                normal(x) * normal(y) / (ERF_SQRT_2 * ERF_SQRT_2)
            }
        }
    }
}
