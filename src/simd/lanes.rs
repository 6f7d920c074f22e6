//! `N` lanes of `f32` as a fixed-size array. Every operation is a loop over the lanes that LLVM
//! turns into vector instructions (SSE2 for the portable build, AVX2/AVX-512 where the caller is
//! compiled for them).

use super::{Mask, Real};
use std::ops::{Add, AddAssign, BitAnd, BitOr, Div, Mul, MulAssign, Neg, Not, Sub, SubAssign};

/// `N` floats, one per path.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct Lanes<const N: usize>(pub [f32; N]);

/// `N` booleans, one per path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LanesMask<const N: usize>(pub [bool; N]);

#[inline(always)]
fn map<const N: usize>(a: Lanes<N>, f: impl Fn(f32) -> f32) -> Lanes<N> {
    Lanes(std::array::from_fn(|i| f(a.0[i])))
}

#[inline(always)]
fn zip<const N: usize>(a: Lanes<N>, b: Lanes<N>, f: impl Fn(f32, f32) -> f32) -> Lanes<N> {
    Lanes(std::array::from_fn(|i| f(a.0[i], b.0[i])))
}

#[inline(always)]
fn cmp<const N: usize>(a: Lanes<N>, b: Lanes<N>, f: impl Fn(f32, f32) -> bool) -> LanesMask<N> {
    LanesMask(std::array::from_fn(|i| f(a.0[i], b.0[i])))
}

macro_rules! binary {
    ($tr:ident, $f:ident, $atr:ident, $af:ident, $op:tt) => {
        impl<const N: usize> $tr for Lanes<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                zip(self, o, |a, b| a $op b)
            }
        }
        impl<const N: usize> $atr for Lanes<N> {
            #[inline(always)]
            fn $af(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    };
}
binary!(Add, add, AddAssign, add_assign, +);
binary!(Sub, sub, SubAssign, sub_assign, -);
binary!(Mul, mul, MulAssign, mul_assign, *);

impl<const N: usize> Div for Lanes<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        zip(self, o, |a, b| a / b)
    }
}

impl<const N: usize> Neg for Lanes<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        map(self, |a| -a)
    }
}

macro_rules! mask_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<const N: usize> $tr for LanesMask<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                LanesMask(std::array::from_fn(|i| self.0[i] $op o.0[i]))
            }
        }
    };
}
mask_op!(BitAnd, bitand, &);
mask_op!(BitOr, bitor, |);

impl<const N: usize> Not for LanesMask<N> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        LanesMask(self.0.map(|m| !m))
    }
}

impl<const N: usize> Mask for LanesMask<N> {
    #[inline(always)]
    fn splat(v: bool) -> Self {
        LanesMask([v; N])
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().fold(false, |a, &m| a | m)
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.0.iter().fold(true, |a, &m| a & m)
    }
    #[inline(always)]
    fn lane(self, i: usize) -> bool {
        self.0[i]
    }
}

/// The float one ulp above (`up`) or below `v`,
/// as [`crate::math::offset::next_float_up`]/`next_float_down`: ±0 steps to ±f32::MIN_POSITIVE, ±∞ stays.
#[inline(always)]
fn next_toward(v: f32, up: bool) -> f32 {
    // Branch-free, so that the loop over lanes vectorises: moving away from zero adds one to
    // the magnitude's bits, toward zero subtracts one.
    let bits = v.to_bits();
    let negative = bits >> 31 == 1;
    let stepped = if negative != up { bits.wrapping_add(1) } else { bits.wrapping_sub(1) };
    let zero = if up { f32::MIN_POSITIVE } else { -f32::MIN_POSITIVE };
    let stays = if up { f32::INFINITY } else { f32::NEG_INFINITY };
    let r = if v == stays { v } else { f32::from_bits(stepped) };
    if v == 0.0 {
        zero
    } else {
        r
    }
}

impl<const N: usize> Real for Lanes<N> {
    type Mask = LanesMask<N>;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        Lanes([v; N])
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.0[i]
    }
    #[inline(always)]
    fn set_lane(&mut self, i: usize, v: f32) {
        self.0[i] = v;
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        map(self, f32::sqrt)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        map(self, f32::abs)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        zip(self, o, f32::min)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        zip(self, o, f32::max)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> LanesMask<N> {
        cmp(self, o, |a, b| a < b)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> LanesMask<N> {
        cmp(self, o, |a, b| a == b)
    }
    #[inline(always)]
    fn is_finite(self) -> LanesMask<N> {
        cmp(self, self, |a, _| a.is_finite())
    }
    #[inline(always)]
    fn select(m: LanesMask<N>, a: Self, b: Self) -> Self {
        Lanes(std::array::from_fn(|i| if m.0[i] { a.0[i] } else { b.0[i] }))
    }
    #[inline(always)]
    fn next_up(self) -> Self {
        map(self, |v| next_toward(v, true))
    }
    #[inline(always)]
    fn next_down(self) -> Self {
        map(self, |v| next_toward(v, false))
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        zip(self, sign, f32::copysign)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::offset::{next_float_down, next_float_up};

    #[test]
    fn lane_steps_equal_the_scalar_steps() {
        let vals =
            [0.0, -0.0, 1.0, -1.0, 1e-30, -3.5e7, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, -f32::MIN_POSITIVE];
        for v in vals {
            let l = Lanes::<4>::splat(v);
            assert_eq!(l.next_up().0[0].to_bits(), next_float_up(v).to_bits(), "up {v}");
            assert_eq!(l.next_down().0[0].to_bits(), next_float_down(v).to_bits(), "down {v}");
        }
    }

    #[test]
    fn select_and_masks_work_per_lane() {
        let a = Lanes([1.0, 2.0, 3.0, 4.0]);
        let b = Lanes([4.0, 3.0, 2.0, 1.0]);
        let m = a.lt(b);
        assert_eq!(m, LanesMask([true, true, false, false]));
        assert_eq!(Lanes::select(m, a, b), Lanes([1.0, 2.0, 2.0, 1.0]));
        assert!(m.any() && !m.all() && (m | !m).all() && !(m & !m).any());
    }
}
