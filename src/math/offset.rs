//! Robust spawn points for secondary rays: offset a hit point along the geometric normal by a
//! conservative bound on its floating-point error (pbrt-v4 §6.8.6, "Robust Spawned Ray Origins"),
//! instead of a global epsilon, so rays neither re-hit their own surface nor skip thin geometry at
//! any scene scale.

use crate::simd::{Real, V3};
use glam::Vec3;

/// γ(n) = nε/(1−nε), the bound on accumulated relative rounding error after n operations
/// (Higham 2002), with ε = 2⁻²⁴ the unit roundoff of f32.
#[inline]
pub const fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5;
    (n as f32 * e) / (1.0 - n as f32 * e)
}

/// The point Σ bᵢ pᵢ of a triangle and its absolute error bound γ(7) Σ |bᵢ pᵢ| (pbrt-v4 eq. 6.29).
#[inline]
pub fn triangle_point(p: [Vec3; 3], b: [f32; 3]) -> (Vec3, Vec3) {
    let point = p[0] * b[0] + p[1] * b[1] + p[2] * b[2];
    let err = ((p[0] * b[0]).abs() + (p[1] * b[1]).abs() + (p[2] * b[2]).abs()) * gamma(7);
    (point, err)
}

/// Moves `p` (with per-axis error bound `p_err`) off the surface with normal `n` to the side of
/// direction `w`, far enough that the rounding in `p` cannot put it back on the other side; then
/// rounds each component one ulp further away.
///
/// pbrt-v4 offsets by |n|·δp with the per-axis bound δp. That is enough for an intersector that
/// evaluates the plane in the same axes, but Embree's arithmetic mixes the axes (on the Cornell
/// box's wall at x = 0, δp.x = 0 while y, z carry errors of 1e-4), and it then re-hits the
/// surface at t ≈ 1e-38. So the bound is treated as isotropic: |n|₁ · max(δp). A zero bound (a
/// hit exactly on a representable vertex) still moves the point by one ulp.
#[inline]
pub fn offset_ray_origin(p: Vec3, p_err: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    offset_ray_origin_lanes(p.into(), p_err.into(), n.into(), w.into()).into()
}

/// [`offset_ray_origin`] for every lane.
#[inline(always)]
pub fn offset_ray_origin_lanes<R: Real>(p: V3<R>, p_err: V3<R>, n: V3<R>, w: V3<R>) -> V3<R> {
    // The floor keeps every offset component with n[i] ≠ 0 nonzero (and normal, not denormal).
    let d = (n.abs_sum() * p_err.max_element()).max(R::splat(1e-30));
    let offset = n * d;
    let offset = V3::select(w.dot(n).lt(R::splat(0.0)), -offset, offset);
    let po = p + offset;
    V3::new(step_away(po.x, offset.x), step_away(po.y, offset.y), step_away(po.z, offset.z))
}

/// `v` one ulp further in the direction of the sign of `o` (unchanged where `o` is 0).
#[inline(always)]
fn step_away<R: Real>(v: R, o: R) -> R {
    let zero = R::splat(0.0);
    R::select(zero.lt(o), v.next_up(), R::select(o.lt(zero), v.next_down(), v))
}

/// The next representable f32 above `v`. From ±0 it steps to the smallest *normal* float, since
/// render threads run with flush-to-zero/denormals-are-zero and would read a denormal as 0.
#[inline]
pub fn next_float_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 {
        return v;
    }
    if v == 0.0 {
        return f32::MIN_POSITIVE;
    }
    let bits = v.to_bits();
    f32::from_bits(if v >= 0.0 { bits + 1 } else { bits - 1 })
}

/// The next representable f32 below `v` (from ±0: the most negative-small normal float).
#[inline]
pub fn next_float_down(v: f32) -> f32 {
    if v.is_infinite() && v < 0.0 {
        return v;
    }
    if v == 0.0 {
        return -f32::MIN_POSITIVE;
    }
    let bits = v.to_bits();
    f32::from_bits(if v > 0.0 { bits - 1 } else { bits + 1 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_point_is_strictly_on_the_requested_side_at_all_scales() {
        // A tilted triangle far from the origin, at scales 1e-4 … 1e5.
        for &scale in &[1e-4f32, 1e-2, 1.0, 1e2, 1e5] {
            for &shift in &[0.0f32, 1e5] {
                let base = Vec3::splat(shift);
                let p = [
                    base + Vec3::new(0.0, 0.0, 0.0) * scale,
                    base + Vec3::new(1.0, 0.2, 0.1) * scale,
                    base + Vec3::new(0.3, 1.0, -0.4) * scale,
                ];
                let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                if !n.is_finite() {
                    continue; // the vertices collapsed to one f32 value: no triangle to test
                }
                let n64 = (p[1].as_dvec3() - p[0].as_dvec3()).cross(p[2].as_dvec3() - p[0].as_dvec3());
                for k in 0..50 {
                    let u = (k as f32 * 0.618).fract() * 0.9;
                    let v = (1.0 - u) * (k as f32 * 0.377).fract();
                    let (pt, err) = triangle_point(p, [1.0 - u - v, u, v]);
                    for side in [1.0f32, -1.0] {
                        let o = offset_ray_origin(pt, err, n, n * side);
                        // Side test in f64 against the plane of the f32 vertices.
                        let d = (o.as_dvec3() - p[0].as_dvec3()).dot(n64);
                        assert!(d * side as f64 > 0.0, "scale {scale} shift {shift}: {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn next_float_steps_one_ulp() {
        assert!(next_float_up(1.0) > 1.0 && next_float_down(1.0) < 1.0);
        assert_eq!(next_float_up(-0.0), f32::MIN_POSITIVE);
        assert_eq!(next_float_down(0.0), -f32::MIN_POSITIVE);
    }
}
