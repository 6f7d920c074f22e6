//! Math: glam re-exports, orthonormal frames.

mod frame;

pub use frame::Frame;
pub use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

/// π as f32.
pub const PI: f32 = std::f32::consts::PI;
/// 1/π.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
