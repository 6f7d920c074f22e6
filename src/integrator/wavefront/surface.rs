//! The surface stage: for each path whose ray hit something (or escaped), the emission found,
//! the vertex count, the material's BSDF with its textures, the light chosen for next-event
//! estimation and the vertex's sampler dimensions, in the scalar loop's order; then the path is
//! queued by its BSDF kind. Scalar: the interaction, texture lookups and light choice read
//! scene data that differs per path.

use super::super::{DirectStrategy, Integrator, Stats};
use super::diffuse::{DiffuseQueue, DiffuseVertex};
use super::other_kinds::{OtherQueue, OtherVertex};
use super::paths::Paths;
use crate::bsdf::Bxdf;
use crate::geometry::Hit;
use crate::light::{Light, LightSampleContext};
use crate::scene::Scene;

/// Runs the stage over the paths `active` (whose rays found `hits`), filling the two queues.
/// Paths that end here (escaped, at the depth limit, on a surface that does not scatter)
/// drop out.
#[allow(clippy::too_many_arguments)]
pub(super) fn surface<'s>(
    integrator: &Integrator,
    scene: &'s Scene,
    paths: &mut Paths,
    active: &[u32],
    hits: &[Option<Hit>],
    diffuse: &mut DiffuseQueue,
    other: &mut OtherQueue<'s>,
    stats: &mut Stats,
) {
    let use_nee = integrator.strategy != DirectStrategy::BsdfOnly;
    for (&k, hit) in active.iter().zip(hits) {
        let k = k as usize;
        let (state, w, ray) = (&mut paths.state[k], &mut paths.lambdas[k], &paths.ray[k]);
        stats.rays += 1;
        let Some(hit) = hit else {
            let d = ray.d.normalize();
            for (id, light) in scene.infinite_lights() {
                let weight = integrator.emission_weight(state, scene.light_pdf(id, &state.prev, d));
                state.l += state.beta * light.escaped_radiance(ray.o, d, w) * weight;
            }
            continue;
        };
        let si = scene.interaction(ray, hit);
        if let Some((id, _)) = si.area_light() {
            let le = si.emitted(w);
            if !le.is_black() {
                let weight = integrator.emission_weight(state, scene.light_pdf(id, &state.prev, -si.wo));
                state.l += state.beta * le * weight;
            }
        }
        if !integrator.next_vertex(state) {
            continue;
        }
        let Some(bsdf) = integrator.vertex_bsdf(&si, w, paths.differentials[k].as_ref(), state) else { continue };
        let flags = bsdf.flags();
        if flags.is_empty() {
            continue;
        }
        let sampler = &mut paths.sampler[k];
        let light = if use_nee && flags.is_non_specular() {
            let ctx = LightSampleContext::surface(si.p, bsdf.ns());
            scene.sample_light(&ctx, sampler.get_2d()).map(|(_, light, pmf, u)| (light, pmf, u))
        } else {
            None
        };
        match &bsdf.bxdf {
            Bxdf::Diffuse(d) => {
                let _uc = sampler.get_1d();
                let u_bsdf = sampler.get_2d();
                let light = light.map(|(l, pmf, u)| {
                    let Light::Area(a) = l else { unreachable!("wavefront::check admits area lights only") };
                    (a, pmf, u, a.spectrum.sample(w) * a.scale)
                });
                diffuse.push(DiffuseVertex {
                    path: k as u32,
                    p: si.p,
                    p_err: si.p_err,
                    ng: si.shading.ng,
                    frame: bsdf.frame,
                    wo: si.wo,
                    rho: d.r,
                    beta: state.beta,
                    light,
                    u_bsdf,
                });
            }
            _ => other.push(OtherVertex { path: k as u32, si, bsdf, light }),
        }
    }
}
