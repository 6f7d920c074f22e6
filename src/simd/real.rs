//! The lane-generic float and mask traits.

use std::ops::{Add, AddAssign, BitAnd, BitOr, Div, Mul, MulAssign, Neg, Not, Sub, SubAssign};

/// A per-lane boolean: `bool` for one lane, [`super::LanesMask`] for many.
pub trait Mask: Copy + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> {
    /// Every lane `v`.
    fn splat(v: bool) -> Self;
    /// True when any lane is set.
    fn any(self) -> bool;
    /// True when every lane is set.
    fn all(self) -> bool;
    /// Lane `i`.
    fn lane(self, i: usize) -> bool;
}

/// One `f32` per lane, with the operations the renderer's physics needs. Every operation is
/// lane-wise; `select` replaces branches.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// The per-lane boolean.
    type Mask: Mask;
    /// Every lane `v`.
    fn splat(v: f32) -> Self;
    /// Lane `i`.
    fn lane(self, i: usize) -> f32;
    /// Sets lane `i`.
    fn set_lane(&mut self, i: usize, v: f32);
    /// Square root.
    fn sqrt(self) -> Self;
    /// |x|.
    fn abs(self) -> Self;
    /// Lane-wise minimum (the other operand when one is NaN, as `f32::min`).
    fn min(self, o: Self) -> Self;
    /// Lane-wise maximum (as `f32::max`).
    fn max(self, o: Self) -> Self;
    /// x < o.
    fn lt(self, o: Self) -> Self::Mask;
    /// x == o.
    fn eq(self, o: Self) -> Self::Mask;
    /// Finite (neither infinite nor NaN).
    fn is_finite(self) -> Self::Mask;
    /// `a` where `m` is set, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// The next representable value above (from ±0: the smallest normal float, since render
    /// threads flush denormals to zero).
    fn next_up(self) -> Self;
    /// The next representable value below (from ±0: minus the smallest normal float).
    fn next_down(self) -> Self;
    /// |self| with the sign of `sign`.
    fn copysign(self, sign: Self) -> Self;

    /// (sin x, cos x) for |x| ≤ π/4: odd degree-7 and even degree-8 minimax polynomials with the
    /// coefficients of Cephes' `sinf`/`cosf` (Moshier 1989, "Methods and Programs for
    /// Mathematical Functions"); within 2 ulp of the exact values there (tested).
    #[inline(always)]
    fn sin_cos_quarter_pi(self) -> (Self, Self) {
        let x2 = self * self;
        let s = ((Self::splat(-1.951_529_6e-4) * x2 + Self::splat(8.332_161e-3)) * x2 + Self::splat(-1.666_665_5e-1))
            * x2
            * self
            + self;
        let c = ((Self::splat(2.443_315_7e-5) * x2 + Self::splat(-1.388_731_6e-3)) * x2 + Self::splat(4.166_664_6e-2))
            * x2
            * x2
            - Self::splat(0.5) * x2
            + Self::splat(1.0);
        (s, c)
    }
}

impl Mask for bool {
    #[inline(always)]
    fn splat(v: bool) -> Self {
        v
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn lane(self, _: usize) -> bool {
        self
    }
}

impl Real for f32 {
    type Mask = bool;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        v
    }
    #[inline(always)]
    fn lane(self, _: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn set_lane(&mut self, _: usize, v: f32) {
        *self = v;
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        f32::min(self, o)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        f32::max(self, o)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn eq(self, o: Self) -> bool {
        self == o
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn next_up(self) -> Self {
        crate::math::offset::next_float_up(self)
    }
    #[inline(always)]
    fn next_down(self) -> Self {
        crate::math::offset::next_float_down(self)
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        f32::copysign(self, sign)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quarter_turn_sine_and_cosine_are_within_two_ulps_of_libm() {
        // Against f64 libm, on a dense grid of [−π/4, π/4].
        let n = 100_000;
        for i in 0..=n {
            let x = (i as f32 / n as f32 * 2.0 - 1.0) * std::f32::consts::FRAC_PI_4;
            let (s, c) = x.sin_cos_quarter_pi();
            let (es, ec) = ((x as f64).sin(), (x as f64).cos());
            let ulp = |v: f64| (v.abs() as f32).max(f32::MIN_POSITIVE) as f64 * f32::EPSILON as f64;
            assert!((s as f64 - es).abs() <= 2.0 * ulp(es), "sin {x}: {s} vs {es}");
            assert!((c as f64 - ec).abs() <= 2.0 * ulp(ec), "cos {x}: {c} vs {ec}");
        }
    }
}
