//! Where the camera is at each instant: camera space → world space, fixed, or moving between two
//! keyframes as pbrt-v4's `CameraTransform` over an `AnimatedTransform` (Pharr, Jakob &
//! Humphreys, *Physically Based Rendering*, 4th ed., §5.1.1 and §3.10.1). Every camera ray is
//! made in camera space and carried to world space by the transform at the ray's time, so a
//! camera that moves during the shutter blurs the scene as an equal and opposite motion of the
//! scene would.

use crate::geometry::AnimatedTransform;
use glam::Mat4;

/// Camera space → world space at every time of the shutter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraTransform {
    /// The transform of a fixed camera, or of a moving one at its motion's start.
    world_from_camera: Mat4,
    /// Its inverse.
    camera_from_world: Mat4,
    /// The motion (`None`: the camera does not move).
    motion: Option<AnimatedTransform>,
}

impl CameraTransform {
    /// A camera fixed at `world_from_camera`.
    pub fn fixed(world_from_camera: Mat4) -> Self {
        Self { world_from_camera, camera_from_world: world_from_camera.inverse(), motion: None }
    }

    /// A camera at `world_from_camera`, moving by `motion` when it is given and its keyframes
    /// differ (its start matrix then replaces `world_from_camera`).
    pub fn new(world_from_camera: Mat4, motion: Option<AnimatedTransform>) -> Self {
        match motion.filter(AnimatedTransform::is_animated) {
            Some(m) => Self { motion: Some(m), ..Self::fixed(m.start) },
            None => Self::fixed(world_from_camera),
        }
    }

    /// True when the camera moves, so its rays must sample a time.
    pub fn moves(&self) -> bool {
        self.motion.is_some()
    }

    /// The motion, when the camera moves.
    pub fn motion(&self) -> Option<&AnimatedTransform> {
        self.motion.as_ref()
    }

    /// A time inside the motion: its middle (0 for a fixed camera, whose transform is the same
    /// at every time).
    pub fn mid_time(&self) -> f32 {
        self.motion.map_or(0.0, |m| 0.5 * (m.start_time + m.end_time))
    }

    /// Camera space → world space at `time` [the scene's time units].
    #[inline]
    pub fn world_from_camera(&self, time: f32) -> Mat4 {
        match &self.motion {
            None => self.world_from_camera,
            Some(m) => m.interpolate(time),
        }
    }

    /// World space → camera space at `time`.
    #[inline]
    pub fn camera_from_world(&self, time: f32) -> Mat4 {
        match &self.motion {
            None => self.camera_from_world,
            Some(m) => m.interpolate(time).inverse(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec3};

    #[test]
    fn a_fixed_transform_is_the_same_at_every_time_and_a_moving_one_interpolates() {
        let a = Mat4::from_rotation_translation(Quat::from_rotation_y(0.3), Vec3::new(1.0, 2.0, 3.0));
        let fixed = CameraTransform::new(a, None);
        assert!(!fixed.moves());
        for t in [-1.0, 0.0, 0.4, 7.0] {
            assert_eq!(fixed.world_from_camera(t), a);
            assert_eq!(fixed.camera_from_world(t), a.inverse());
        }
        // Equal keyframes are no motion.
        assert!(!CameraTransform::new(a, Some(AnimatedTransform::new(a, 0.0, a, 1.0))).moves());
        // A quarter turn about y and a translation along x between times 2 and 4: at time 3 the
        // camera has turned 45° and moved half way.
        let b = Mat4::from_rotation_translation(
            Quat::from_rotation_y(0.3 + std::f32::consts::FRAC_PI_2),
            Vec3::new(5.0, 2.0, 3.0),
        );
        let moving = CameraTransform::new(Mat4::IDENTITY, Some(AnimatedTransform::new(a, 2.0, b, 4.0)));
        assert!(moving.moves());
        assert_eq!(moving.mid_time(), 3.0);
        let m = moving.world_from_camera(3.0);
        assert!(m.transform_point3(Vec3::ZERO).abs_diff_eq(Vec3::new(3.0, 2.0, 3.0), 1e-5));
        let turned = Quat::from_rotation_y(0.3 + std::f32::consts::FRAC_PI_4) * Vec3::Z;
        assert!(m.transform_vector3(Vec3::Z).abs_diff_eq(turned, 1e-5), "{}", m.transform_vector3(Vec3::Z));
        assert!((moving.camera_from_world(3.0) * m).abs_diff_eq(Mat4::IDENTITY, 1e-5));
        // Before and after the motion it stays at the nearer keyframe.
        assert_eq!(moving.world_from_camera(0.0), a);
        assert_eq!(moving.world_from_camera(9.0), b);
    }
}
