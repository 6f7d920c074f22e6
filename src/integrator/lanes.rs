//! Paths in lanes: the path tracer of [`super::PathIntegrator`] advancing `N` camera paths
//! together, one per SIMD lane, with divergence expressed by masks (the design of Mitsuba 3's
//! vectorised variants; Jakob et al. 2022). Rays are traced eight at a time as Embree packets
//! (`rtcIntersect8`/`rtcOccluded8`) or one by one; the BSDF, the light sample, MIS, the ray
//! offsets and Russian roulette run on lanes through the same lane-generic code the scalar
//! renderer runs with one lane. What each lane reads from the scene (the hit's geometry, the
//! material's reflectance at its wavelengths, the light it picked, its sampler's numbers) is
//! gathered lane by lane.
//!
//! A prototype for measuring the design: it renders scenes whose materials are all Lambertian
//! and whose lights are all area lights ([`LaneTracer::new`] refuses others). Each lane draws
//! its sampler's dimensions in the scalar path's order, so a lane's path equals the scalar
//! path of the same sample up to rounding.

// Lane code reads and writes several per-lane arrays at one lane index.
#![allow(clippy::needless_range_loop)]

use super::path::PathIntegrator;
use super::{DirectStrategy, Stats};
use crate::bsdf::{BsdfLanes, Bxdf, DiffuseLanes};
use crate::geometry::Ray;
use crate::light::{AreaLight, Light, LightSampleContext, TriangleLightLanes};
use crate::material::Material;
use crate::math::offset::offset_ray_origin_lanes;
use crate::math::FrameLanes;
use crate::sampling::mis::power_heuristic_lanes;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::simd::{Lanes, LanesMask, Mask, Real, S4, V3};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::Footprint;

/// How a group of rays is traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LaneTrace {
    /// As one packet (`Accel::intersect8`: Embree's `rtcIntersect8`).
    Packet,
    /// One `Accel::intersect` per lane.
    Single,
}

/// Lanes per group: one AVX2 register of f32, and Embree's 8-ray packet.
pub const LANES: usize = 8;

type L = Lanes<LANES>;
type M = LanesMask<LANES>;

/// The lane path tracer over one scene.
pub struct LaneTracer<'s> {
    integrator: PathIntegrator,
    scene: &'s Scene,
    trace: LaneTrace,
    /// A light of the scene, to fill the lanes that take no light sample.
    filler: &'s AreaLight,
}

/// Why a scene cannot be rendered in lanes.
#[derive(Debug, thiserror::Error)]
#[error("the lane path tracer renders only Lambertian materials, area lights and MIS; {0}")]
pub struct Unsupported(String);

impl<'s> LaneTracer<'s> {
    /// A tracer for `scene`, or why the prototype cannot render it.
    pub fn new(integrator: PathIntegrator, scene: &'s Scene, trace: LaneTrace) -> Result<Self, Unsupported> {
        if let Some(m) = scene.materials().iter().find(|m| !matches!(m, Material::Diffuse { .. })) {
            return Err(Unsupported(format!("this scene has a material that is not Lambertian ({m:.40?}…)")));
        }
        if scene.lights().iter().any(|l| !matches!(l, Light::Area(AreaLight { image: None, .. }))) {
            return Err(Unsupported("this scene has lights other than untextured area lights".into()));
        }
        if integrator.strategy != DirectStrategy::Mis {
            return Err(Unsupported("another direct-light strategy was chosen".into()));
        }
        let Some(Light::Area(filler)) = scene.lights().first() else {
            return Err(Unsupported("this scene has no light".into()));
        };
        Ok(Self { integrator, scene, trace, filler })
    }

    fn intersect(&self, rays: &[Ray; LANES], active: M) -> [Option<crate::geometry::Hit>; LANES] {
        let accel = self.scene.accel();
        match self.trace {
            LaneTrace::Packet => accel.intersect8(rays, &active.0),
            LaneTrace::Single => std::array::from_fn(|i| if active.0[i] { accel.intersect(&rays[i]) } else { None }),
        }
    }

    fn occluded(&self, rays: &[Ray; LANES], active: M) -> [bool; LANES] {
        let accel = self.scene.accel();
        match self.trace {
            LaneTrace::Packet => accel.occluded8(rays, &active.0),
            LaneTrace::Single => std::array::from_fn(|i| active.0[i] && accel.occluded(&rays[i])),
        }
    }

    /// Radiance along each lane's camera ray at its wavelengths (the lanes of `active`; the
    /// others are returned as zero), as [`PathIntegrator::li`] per lane.
    pub fn li(
        &self,
        camera: [Ray; LANES],
        w: &mut [SampledWavelengths; LANES],
        samplers: &mut [Sampler; LANES],
        mut active: M,
        stats: &mut Stats,
    ) -> [SampledSpectrum; LANES] {
        let scene = self.scene;
        let zero = L::splat(0.0);
        let mut l = S4::<L>::splat(0.0);
        let mut beta = S4::<L>::splat(1.0);
        let mut prev_p = V3::<L>::splat(glam::Vec3::ZERO);
        // The previous vertex's shading normal (zero at the camera), for the light sampler's pmf.
        let mut prev_n = V3::<L>::splat(glam::Vec3::ZERO);
        for (i, r) in camera.iter().enumerate() {
            prev_p.set_lane(i, r.o);
        }
        let mut prev_pdf = zero;
        let mut specular = M::splat(true);
        let mut rays = camera;
        let mut depth = 0u32;
        let cap = if self.integrator.max_depth == super::UNBOUNDED_DEPTH { 0.95 } else { 1.0 };
        loop {
            // The next vertex of every lane, and the emission the ray finds there.
            stats.rays += active.0.iter().filter(|&&a| a).count() as u64;
            let hits = self.intersect(&rays, active);
            let mut p = V3::<L>::splat(glam::Vec3::ZERO);
            let (mut p_err, mut ng, mut ns, mut dpdu, mut wo) = (p, p, p, p, p);
            let mut rho = S4::<L>::splat(0.0);
            for i in 0..LANES {
                if !active.0[i] {
                    continue;
                }
                let Some(hit) = hits[i] else {
                    active.0[i] = false; // no infinite lights: an escaped path is done
                    continue;
                };
                let si = scene.interaction(&rays[i], &hit);
                if let Some((id, _)) = si.area_light() {
                    let le = si.emitted(&w[i]);
                    if !le.is_black() {
                        let weight = if specular.0[i] {
                            1.0
                        } else {
                            let prev = LightSampleContext::surface(prev_p.lane(i), prev_n.lane(i));
                            let light_pdf = scene.light_pdf(id, &prev, -si.wo);
                            power_heuristic_lanes(prev_pdf.0[i], light_pdf)
                        };
                        let li = l.lane(i) + beta.lane(i) * le * weight;
                        l.set_lane(i, li);
                    }
                }
                let Some(Bxdf::Diffuse(d)) =
                    si.bsdf(&mut w[i], self.integrator.footprint.as_ref().map(Footprint::Camera)).map(|b| b.bxdf)
                else {
                    unreachable!("LaneTracer::new admits Lambertian materials only")
                };
                rho.set_lane(i, d.r);
                p.set_lane(i, si.p);
                p_err.set_lane(i, si.p_err);
                ng.set_lane(i, si.shading.ng);
                ns.set_lane(i, si.shading.ns);
                dpdu.set_lane(i, si.dpdu);
                wo.set_lane(i, si.wo);
            }
            // Every vertex counts toward the depth limit (the same for every lane in step).
            if depth == self.integrator.max_depth || !active.any() {
                break;
            }
            depth += 1;
            let bsdf = BsdfLanes { frame: FrameLanes::from_normal_tangent(ns, dpdu), bxdf: DiffuseLanes { r: rho } };
            active = active & !rho.is_black();

            // Next-event estimation: each lane picks a light and a point on it.
            let mut light = TriangleLightLanes::<L>::splat(self.filler);
            let mut pmf = zero;
            let mut le = S4::<L>::splat(0.0);
            let (mut ux, mut uy) = (zero, zero);
            for i in 0..LANES {
                if !active.0[i] {
                    continue;
                }
                let ctx = LightSampleContext::surface(p.lane(i), ns.lane(i));
                let Some((_, Light::Area(a), lpmf, u)) = scene.sample_light(&ctx, samplers[i].get_2d()) else {
                    continue;
                };
                (ux.0[i], uy.0[i]) = (u.x, u.y);
                pmf.0[i] = lpmf;
                for k in 0..3 {
                    light.p[k].set_lane(i, a.p[k]);
                }
                light.n.set_lane(i, a.n);
                light.area.0[i] = a.area;
                light.two_sided.0[i] = a.two_sided;
                le.set_lane(i, a.spectrum.sample(&w[i]) * a.scale);
            }
            let ls = light.sample(p, ux, uy);
            let f = bsdf.f(wo, ls.wi).scale(ls.wi.dot(ns).abs());
            let shadow_active = active & ls.valid & zero.lt(pmf) & !le.is_black() & !f.is_black();
            let to_light = ls.p_light - p;
            let o = offset_ray_origin_lanes(p, p_err, ng, to_light);
            let d = ls.p_light - o;
            let time: [f32; LANES] = std::array::from_fn(|i| rays[i].time);
            let shadow: [Ray; LANES] =
                std::array::from_fn(|i| Ray::segment(o.lane(i), d.lane(i), 1.0 - 1e-4).at_time(time[i]));
            stats.rays += shadow_active.0.iter().filter(|&&a| a).count() as u64;
            let blocked = LanesMask(self.occluded(&shadow, shadow_active));
            let p_light = pmf * ls.pdf;
            let weight = power_heuristic_lanes(p_light, bsdf.pdf(wo, ls.wi));
            let ld = (f * le).scale(weight / p_light);
            l += beta * S4::select(shadow_active & !blocked, ld, S4::splat(0.0));

            // Continue every path by sampling its BSDF.
            for i in 0..LANES {
                if active.0[i] {
                    let _uc = samplers[i].get_1d();
                    let u = samplers[i].get_2d();
                    (ux.0[i], uy.0[i]) = (u.x, u.y);
                }
            }
            let bs = bsdf.sample_f(wo, ux, uy);
            let cos = bs.wi.dot(ns).abs();
            active = active & bs.valid;
            beta = S4::select(active, beta * bs.f.scale(cos / bs.pdf), beta);
            prev_pdf = bs.pdf;
            specular = M::splat(false);
            let o = offset_ray_origin_lanes(p, p_err, ng, bs.wi);
            rays = std::array::from_fn(|i| Ray::new(o.lane(i), bs.wi.lane(i)).at_time(time[i]));
            prev_p = p;
            prev_n = ns;
            active = active & !beta.is_black();

            // Russian roulette, as the scalar path (no refraction here, so η scale is 1).
            if depth >= self.integrator.rr_depth {
                let survival = beta.max_value().min(L::splat(cap));
                let mut q = zero;
                for i in 0..LANES {
                    if active.0[i] && survival.0[i] < 1.0 {
                        let qi = (1.0 - survival.0[i]).max(0.0);
                        if samplers[i].get_1d() < qi {
                            active.0[i] = false;
                        }
                        q.0[i] = qi;
                    }
                }
                beta = beta.scale(L::splat(1.0) / (L::splat(1.0) - q));
            }
        }
        stats.last_depth = depth;
        std::array::from_fn(|i| l.lane(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::AccelKind;
    use crate::render::{render, RenderSettings, SamplerKind};
    use crate::scene::SceneBuilder;

    fn cornell(kind: AccelKind, lanes: Option<LaneTrace>, sampler: SamplerKind) -> Vec<glam::DVec3> {
        let scene = SceneBuilder::cornell_box().build(kind).unwrap();
        // 21 columns: the last group of every band is partial.
        let settings = RenderSettings { resolution: (21, 16), spp: 8, sampler, lanes, ..Default::default() };
        let (film, _) = render(&scene, &settings, |_| {}).unwrap();
        film.pixels.iter().map(|p| p.xyz_sum / p.weight_sum).collect()
    }

    /// Each lane draws its sampler's numbers in the scalar path's order and runs the same
    /// lane-generic physics, so the image equals the scalar one pixel by pixel, up to rounding
    /// (a differently rounded direction could send one path elsewhere; at these 2688 paths none
    /// does). A lane tracer that skipped NEE, MIS or Russian roulette in any lane, mixed up lanes
    /// or lost the partial group would differ by whole path contributions.
    #[test]
    fn the_lane_tracer_renders_the_scalar_image() {
        let mut kinds = vec![AccelKind::Obvhs];
        if cfg!(embree) {
            kinds.push(AccelKind::Embree);
        }
        for kind in kinds {
            for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
                let scalar = cornell(kind, None, sampler);
                let mean = scalar.iter().map(|v| v.y).sum::<f64>() / scalar.len() as f64;
                assert!(mean > 0.01, "black image: {mean}");
                for trace in [LaneTrace::Packet, LaneTrace::Single] {
                    let lanes = cornell(kind, Some(trace), sampler);
                    for (i, (a, b)) in scalar.iter().zip(&lanes).enumerate() {
                        let d = (*a - *b).abs().max_element();
                        assert!(d <= 1e-4 * mean, "{kind:?} {sampler:?} {trace:?} pixel {i}: {a} vs {b}");
                    }
                }
            }
        }
    }

    #[test]
    fn scenes_outside_the_prototype_are_refused() {
        let mut b = SceneBuilder::cornell_box();
        b.add_material(Material::Dielectric {
            eta: crate::material::Ior::Constant(1.5),
            roughness: crate::material::Roughness::alpha(0.0),
        });
        let scene = b.build(AccelKind::Obvhs).unwrap();
        let e = LaneTracer::new(PathIntegrator::default(), &scene, LaneTrace::Single).err().expect("refused");
        assert!(e.to_string().contains("not Lambertian"), "{e}");
    }
}
