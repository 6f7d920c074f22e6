//! A quadric placed in the world: its object-space shape ([`Quadric`]) with the object-to-world
//! transform (static or moving) and its orientation. Rays are carried into object space and
//! intersected there exactly ([`crate::geometry::quadric_hit`]); the hit point, its error bound,
//! normal and derivatives are carried back (PBR 4th ed. §6.1.3, §6.8.5).
//!
//! The error bound of a world-space hit point is the object-space bound carried through the
//! transform with the transform's own rounding (pbrt-v4 `Transform::operator()(Point3fi)`),
//! plus the rounding of carrying a spawned ray's origin back into object space,
//! γ₃(|M⁻¹| |p| + |t⁻¹|) mapped to world space by |M|: pbrt-v4 carries that error as an
//! interval through its quadratic; here it widens the offset instead, so a ray leaving the
//! surface starts on its own side of it in object space too.

use std::borrow::Cow;

use glam::{Mat3, Mat4, Vec2, Vec3};

use super::animated::AnimatedTransform;
use super::quadric_hit::QuadricHit;
use super::{Bounds3, Instance, Quadric, Ray};

/// Relative margin by which world boxes are grown, as the triangle boxes of the Embree user
/// geometry are (their slab tests round by about 2⁻²⁴ of the coordinates).
const BOX_PAD: f32 = 1.0 / (1u32 << 18) as f32;

/// A quadric with its placement.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedQuadric {
    /// The shape in object space.
    pub quadric: Quadric,
    /// World from object space (moving when its `motion` is set); its prototype is unused.
    pub placement: Instance,
    /// The normal is −∂p/∂u × ∂p/∂v: ReverseOrientation, or a transform that swaps handedness
    /// (pbrt-v4 flips it for either, not for both).
    pub flip_normal: bool,
}

/// The world-space surface at a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricSurface {
    /// Point on the surface.
    pub p: Vec3,
    /// Per-axis bound on the absolute error of `p`.
    pub p_err: Vec3,
    /// Unit normal (geometric and shading alike), flipped as `flip_normal` says.
    pub n: Vec3,
    /// ∂p/∂u.
    pub dpdu: Vec3,
    /// ∂p/∂v.
    pub dpdv: Vec3,
    /// pbrt-v4's (u, v).
    pub uv: Vec2,
    /// World area per unit object area at the point, |det A| |A⁻ᵀ n| (1 under a rigid motion).
    pub area_scale: f32,
}

impl PlacedQuadric {
    /// `quadric` at `world_from_object`; `None` when the transform is singular or not finite.
    pub fn new(quadric: Quadric, world_from_object: Mat4, reverse_orientation: bool) -> Option<Self> {
        let placement = Instance::new(0, world_from_object)?;
        let flip_normal = reverse_orientation ^ (placement.handedness < 0.0);
        Some(Self { quadric, placement, flip_normal })
    }

    /// `quadric` moving by `motion` (static when its two matrices are equal); `None` as
    /// [`PlacedQuadric::new`].
    pub fn moving(quadric: Quadric, motion: AnimatedTransform, reverse_orientation: bool) -> Option<Self> {
        let placement = Instance::animated(0, motion)?;
        let flip_normal = reverse_orientation ^ (placement.handedness < 0.0);
        Some(Self { quadric, placement, flip_normal })
    }

    /// The static quadric carried on by `m` (world from its present world space); `None` when
    /// it moves or the result is singular.
    pub fn placed_by(&self, m: &Mat4) -> Option<Self> {
        if self.moves() {
            return None;
        }
        let reverse = self.flip_normal ^ (self.placement.handedness < 0.0);
        Self::new(self.quadric, *m * self.placement.world_from_object, reverse)
    }

    /// True when the placement moves over the shutter interval.
    pub fn moves(&self) -> bool {
        self.placement.motion.is_some()
    }

    /// World-space box over the whole motion, grown by a relative margin against the rounding
    /// of box tests.
    pub fn bounds(&self) -> Bounds3 {
        self.placement.world_bounds(self.quadric.object_bounds()).padded(BOX_PAD)
    }

    /// The ray in object space at its time: origin, direction, and the placement used.
    #[inline]
    fn object_ray(&self, ray: &Ray) -> (Vec3, Vec3, Cow<'_, Instance>) {
        let inst = self.placement.placed_at(ray.time);
        let m = &inst.object_from_world;
        (m.transform_point3(ray.o), m.transform_vector3(ray.d), inst)
    }

    /// The ray parameter of the nearest hit with t in (0, `t_max`), if any (t is the same in
    /// object and world space: the map is affine).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let m = self.placement.object_from_world_at(ray.time);
        self.quadric.intersect_t(m.transform_point3(ray.o), m.transform_vector3(ray.d), t_max)
    }

    /// The surface where `ray` meets the shape at `t` (a hit [`PlacedQuadric::intersect`]
    /// found), in world space.
    pub fn surface(&self, ray: &Ray, t: f32) -> QuadricSurface {
        let (o, d, inst) = self.object_ray(ray);
        self.carried_to_world(&inst, &self.quadric.surface_at(o, d, t))
    }

    /// [`PlacedQuadric::surface`] without (u, v) and the derivatives (left zero), for a
    /// boundary between media.
    pub fn boundary(&self, ray: &Ray, t: f32) -> QuadricSurface {
        let (o, d, inst) = self.object_ray(ray);
        self.carried_to_world(&inst, &self.quadric.boundary_at(o, d, t))
    }

    /// The object-space hit `h` carried to world space by `inst`.
    fn carried_to_world(&self, inst: &Instance, h: &QuadricHit) -> QuadricSurface {
        let (p, p_err) = inst.spawn_point_to_world(h.p, h.p_err);
        let n = inst.normal_to_world(h.n);
        QuadricSurface {
            area_scale: (inst.normal_cofactor * h.n).length(),
            p,
            p_err,
            n: if self.flip_normal { -n } else { n },
            dpdu: inst.vector_to_world(h.dpdu),
            dpdv: inst.vector_to_world(h.dpdv),
            uv: h.uv,
        }
    }

    /// ∂n/∂u and ∂n/∂v in world space at the hit of `ray` at `t` (normals carried by the
    /// inverse transpose, as pbrt-v4 carries them; reversed with the normal).
    pub fn normal_derivatives(&self, ray: &Ray, t: f32) -> (Vec3, Vec3) {
        let (o, d, inst) = self.object_ray(ray);
        let h = self.quadric.surface_at(o, d, t);
        let (dndu, dndv) = self.quadric.normal_derivatives(&h);
        // A⁻ᵀ = cofactor / det A.
        let det = Mat3::from_mat4(inst.world_from_object).determinant();
        let to_world = |v: Vec3| {
            let w = inst.normal_cofactor * v / det;
            if self.flip_normal {
                -w
            } else {
                w
            }
        };
        (to_world(dndu), to_world(dndv))
    }

    /// World-space area [scene units²]: the object area times k² under a similarity of scale
    /// k, else the area of the transformed tessellation ([`Quadric::tessellate`], within 10⁻³).
    pub fn area(&self) -> f32 {
        match super::quadric::similarity_scale(&self.placement.world_from_object) {
            Some(k) => self.quadric.area() * k * k,
            None => self.quadric.tessellate().transformed(&self.placement.world_from_object).area(),
        }
    }

    /// The full sphere's world centre and radius, when the shape is a full sphere under a
    /// static similarity (the shape pbrt-v4 samples by solid angle).
    pub fn full_sphere(&self) -> Option<(Vec3, f32)> {
        let Quadric::Sphere { radius, .. } = self.quadric else { return None };
        let k = super::quadric::similarity_scale(&self.placement.world_from_object)?;
        (self.quadric.is_full_sphere() && !self.moves())
            .then(|| (self.placement.world_from_object.transform_point3(Vec3::ZERO), radius * k))
    }

    /// The world-space point, unit normal (flipped as the surface's) and the area element
    /// |∂p_world/∂p_object| (world area per unit object area) at object parameters (u, v).
    pub fn point(&self, u: f32, v: f32) -> (Vec3, Vec3, f32) {
        let q = self.quadric.point(u, v);
        let inst = &self.placement;
        let scaled = inst.normal_cofactor * q.n;
        let n = scaled.normalize_or_zero() * inst.handedness;
        (inst.world_from_object.transform_point3(q.p), if self.flip_normal { -n } else { n }, scaled.length())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::offset_ray_origin;
    use crate::sampling::rng::Rng;
    use glam::Quat;

    /// From random points of each shape, at scales from 10⁻³ to 10⁴ and as far as 10⁴ from the
    /// origin, rays spawned in random directions on either side (their origins offset past the
    /// error bound, as `SurfaceInteraction::spawn_ray` does) never meet the surface again at
    /// the point they left: any hit is at least 10⁻³ of the shape's size away (a ray into a
    /// sphere or cylinder meets its far side, a disk none).
    #[test]
    fn spawned_rays_never_re_hit_the_surface_they_leave() {
        let shapes = [
            Quadric::Sphere { radius: 1.0, z_min: -1.0, z_max: 1.0, phi_max: 360.0 },
            Quadric::Sphere { radius: 1.0, z_min: -0.7, z_max: 0.4, phi_max: 300.0 },
            Quadric::Cylinder { radius: 1.0, z_min: -1.0, z_max: 1.0, phi_max: 270.0 },
            Quadric::Disk { height: 0.3, radius: 1.0, inner_radius: 0.2, phi_max: 360.0 },
        ];
        let mut rng = Rng::new(17, 4);
        let mut spawned = 0;
        for q in shapes {
            for &scale in &[1e-3f32, 1.0, 37.0, 1e4] {
                for &offset in &[0.0f32, 1.0, 1e3, 1e4] {
                    let axis = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalize();
                    let at = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * offset;
                    let m =
                        Mat4::from_scale_rotation_translation(Vec3::splat(scale), Quat::from_axis_angle(axis, 1.3), at);
                    let placed = PlacedQuadric::new(q, m, false).unwrap();
                    for _ in 0..2000 {
                        // A hit by a ray from outside at a random point of the shape.
                        let (target, n, _) = placed.point(rng.uniform(), rng.uniform());
                        let o = target + n * (3.0 * scale) + n.any_orthonormal_vector() * (rng.uniform() - 0.5) * scale;
                        let ray = Ray::new(o, (target - o).normalize());
                        let Some(t) = placed.intersect(&ray, f32::INFINITY) else { continue };
                        let s = placed.surface(&ray, t);
                        let d = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalize();
                        let next = Ray::new(offset_ray_origin(s.p, s.p_err, s.n, d), d);
                        spawned += 1;
                        if let Some(t2) = placed.intersect(&next, f32::INFINITY) {
                            assert!(t2 > 1e-3 * scale, "{q:?} scale {scale} at {at}: re-hit at t = {t2} from {}", s.p);
                        }
                    }
                }
            }
        }
        assert!(spawned > 50_000, "{spawned} spawned rays");
    }
}
