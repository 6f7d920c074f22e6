//! The surface interaction at a curve hit: the hit's t and u (from either backend) with the
//! curve give the point, the normal — shading and geometric alike, as pbrt-v4 has them for
//! curves — ∂p/∂u along the curve, ∂p/∂v across it and (u, v)
//! ([`crate::geometry::curve_hit::curve_surface`]). The point's error bound is the curve's
//! width there, so a spawned ray starts clear of the curve it leaves. Under `ReverseOrientation`
//! (or a handedness-swapping transform) both normals are reversed, as pbrt-v4 reverses them.
//! Curves in an object instance are met by the ray carried into the prototype's space (as
//! pbrt-v4 meets curves in their object space), and the surface is carried back.

use super::quadric_interaction::Instanced;
use super::{Bound, SurfaceInteraction, SurfaceNormals};
use crate::geometry::curve_hit::{curve_surface, CurveSurface};
use crate::geometry::{Curves, Hit, Ray};
use crate::scene::{Primitive, Scene};
use glam::{Vec2, Vec3};

impl<'s> SurfaceInteraction<'s> {
    /// The interaction for `hit` of `ray` on `curves`, the geometry of `primitive`.
    pub(super) fn on_curve(scene: &'s Scene, primitive: &'s Primitive, curves: &Curves, ray: &Ray, hit: &Hit) -> Self {
        let instance = Instanced::of(scene, hit.inst_id, ray.time);
        let local = instance.as_ref().map(|i| i.0.ray_to_object(ray));
        let s = Self::curve_point(curves, local.as_ref().unwrap_or(ray), hit);
        let n = if curves.flip_normal { -s.n } else { s.n };
        match instance {
            None => Self::on_analytic_surface(scene, primitive, ray, hit, (s.p, s.p_err), n, (s.dpdu, s.dpdv), s.uv),
            Some(inst) => {
                let p = inst.0.spawn_point_to_world(s.p, s.p_err);
                let (dpdu, dpdv) = (inst.0.vector_to_world(s.dpdu), inst.0.vector_to_world(s.dpdv));
                Self::on_analytic_surface(scene, primitive, ray, hit, p, inst.normal(n), (dpdu, dpdv), s.uv)
            }
        }
    }

    /// The surface of `curves` at `hit` of `ray` (both in the curves' space).
    fn curve_point(curves: &Curves, ray: &Ray, hit: &Hit) -> CurveSurface {
        let seg = &curves.segments[hit.prim_id as usize];
        curve_surface(seg, ray, hit.t, hit.u).unwrap_or_else(|| {
            // A degenerate frame (zero tangent): face the ray.
            let n = -ray.d.normalize_or_zero();
            let w = seg.width_at(hit.u.clamp(0.0, 1.0));
            let dpdu = n.any_orthonormal_vector();
            CurveSurface {
                p: ray.at(hit.t),
                p_err: Vec3::splat(w),
                n,
                dpdu,
                dpdv: n.cross(dpdu) * w,
                uv: Vec2::new(hit.u, 0.5),
            }
        })
    }

    /// The interaction at a point `p` (error bound `p_err`) of an analytic surface whose shading
    /// and geometric normals are both `n`, with ∂p/∂u, ∂p/∂v and (u, v) as the shape gives them.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn on_analytic_surface(
        scene: &'s Scene,
        primitive: &'s Primitive,
        ray: &Ray,
        hit: &Hit,
        (p, p_err): (Vec3, Vec3),
        n: Vec3,
        (dpdu, dpdv): (Vec3, Vec3),
        uv: Vec2,
    ) -> Self {
        Self {
            p,
            p_err,
            shading: SurfaceNormals { ns: n, ng: n },
            dpdu,
            dpdv,
            uv,
            wo: -ray.d.normalize(),
            bound: Some(Bound { scene, primitive }),
            mesh: hit.geom_id,
            prim: hit.prim_id,
            inst: hit.inst_id,
            time: ray.time,
        }
    }
}
