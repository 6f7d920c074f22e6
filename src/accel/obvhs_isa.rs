//! The obvhs backend's ray queries compiled twice, for baseline x86-64 (SSE2) and for
//! AVX2 + FMA (with BMI1/2, LZCNT and POPCNT, which the traversal's bit counts use: the
//! x86-64-v3 level), the variant picked once at run time from the CPU's features (the
//! `multiversion` crate: `is_x86_feature_detected!`, then a safe call). Embree dispatches the
//! same way.
//!
//! The traversal, node decoding and triangle test, and the closures handed to the traversal,
//! are `#[inline(always)]` into these functions, so both variants hold the whole query (a call
//! that is not inlined runs baseline code). They compute the same values bit for bit: Rust never
//! contracts `a * b + c` into a fused multiply-add, the backend's code has no explicit
//! `mul_add`, and glam chooses its own fused paths by compile-time `cfg(target_feature)`, which a
//! per-function target does not change. `dispatched_and_baseline_queries_agree_bit_for_bit` (in
//! `obvhs_tests.rs`) checks it against [`ObvhsAccel::closest_hit`] & co. called directly, i.e.
//! compiled for the crate's baseline target.

use multiversion::multiversion;

use super::ObvhsAccel;
use crate::geometry::{Hit, Ray};

/// [`ObvhsAccel::closest_hit`] in the CPU's best variant.
#[multiversion(targets("x86_64+avx2+fma+bmi1+bmi2+lzcnt+popcnt"))]
pub(super) fn closest_hit(accel: &ObvhsAccel, ray: &Ray) -> Option<Hit> {
    accel.closest_hit(ray)
}

/// [`ObvhsAccel::any_hit`] in the CPU's best variant.
#[multiversion(targets("x86_64+avx2+fma+bmi1+bmi2+lzcnt+popcnt"))]
pub(super) fn any_hit(accel: &ObvhsAccel, ray: &Ray) -> bool {
    accel.any_hit(ray)
}

/// [`ObvhsAccel::every_hit`] in the CPU's best variant.
#[multiversion(targets("x86_64+avx2+fma+bmi1+bmi2+lzcnt+popcnt"))]
pub(super) fn every_hit(accel: &ObvhsAccel, ray: &Ray, hits: &mut Vec<Hit>) {
    accel.every_hit(ray, hits)
}
