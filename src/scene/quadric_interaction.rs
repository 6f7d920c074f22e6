//! The surface interaction at a quadric hit: the hit's t (from either backend) with the ray and
//! the quadric give the point re-projected onto the surface, its error bound, the analytic
//! normal — shading and geometric alike, as pbrt-v4 has them for quadrics — pbrt-v4's (u, v),
//! ∂p/∂u and ∂p/∂v ([`PlacedQuadric::surface`]); bump mapping gets ∂n/∂u and ∂n/∂v from the
//! Weingarten equations ([`PlacedQuadric::normal_derivatives`]). Under ReverseOrientation, or
//! a transform that swaps handedness, the normal is reversed, as pbrt-v4 reverses it.
//!
//! A quadric in an object instance is placed in the prototype's space: the ray is carried there
//! by the instance's transform at the ray's time, and the surface back ([`Instanced`]).

use super::SurfaceInteraction;
use crate::geometry::{Hit, Instance, PlacedQuadric, QuadricSurface, Ray};
use crate::material::ShadingDerivatives;
use crate::scene::{Primitive, Scene};
use glam::{Mat3, Vec3};

/// An object instance placed at a ray's time, which carries surfaces found in its prototype's
/// space to the world.
pub(super) struct Instanced(pub(super) Instance);

impl Instanced {
    /// The instance `hit` names in `scene`, placed at `time` (`None` for world geometry).
    #[inline]
    pub(super) fn of(scene: &Scene, hit_instance: u32, time: f32) -> Option<Self> {
        scene.instances.get(hit_instance as usize).map(|i| Self(i.at(time)))
    }

    /// A surface normal in world space: by the inverse transpose, and reversed when the instance
    /// swaps handedness, as the normal of the shape's flattened copy (whose own transform then
    /// swaps it) is.
    #[inline]
    pub(super) fn normal(&self, n: Vec3) -> Vec3 {
        self.0.normal_to_world(n) * self.0.handedness
    }

    /// `s` (in the prototype's space) in world space: the point with its error bound widened for
    /// rays spawned from it ([`Instance::spawn_point_to_world`]), the normal, ∂p/∂u and ∂p/∂v.
    pub(super) fn surface(&self, s: QuadricSurface) -> QuadricSurface {
        let (p, p_err) = self.0.spawn_point_to_world(s.p, s.p_err);
        let (dpdu, dpdv) = (self.0.vector_to_world(s.dpdu), self.0.vector_to_world(s.dpdv));
        QuadricSurface { p, p_err, n: self.normal(s.n), dpdu, dpdv, uv: s.uv, area_scale: s.area_scale }
    }
}

impl<'s> SurfaceInteraction<'s> {
    /// The interaction for `hit` of `ray` on `quadric`, the geometry of `primitive`.
    pub(super) fn on_quadric(
        scene: &'s Scene,
        primitive: &'s Primitive,
        quadric: &PlacedQuadric,
        ray: &Ray,
        hit: &Hit,
    ) -> Self {
        let surface = |ray: &Ray| {
            if primitive.bare_boundary {
                quadric.boundary(ray, hit.t)
            } else {
                quadric.surface(ray, hit.t)
            }
        };
        let s = match Instanced::of(scene, hit.inst_id, ray.time) {
            None => surface(ray),
            Some(inst) => inst.surface(surface(&inst.0.ray_to_object(ray))),
        };
        Self::on_analytic_surface(scene, primitive, ray, hit, (s.p, s.p_err), s.n, (s.dpdu, s.dpdv), s.uv)
    }

    /// pbrt-v4's shading derivatives of a quadric: ∂p/∂u, ∂p/∂v and ∂n/∂u, ∂n/∂v at this
    /// point, found again from the ray back along `wo` to it.
    pub(super) fn quadric_derivatives(&self, scene: &Scene, quadric: &PlacedQuadric) -> ShadingDerivatives {
        // A ray that meets the surface at t = 1 (the point is on it; only its object-space
        // position matters).
        let ray = Ray { o: self.p + self.wo, d: -self.wo, t_max: f32::INFINITY, time: self.time };
        let (dndu, dndv) = match Instanced::of(scene, self.inst, self.time) {
            None => quadric.normal_derivatives(&ray, 1.0),
            Some(inst) => {
                // Normals' derivatives go to world space as normals do: by A⁻ᵀ = cofactor / det A.
                let (dndu, dndv) = quadric.normal_derivatives(&inst.0.ray_to_object(&ray), 1.0);
                let det = Mat3::from_mat4(inst.0.world_from_object).determinant();
                let to_world = |v: Vec3| inst.0.normal_cofactor * v / det * inst.0.handedness;
                (to_world(dndu), to_world(dndv))
            }
        };
        ShadingDerivatives { dpdu: self.dpdu, dpdv: self.dpdv, dndu, dndv }
    }
}
