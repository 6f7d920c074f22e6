//! Ambient occlusion (pbrt-v4's `ambientocclusion`): at the camera ray's first surface, the
//! cosine-weighted fraction of the hemisphere about the geometric normal that is open out to a
//! distance, A = (1/π) ∫_Ω V(p, ω) cos θ dω, shown as the output space's white times A (so an
//! unoccluded point is white). Not a light-transport estimate: a visibility image.

use super::interface::Integrator;
use super::state::next_surface;
use super::Stats;
use crate::film::VisibleSurface;
use crate::geometry::Ray;
use crate::math::{Frame, PI};
use crate::sampling::warp::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_hemisphere, uniform_hemisphere_pdf,
};
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{Footprint, RayDifferentials};

impl Integrator {
    /// One sample of the ambient occlusion seen along `ray`: zero where it sees no surface.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn ambient_occlusion(
        &self,
        scene: &Scene,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        visible: Option<&mut Option<VisibleSurface>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> SampledSpectrum {
        let Some(si) = next_surface(scene, ray, stats) else { return SampledSpectrum::zero() };
        if let Some(v) = visible {
            let footprint = Footprint::of_vertex(self.footprint.as_ref(), differentials, true);
            if let Some(bsdf) = si.bsdf(w, footprint) {
                *v = Some(super::visible_surface::visible_surface(&si, &bsdf, footprint));
            }
        }
        // The frame of the geometric normal on the viewer's side (shading normals can point
        // into the surface).
        let n = if si.shading.ng.dot(si.wo) < 0.0 { -si.shading.ng } else { si.shading.ng };
        let u = sampler.get_2d();
        let (local, pdf) = if self.ao.cos_sample {
            let d = sample_cosine_hemisphere(u);
            (d, cosine_hemisphere_pdf(d.z))
        } else {
            (sample_uniform_hemisphere(u), uniform_hemisphere_pdf())
        };
        if pdf <= 0.0 {
            return SampledSpectrum::zero();
        }
        let wi = Frame::from_normal(n).to_world(local);
        let mut probe = si.spawn_ray(wi);
        probe.t_max = self.ao.max_distance;
        stats.rays += 1;
        if scene.occluded(&probe) {
            return SampledSpectrum::zero();
        }
        self.ao.space.illuminant.sample(w) * (wi.dot(n) / (PI * pdf))
    }
}
