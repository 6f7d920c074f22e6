//! Object instancing: prototypes (a set of meshes in object space, each with its material) and
//! instances (a prototype placed by an object-to-world transform), as pbrt-v4's
//! ObjectBegin/ObjectInstance describe them. The accelerators trace the prototypes once and
//! transform rays per instance (Embree: instance geometries; obvhs: a two-level BVH), so memory
//! grows with the number of distinct triangles, not with the number of placed copies.
//!
//! Hit points on instances are transformed back to world space together with their rounding-error
//! bounds (pbrt-v4, `Transform::operator()(Point3fi)`, §6.8.5), so spawned rays stay robust.

use std::borrow::Cow;
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3};

use super::animated::{corner_box, AnimatedTransform};
use super::motion::Motion;
use super::{Bounds3, Mesh};
use crate::math::offset::gamma;

/// A prototype: primitives (indices into the scene's primitive and mesh lists) that are
/// instanced together — triangle meshes, and curves or quadrics (whose meshes are empty).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prototype {
    /// Primitive ids in object space; a hit's `geom_id` is one of these.
    pub meshes: Vec<u32>,
}

/// One placed copy of a prototype.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Index into the prototype list.
    pub prototype: u32,
    /// World from object space (affine, invertible).
    pub world_from_object: Mat4,
    /// Its inverse: rays are carried into object space by it.
    pub object_from_world: Mat4,
    /// Cofactor matrix of the linear part, det(A)·A⁻ᵀ: maps an object-space cross product
    /// a × b to (A a) × (A b), so unnormalised triangle normals keep their meaning.
    pub normal_cofactor: Mat3,
    /// Sign of det(A): −1 when the transform mirrors (swaps handedness).
    pub handedness: f32,
    /// The motion, for an instance that moves over the shutter interval; the matrices above are
    /// then those of its start time (see [`Instance::at`]). Shared: instances are cloned while
    /// a scene is built, and a static one stays small.
    pub motion: Option<Arc<Motion>>,
}

impl Instance {
    /// An instance of `prototype` at `world_from_object`; `None` when the matrix is singular or
    /// not finite (such an instance has no volume to place and no inverse to trace with).
    pub fn new(prototype: u32, world_from_object: Mat4) -> Option<Self> {
        let a = Mat3::from_mat4(world_from_object);
        let det = a.determinant();
        let object_from_world = Self::checked_inverse(world_from_object, det)?;
        let normal_cofactor = a.inverse().transpose() * det;
        Some(Self {
            prototype,
            world_from_object,
            object_from_world,
            normal_cofactor,
            handedness: det.signum(),
            motion: None,
        })
    }

    /// An instance of `prototype` moving by `motion`; static when the two matrices are equal.
    /// `None` when either keyframe is singular or not finite.
    pub fn animated(prototype: u32, motion: AnimatedTransform) -> Option<Self> {
        Self::moving(prototype, Motion::One(motion))
    }

    /// An instance of `prototype` moving by `motion` (static when it does not move); `None`
    /// when its matrix at either end of its time span is singular or not finite.
    pub fn moving(prototype: u32, motion: Motion) -> Option<Self> {
        let (t0, t1) = motion.time_span();
        let start = Self::new(prototype, motion.interpolate(t0))?;
        Self::new(prototype, motion.interpolate(t1))?;
        Some(Self { motion: motion.is_animated().then(|| Arc::new(motion)), ..start })
    }

    /// The instance as it is placed at `time` (itself when it does not move; its start placement
    /// should the interpolated matrix be singular, as a scale passing through zero is); never
    /// moving.
    #[inline]
    pub fn at(&self, time: f32) -> Self {
        match &self.motion {
            None => self.fixed(),
            Some(m) => Self::new(self.prototype, m.interpolate(time)).unwrap_or_else(|| self.fixed()),
        }
    }

    /// [`Instance::at`] without copying a placement that does not move: itself then.
    #[inline]
    pub fn placed_at(&self, time: f32) -> Cow<'_, Self> {
        match &self.motion {
            None => Cow::Borrowed(self),
            Some(_) => Cow::Owned(self.at(time)),
        }
    }

    /// [`Instance::at`]'s `object_from_world` alone: a ray's carrier into object space at
    /// `time`, without the normal cofactor and the copy of the rest (a moving quadric is tested
    /// against far more rays than it is hit by).
    #[inline]
    pub fn object_from_world_at(&self, time: f32) -> Mat4 {
        match &self.motion {
            None => self.object_from_world,
            Some(m) => {
                let world_from_object = m.interpolate(time);
                let det = Mat3::from_mat4(world_from_object).determinant();
                Self::checked_inverse(world_from_object, det).unwrap_or(self.object_from_world)
            }
        }
    }

    /// The inverse of `world_from_object`, whose linear part has determinant `det`, when
    /// [`Instance::new`] accepts it (finite, with a finite non-zero determinant and a finite
    /// inverse).
    #[inline]
    fn checked_inverse(world_from_object: Mat4, det: f32) -> Option<Mat4> {
        if !world_from_object.is_finite() || det == 0.0 || !det.is_finite() {
            return None;
        }
        Some(world_from_object.inverse()).filter(Mat4::is_finite)
    }

    /// The placement of its start time, without the motion.
    #[inline]
    fn fixed(&self) -> Self {
        Self {
            prototype: self.prototype,
            world_from_object: self.world_from_object,
            object_from_world: self.object_from_world,
            normal_cofactor: self.normal_cofactor,
            handedness: self.handedness,
            motion: None,
        }
    }

    /// World-space box around the object-space box `b` (its eight corners transformed), over
    /// the whole motion for a moving instance ([`Motion::motion_bounds`]).
    pub fn world_bounds(&self, b: Bounds3) -> Bounds3 {
        match &self.motion {
            None => corner_box(&self.world_from_object, b),
            Some(m) => m.motion_bounds(b),
        }
    }

    /// The instance followed by the static transform `m` (world from world), `None` when the
    /// result is singular.
    pub fn then(&self, m: Mat4) -> Option<Self> {
        match &self.motion {
            None => Self::new(self.prototype, m * self.world_from_object),
            Some(motion) => Self::moving(self.prototype, motion.then(m)),
        }
    }

    /// Transforms an object-space point with per-axis absolute error bound `err` to world space,
    /// returning the point and a bound on its error: the propagated input error plus the rounding
    /// of the transform itself (pbrt-v4 `Transform::operator()(Point3fi)`):
    /// δ'ᵢ = (γ₃+1) Σⱼ |mᵢⱼ| δⱼ + γ₃ (Σⱼ |mᵢⱼ pⱼ| + |tᵢ|).
    pub fn point_to_world(&self, p: Vec3, err: Vec3) -> (Vec3, Vec3) {
        let m = &self.world_from_object;
        let a = abs(Mat3::from_mat4(*m));
        let t = m.w_axis.truncate();
        let rounding = (a * p.abs() + t.abs()) * gamma(3);
        let propagated = (a * err) * (gamma(3) + 1.0);
        (m.transform_point3(p), propagated + rounding)
    }

    /// An object-space surface normal in world space by the inverse transpose A⁻ᵀ (so a mirrored
    /// instance faces the way its flattened copy does: `Mesh::transformed` re-winds mirrored
    /// triangles), unit length (zero stays zero).
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        (self.normal_cofactor * n).normalize_or_zero() * self.handedness
    }

    /// An object-space tangent vector in world space.
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.world_from_object.transform_vector3(v)
    }

    /// [`Instance::point_to_world`] for a point rays will leave from: the bound also covers the
    /// rounding of carrying a point near it back into object space, γ₃(|M⁻¹| |p| + |t⁻¹|) mapped
    /// to world space by |M| (pbrt-v4 carries that error as an interval through its object-space
    /// tests; here it widens the offset instead, so a spawned ray starts on its own side of the
    /// surface in object space too).
    pub fn spawn_point_to_world(&self, p: Vec3, err: Vec3) -> (Vec3, Vec3) {
        let (p, p_err) = self.point_to_world(p, err);
        let inverse = abs(Mat3::from_mat4(self.object_from_world));
        let back = gamma(3) * (inverse * p.abs() + self.object_from_world.w_axis.truncate().abs());
        (p, p_err + abs(Mat3::from_mat4(self.world_from_object)) * back)
    }

    /// A ray in object space (same t, same time).
    #[inline]
    pub fn ray_to_object(&self, ray: &super::Ray) -> super::Ray {
        let m = &self.object_from_world;
        super::Ray { o: m.transform_point3(ray.o), d: m.transform_vector3(ray.d), ..*ray }
    }
}

/// |A| of a 3×3 matrix, entry by entry.
fn abs(a: Mat3) -> Mat3 {
    Mat3::from_cols(a.x_axis.abs(), a.y_axis.abs(), a.z_axis.abs())
}

/// The instancing part of a scene's geometry: which meshes are placed directly in the world,
/// the prototypes, and their instances. Mesh ids index the scene's one mesh list.
#[derive(Clone, Debug, Default)]
pub struct InstanceSet {
    /// Meshes in world space (not part of any prototype).
    pub world_meshes: Vec<u32>,
    /// Prototypes.
    pub prototypes: Vec<Prototype>,
    /// Instances.
    pub instances: Vec<Instance>,
}

impl InstanceSet {
    /// Object-space bounds of each prototype.
    pub fn prototype_bounds(&self, meshes: &[Mesh]) -> Vec<Bounds3> {
        self.prototypes
            .iter()
            .map(|p| p.meshes.iter().fold(Bounds3::EMPTY, |b, &m| b.union(meshes[m as usize].bounds())))
            .collect()
    }

    /// Triangles the instances place in the world (counting every copy), plus world triangles.
    pub fn placed_triangles(&self, meshes: &[Mesh]) -> usize {
        let proto_tris: Vec<usize> =
            self.prototypes.iter().map(|p| p.meshes.iter().map(|&m| meshes[m as usize].len()).sum()).collect();
        let world: usize = self.world_meshes.iter().map(|&m| meshes[m as usize].len()).sum();
        world + self.instances.iter().map(|i| proto_tris[i.prototype as usize]).sum::<usize>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn singular_and_non_finite_transforms_are_rejected() {
        assert!(Instance::new(0, Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
        assert!(Instance::new(0, Mat4::from_translation(Vec3::NAN)).is_none());
        assert!(Instance::new(0, Mat4::from_scale(Vec3::splat(2.0))).is_some());
    }

    #[test]
    fn the_object_from_world_at_a_time_is_that_of_the_placement_then() {
        let start = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)) * Mat4::from_scale(Vec3::splat(0.5));
        let end = Mat4::from_rotation_y(1.2) * Mat4::from_scale(Vec3::new(2.0, 1.0, 0.7));
        let moving = Instance::animated(0, AnimatedTransform::new(start, 0.0, end, 1.0)).expect("invertible");
        let still = Instance::new(0, start).expect("invertible");
        // A scale through zero at mid-motion: the start placement stands in for it.
        let through_zero = AnimatedTransform::new(start, 0.0, Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)), 1.0);
        let flipping = Instance::animated(0, through_zero).expect("ends invertible");
        for inst in [&moving, &still, &flipping] {
            for time in [-1.0, 0.0, 0.1, 1.0 / 3.0, 0.5, 0.9, 1.0, 2.0] {
                let want = inst.at(time).object_from_world.to_cols_array().map(f32::to_bits);
                assert_eq!(inst.object_from_world_at(time).to_cols_array().map(f32::to_bits), want, "{time}");
            }
        }
    }

    #[test]
    fn cofactor_maps_cross_products_of_transformed_edges() {
        let m = Mat4::from_translation(Vec3::new(1.0, -2.0, 3.0))
            * Mat4::from_rotation_z(0.3)
            * Mat4::from_scale(Vec3::new(2.0, -0.5, 1.5));
        let inst = Instance::new(0, m).unwrap();
        let (a, b) = (Vec3::new(0.3, 1.0, -0.2), Vec3::new(-0.7, 0.1, 0.9));
        let direct = m.transform_vector3(a).cross(m.transform_vector3(b));
        assert!((inst.normal_cofactor * a.cross(b) - direct).length() < 1e-5 * direct.length());
    }

    #[test]
    fn point_error_bound_covers_the_exact_transform() {
        // Compare the f32 transform against f64 arithmetic: the bound must contain the difference.
        let m = Mat4::from_translation(Vec3::new(1e5, -3e4, 7.0))
            * Mat4::from_rotation_y(0.7)
            * Mat4::from_scale(Vec3::splat(3.3));
        let inst = Instance::new(0, m).unwrap();
        let mut seed = 1u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 200.0 - 100.0
        };
        for _ in 0..10_000 {
            let p = Vec3::new(rnd(), rnd(), rnd());
            let (w, err) = inst.point_to_world(p, Vec3::ZERO);
            let cols = m.to_cols_array_2d();
            for (i, wi) in w.to_array().iter().enumerate() {
                let exact = (0..3).map(|j| cols[j][i] as f64 * p[j] as f64).sum::<f64>() + cols[3][i] as f64;
                assert!((*wi as f64 - exact).abs() <= err[i] as f64, "axis {i}: {wi} vs {exact} ± {}", err[i]);
            }
        }
    }
}
