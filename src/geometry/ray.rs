//! Rays and the record of a ray–triangle hit.

use glam::Vec3;

/// A ray `o + t d` for t in (0, t_max] at one instant `time`. `d` need not be unit length; `t`
/// is in units of |d|.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin [scene units].
    pub o: Vec3,
    /// Direction.
    pub d: Vec3,
    /// Largest parametric distance considered.
    pub t_max: f32,
    /// The instant the ray samples, in the scene's time units (between the camera's shutter
    /// open and close times): moving objects are intersected where they are at this time.
    pub time: f32,
}

impl Ray {
    /// An unbounded ray at time 0.
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Self { o, d, t_max: f32::INFINITY, time: 0.0 }
    }
    /// A ray bounded at `t_max`, at time 0.
    pub fn segment(o: Vec3, d: Vec3, t_max: f32) -> Self {
        Self { o, d, t_max, time: 0.0 }
    }
    /// The same ray at `time`.
    #[inline]
    pub fn at_time(self, time: f32) -> Self {
        Self { time, ..self }
    }
    /// Point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }
}

/// What an accelerator reports for the closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Parametric distance along the ray.
    pub t: f32,
    /// Index of the mesh in the scene.
    pub geom_id: u32,
    /// Index of the triangle within its mesh.
    pub prim_id: u32,
    /// Barycentric coordinates: the hit point is (1-u-v)·p0 + u·p1 + v·p2.
    pub u: f32,
    /// See `u`.
    pub v: f32,
    /// Unnormalised geometric normal, (p1-p0)×(p2-p0), in world space (for an instance hit:
    /// the cross product of the transformed vertices).
    pub ng: Vec3,
    /// Index of the object instance that was hit, or [`Hit::NO_INSTANCE`] for world geometry.
    pub inst_id: u32,
}

impl Hit {
    /// `inst_id` of a hit on geometry that is not part of an object instance.
    pub const NO_INSTANCE: u32 = u32::MAX;
}
