//! The surface interaction at a quadric hit: the hit's t (from either backend) with the ray and
//! the quadric give the point re-projected onto the surface, its error bound, the analytic
//! normal — shading and geometric alike, as pbrt-v4 has them for quadrics — pbrt-v4's (u, v),
//! ∂p/∂u and ∂p/∂v ([`PlacedQuadric::surface`]); bump mapping gets ∂n/∂u and ∂n/∂v from the
//! Weingarten equations ([`PlacedQuadric::normal_derivatives`]). Under ReverseOrientation, or
//! a transform that swaps handedness, the normal is reversed, as pbrt-v4 reverses it.

use super::SurfaceInteraction;
use crate::geometry::{Hit, PlacedQuadric, Ray};
use crate::material::ShadingDerivatives;
use crate::scene::{Primitive, Scene};

impl<'s> SurfaceInteraction<'s> {
    /// The interaction for `hit` of `ray` on `quadric`, the geometry of `primitive`.
    pub(super) fn on_quadric(
        scene: &'s Scene,
        primitive: &'s Primitive,
        quadric: &PlacedQuadric,
        ray: &Ray,
        hit: &Hit,
    ) -> Self {
        let s = if primitive.bare_boundary { quadric.boundary(ray, hit.t) } else { quadric.surface(ray, hit.t) };
        Self::on_analytic_surface(scene, primitive, ray, hit, (s.p, s.p_err), s.n, (s.dpdu, s.dpdv), s.uv)
    }

    /// pbrt-v4's shading derivatives of a quadric: ∂p/∂u, ∂p/∂v and ∂n/∂u, ∂n/∂v at this
    /// point, found again from the ray back along `wo` to it.
    pub(super) fn quadric_derivatives(&self, quadric: &PlacedQuadric) -> ShadingDerivatives {
        // A ray that meets the surface at t = 1 (the point is on it; only its object-space
        // position matters).
        let ray = Ray { o: self.p + self.wo, d: -self.wo, t_max: f32::INFINITY, time: self.time };
        let (dndu, dndv) = quadric.normal_derivatives(&ray, 1.0);
        ShadingDerivatives { dpdu: self.dpdu, dpdv: self.dpdv, dndu, dndv }
    }
}
