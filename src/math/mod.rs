//! Math: glam re-exports, orthonormal frames, robust ray-origin offsets, the equal-area
//! square–sphere mapping.

pub mod equal_area;
mod frame;
pub mod offset;

pub use frame::{Frame, FrameLanes};
pub use glam::{DVec3, Mat3, Mat4, Vec2, Vec3, Vec4};
pub use offset::{offset_ray_origin, triangle_point};

/// π as f32.
pub const PI: f32 = std::f32::consts::PI;
/// 1/π.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;

/// ⌊x⌋ without a library call (x86-64's baseline SSE2 has no rounding instruction, so
/// `f32::floor` calls `floorf`). Exact for every f32 but −0, which gives +0: magnitudes from
/// 2²³ up are integers already and are returned as they are, as are ±∞ and NaN.
#[inline]
pub fn floor(x: f32) -> f32 {
    if x.is_nan() || x.abs() >= 8_388_608.0 {
        return x;
    }
    let t = x as i32 as f32;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn floor_agrees_with_the_library_floor() {
        let mut x = 1e-6f32;
        let specials = [0.0, 0.5, 1.0, 8_388_607.5, 8_388_608.0, 1e30, f32::INFINITY, f32::MAX, f32::MIN_POSITIVE];
        let mut values: Vec<f32> = specials.iter().flat_map(|&v| [v, -v]).collect();
        while x < 1e9 {
            values.extend([x, -x, x.next_up(), -x.next_up()]);
            x *= 1.37;
        }
        for v in values {
            assert_eq!(super::floor(v), v.floor(), "floor({v})");
        }
        assert!(super::floor(f32::NAN).is_nan());
    }
}
