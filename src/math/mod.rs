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
