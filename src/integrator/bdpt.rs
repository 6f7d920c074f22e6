//! Bidirectional path tracing (Veach & Guibas 1995; Veach 1997, ch. 10; PBR 3rd ed. §16.3;
//! pbrt-v4 `BDPTIntegrator`): per camera sample, a camera subpath and a light subpath (its
//! light chosen in proportion to power), and every connection of a prefix of one with a prefix
//! of the other (s light vertices, t camera vertices, s + t − 2 ≤ `max_depth` scattering
//! vertices between), each weighted by the balance heuristic over all strategies that could
//! have made the same path ([`super::bdpt_weights`]). Connections with one camera vertex
//! (t = 1) land at film positions of their own and are splatted; s = 1 samples a new point on a
//! light, t = 1 a new point on the lens.
//!
//! Lights at infinity (Veach 1997 §10.3.5; PBR 3rd ed. §16.3): a light subpath from one starts
//! on a disk across the scene's bounding sphere ([`Light::sample_le`]); a camera subpath that
//! escapes the scene ends at a vertex at infinity that sees every infinite light at once. The
//! densities at such a vertex stay per solid angle (the direction is the vertex), the light's
//! origin density is Σ over the infinite lights of (choice probability × direction density),
//! and the next vertex's area density is that of the disk, 1/(π r²), times its cosine.
//!
//! Participating media (Veach 1997 §10.3.4 and pbrt-v4's `RandomWalk`): the walks sample free
//! flights by delta tracking ([`super::free_flight`]), and a real scattering is a vertex like a
//! surface's, its phase function in place of a BSDF and no cosine where densities turn from
//! solid angle to area; every connection carries the transmittance of its segment by ratio
//! tracking, and interface surfaces (no BSDF) are passed through. As in pbrt-v4, the densities
//! of the MIS weights leave out the free flights' distance densities (σ_s T; the weights stay a
//! partition of unity, only less close to the balance heuristic's), and media do not emit. A
//! subsurface material scatters as its boundary BSDF alone, as in pbrt-v4's `bdpt`.
//! No Russian roulette (as pbrt-v4's): subpaths end at the depth limit or where a BSDF samples
//! nothing.

use super::bdpt_weights::{balance_weight, DensityPath, VertexDensity};
use super::free_flight::{free_flight, segment_transmittance, spectral_mis, Flight};
use super::interface::Integrator;
use super::lightpath::light_point_error;
use super::options::StrategyImageKind;
use super::state::{escaped_radiance, PathState};
use super::{SplatSample, Stats};
use crate::bsdf::{Bsdf, TransportMode};
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::light::{Light, LightSampleContext};
use crate::math::offset_ray_origin;
use crate::media::HenyeyGreenstein;
use crate::sampling::{PssStream, Sampler};
use crate::scene::{Crossings, LightId, Scene, SurfaceInteraction};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::RayDifferentials;
use glam::{Vec2, Vec3, Vec4};

/// What a subpath vertex is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// The point on the lens.
    Camera,
    /// The point on a light that starts the light subpath (for a light at infinity, the point
    /// its ray starts from).
    Light(LightId),
    /// Where a camera subpath escaped the scene: light from every infinite light.
    Sky,
    /// A surface the subpath scattered at.
    Surface,
    /// A real scattering in a medium, with its phase function.
    Medium(HenyeyGreenstein),
}

/// One vertex of a subpath (pbrt's `Vertex`).
#[derive(Clone, Debug)]
struct Vertex<'s> {
    kind: Kind,
    p: Vec3,
    /// Geometric normal (zero at a point: a point light, a pinhole).
    ng: Vec3,
    /// Shading normal.
    ns: Vec3,
    /// Unit direction toward the previous vertex of its subpath; at infinity, the direction
    /// its light travels into the scene.
    wo: Vec3,
    /// A vertex at infinity: a light at infinity, or the sky.
    infinite: bool,
    si: Option<SurfaceInteraction<'s>>,
    bsdf: Option<Bsdf>,
    /// Radiance for camera subpaths, importance for light subpaths.
    mode: TransportMode,
    /// The subpath's throughput up to this vertex (for the first light vertex, L_e / p), at
    /// the hero wavelength's free-flight distances.
    beta: SampledSpectrum,
    /// The rescaled probability of the subpath's free flights up to this vertex (one outside
    /// media): the spectral MIS of a path divides by the average of its parts' product.
    r_u: SampledSpectrum,
    /// Scattered by a delta lobe.
    delta: bool,
    /// Area density with which its own subpath reached it.
    pdf_fwd: f32,
    /// Area density with which the other subpath would reach it (through the vertices after it).
    pdf_rev: f32,
    /// The medium it sits in; at a surface, the one the subpath reached it through.
    medium: Option<u32>,
}

impl<'s> Vertex<'s> {
    fn point(kind: Kind, p: Vec3, n: Vec3, mode: TransportMode, beta: SampledSpectrum, pdf_fwd: f32) -> Self {
        Vertex {
            kind,
            p,
            ng: n,
            ns: n,
            wo: Vec3::ZERO,
            infinite: false,
            si: None,
            bsdf: None,
            mode,
            beta,
            r_u: SampledSpectrum::one(),
            delta: false,
            pdf_fwd,
            pdf_rev: 0.0,
            medium: None,
        }
    }

    /// A vertex at infinity from which light travels along the unit direction `d`.
    fn at_infinity(mut self, d: Vec3) -> Self {
        self.infinite = true;
        self.wo = d;
        self
    }

    /// True for vertices that connections may end at.
    fn connectible(&self) -> bool {
        match self.kind {
            Kind::Surface => !self.delta && self.bsdf.as_ref().is_some_and(|b| b.flags().is_non_specular()),
            Kind::Sky => false,
            Kind::Camera | Kind::Light(_) | Kind::Medium(_) => true,
        }
    }

    /// |cos θ| of the unit direction `d` to the shading normal; 1 at a point (a medium vertex,
    /// a point light).
    fn cos(&self, d: Vec3) -> f32 {
        if self.ns == Vec3::ZERO {
            1.0
        } else {
            self.ns.dot(d).abs()
        }
    }

    /// The medium a ray leaving this vertex along `d` starts in.
    fn medium_toward(&self, d: Vec3) -> Option<u32> {
        match &self.si {
            Some(si) => si.medium_interface().medium_toward(d, si.shading.ng, self.medium),
            None => self.medium,
        }
    }

    /// A shadow ray from this scattering vertex to the point `p` (short of it).
    fn ray_to(&self, p: Vec3, time: f32) -> Ray {
        match &self.si {
            Some(si) => si.spawn_ray_to(p),
            None => Ray::segment(self.p, p - self.p, 1.0 - 1e-4).at_time(time),
        }
    }

    /// A ray from this scattering vertex along the unit direction `d`.
    fn ray_toward(&self, d: Vec3, time: f32) -> Ray {
        match &self.si {
            Some(si) => si.spawn_ray(d),
            None => Ray::new(self.p, d).at_time(time),
        }
    }

    /// Unit direction from this vertex toward `other` (either may be at infinity).
    fn dir_to(&self, other: &Vertex) -> Vec3 {
        if other.infinite {
            -other.wo
        } else if self.infinite {
            self.wo
        } else {
            (other.p - self.p).normalize()
        }
    }

    /// The light this vertex emits as: the light vertex's, or a surface's area light.
    fn light<'a>(&self, scene: &'a Scene) -> Option<(LightId, &'a Light)>
    where
        's: 'a,
    {
        match self.kind {
            Kind::Light(id) => Some((id, &scene.lights()[id as usize])),
            Kind::Surface => self.si.as_ref().and_then(|si| si.area_light()),
            Kind::Camera | Kind::Sky | Kind::Medium(_) => None,
        }
    }

    /// BSDF (or phase function) value toward `next` (f only, no cosine).
    fn f(&self, next: &Vertex) -> SampledSpectrum {
        self.f_toward(self.dir_to(next))
    }

    /// BSDF (or phase function) value toward the unit direction `wi`.
    fn f_toward(&self, wi: Vec3) -> SampledSpectrum {
        match (&self.bsdf, self.kind) {
            (Some(b), _) => b.f(self.wo, wi, self.mode),
            (None, Kind::Medium(phase)) => SampledSpectrum::splat(phase.p(-self.wo, wi)),
            _ => SampledSpectrum::zero(),
        }
    }

    /// Area density at `next` of the solid-angle density `pdf` of a direction from here; at a
    /// vertex at infinity the density stays per solid angle.
    fn to_area(&self, pdf: f32, next: &Vertex) -> f32 {
        if next.infinite {
            return pdf;
        }
        let w = next.p - self.p;
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let mut pdf = pdf / d2;
        if next.ng != Vec3::ZERO {
            pdf *= next.ng.dot(w / d2.sqrt()).abs();
        }
        pdf
    }

    /// Area density with which this vertex, reached from `prev`, samples `next` (pbrt
    /// `Vertex::Pdf`); a light vertex samples it by its emission.
    fn pdf(&self, scene: &Scene, camera: &Camera, time: f32, prev: Option<&Vertex>, next: &Vertex) -> f32 {
        let wn = self.dir_to(next);
        let pdf = match self.kind {
            Kind::Light(_) | Kind::Sky => return self.pdf_light(scene, next),
            Kind::Camera => camera.pdf_we(self.p, wn, time).1,
            Kind::Surface => match (&self.bsdf, prev) {
                (Some(b), Some(prev)) => b.pdf(self.dir_to(prev), wn, self.mode),
                _ => 0.0,
            },
            Kind::Medium(phase) => prev.map_or(0.0, |prev| phase.p(-self.dir_to(prev), wn)),
        };
        self.to_area(pdf, next)
    }

    /// Area density at `next` of this vertex, on a light, emitting toward it. From infinity
    /// that is the density of the disk the light's rays start on, 1/(π r²), projected onto
    /// `next` (pbrt's planar density of infinite lights).
    fn pdf_light(&self, scene: &Scene, next: &Vertex) -> f32 {
        if self.infinite {
            let cos = if next.ng == Vec3::ZERO { 1.0 } else { next.ng.dot(self.wo).abs() };
            return scene.sphere().disk_pdf() * cos;
        }
        let Some((_, light)) = self.light(scene) else { return 0.0 };
        let w = self.dir_to(next);
        self.to_area(light.pdf_le(self.ng, w, &scene.sphere()).1, next)
    }

    /// Density with which a light subpath starts at this vertex, on a light: the light's
    /// choice probability times its point's area density. From infinity it is a density of
    /// directions: Σ over the infinite lights of choice probability × the density of their
    /// emitted direction (pbrt's `InfiniteLightDensity`), as a vertex at infinity stands for
    /// all of them.
    fn pdf_light_origin(&self, scene: &Scene, next: &Vertex) -> f32 {
        let sphere = scene.sphere();
        if self.infinite {
            return scene
                .infinite_lights()
                .map(|(id, light)| scene.emitter_pmf(id) * light.pdf_le(Vec3::ZERO, self.wo, &sphere).1)
                .sum();
        }
        let Some((id, light)) = self.light(scene) else { return 0.0 };
        scene.emitter_pmf(id) * light.pdf_le(self.ng, self.dir_to(next), &sphere).0
    }
}

/// The most vertices a subpath holds: the camera's or the light's point and at most
/// `max_depth + 1` scattering vertices (the other subpath adds at least one vertex).
fn subpath_capacity(max_depth: u32) -> usize {
    (max_depth as usize).saturating_add(2).min(1 << 16)
}

/// No contribution.
const NOTHING: (SampledSpectrum, f32) = (SampledSpectrum(Vec4::ZERO), 0.0);

impl Integrator {
    /// Extends `path` (holding its first vertex) by sampling BSDFs and phase functions from
    /// `ray`, which starts in `medium` and whose direction has solid-angle density `pdf` and
    /// throughput `beta`, up to `max_vertices` vertices.
    #[allow(clippy::too_many_arguments)]
    fn subpath_walk<'s>(
        &self,
        scene: &'s Scene,
        ray: Ray,
        mut medium: Option<u32>,
        mut beta: SampledSpectrum,
        pdf: f32,
        mode: TransportMode,
        max_vertices: usize,
        path: &mut Vec<Vertex<'s>>,
        differentials: Option<&RayDifferentials>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) {
        let mut pdf_fwd = pdf;
        let mut ray = Ray::new(ray.o, ray.d.normalize()).at_time(ray.time);
        // The rescaled path probability of spectral MIS (one at every wavelength outside media).
        let mut r_u = SampledSpectrum::one();
        // Depth and regularisation bookkeeping, as the path loops keep it.
        let mut state = PathState::new(ray.o);
        let mut crossings = Crossings::default();
        while path.len() < max_vertices {
            stats.rays += 1;
            let hit = scene.intersect(&ray);
            // The solid-angle density of sampling the ray back from the new vertex, which turns
            // into the previous vertex's reverse density.
            let pdf_rev = match free_flight(scene, &ray, hit.as_ref(), medium, &mut beta, &mut r_u, w, sampler) {
                Flight::Absorbed => break,
                Flight::Scattered(p, phase) => {
                    state.depth += 1;
                    state.any_non_specular = true;
                    let prev = path.last().expect("the walk starts from a vertex");
                    if p == prev.p && !prev.infinite {
                        // A collision at the walk's very start (a zero distance from a light
                        // at a point) has no direction to or from the previous vertex.
                        break;
                    }
                    let mut v = Vertex::point(Kind::Medium(phase), p, Vec3::ZERO, mode, beta, 0.0);
                    v.r_u = r_u;
                    v.wo = -ray.d;
                    v.medium = medium;
                    v.pdf_fwd = prev.to_area(pdf_fwd, &v);
                    path.push(v);
                    if path.len() == max_vertices {
                        break;
                    }
                    // β ·= p / pdf = 1: HG is sampled exactly; it is symmetric, so the reverse
                    // density is the forward one.
                    let wi = phase.sample(ray.d, sampler.get_2d());
                    pdf_fwd = phase.p(ray.d, wi);
                    ray = Ray::new(p, wi).at_time(ray.time);
                    pdf_fwd
                }
                Flight::Passed => {
                    let Some(si) = hit else {
                        // A camera subpath that escapes ends at the sky, if there is one.
                        if mode == TransportMode::Radiance && scene.infinite_lights().next().is_some() {
                            let mut sky =
                                Vertex::point(Kind::Sky, ray.o, Vec3::ZERO, mode, beta, pdf_fwd).at_infinity(-ray.d);
                            sky.r_u = r_u;
                            path.push(sky);
                        }
                        break;
                    };
                    if si.is_passthrough() {
                        // A boundary between media only: the ray goes on in the medium behind it.
                        if !crossings.allow_another() {
                            break;
                        }
                        (ray, medium) = si.pass_through(&ray, medium);
                        continue;
                    }
                    state.depth += 1;
                    let camera_ray = differentials.filter(|_| mode == TransportMode::Radiance);
                    let bsdf = self.vertex_bsdf(&si, w, camera_ray, &state);
                    let prev = path.last().expect("the walk starts from a vertex");
                    let mut v = Vertex::point(Kind::Surface, si.p, si.shading.ng, mode, beta, 0.0);
                    v.r_u = r_u;
                    v.ns = bsdf.as_ref().map_or(si.shading.ns, Bsdf::ns);
                    v.wo = si.wo;
                    v.medium = medium;
                    v.pdf_fwd = prev.to_area(pdf_fwd, &v);
                    v.si = Some(si);
                    v.bsdf = bsdf;
                    path.push(v);
                    let full = path.len() == max_vertices;
                    let v = path.last_mut().expect("just pushed");
                    let Some(bsdf) = v.bsdf.as_ref().filter(|b| !b.flags().is_empty()) else { break };
                    if full {
                        break;
                    }
                    let Some(bs) = bsdf.sample_f(v.wo, sampler.get_1d(), sampler.get_2d(), mode) else { break };
                    let wo = v.wo;
                    let si = v.si.as_ref().expect("a surface vertex");
                    let wi = bs.wi.normalize();
                    medium = si.medium_interface().medium_toward(wi, si.shading.ng, medium);
                    ray = si.spawn_ray(wi);
                    beta *= bs.f * (bs.wi.dot(bsdf.ns()).abs() / bs.pdf);
                    pdf_fwd = if bs.pdf_is_proportional { bsdf.pdf(wo, bs.wi, mode) } else { bs.pdf };
                    let mut rev = bsdf.pdf(bs.wi, wo, mode);
                    let specular = bs.is_specular();
                    state.any_non_specular |= !specular;
                    if specular {
                        pdf_fwd = 0.0;
                        rev = 0.0;
                    }
                    v.delta = specular;
                    rev
                }
            };
            let n = path.len();
            let (before, last) = path.split_at_mut(n - 1);
            if let Some(prev) = before.last_mut() {
                prev.pdf_rev = last[0].to_area(pdf_rev, prev);
            }
            if beta.is_black() {
                break;
            }
        }
    }

    /// The bidirectional estimate of the camera sample `ray`: the light its own pixel receives
    /// (returned) and the light splatted elsewhere (pushed to `splats`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn bdpt_trace(
        &self,
        scene: &Scene,
        camera: &Camera,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
        splats: &mut Vec<SplatSample>,
    ) -> SampledSpectrum {
        let time = ray.time;
        let capacity = subpath_capacity(self.max_depth);
        // The camera subpath.
        let mut cam: Vec<Vertex> = Vec::with_capacity(capacity);
        let axis = camera.axis(time);
        cam.push(Vertex::point(Kind::Camera, ray.o, Vec3::ZERO, TransportMode::Radiance, SampledSpectrum::one(), 1.0));
        cam[0].ns = axis;
        let pdf_dir = camera.pdf_we(ray.o, ray.d, time).1;
        if pdf_dir > 0.0 {
            let beta = SampledSpectrum::one();
            self.subpath_walk(
                scene,
                ray,
                scene.camera_medium(),
                beta,
                pdf_dir,
                TransportMode::Radiance,
                capacity,
                &mut cam,
                differentials,
                w,
                sampler,
                stats,
            );
        }
        // The light subpath.
        let mut light_path: Vec<Vertex> = Vec::with_capacity(capacity);
        self.light_subpath(scene, time, capacity - 1, &mut light_path, w, sampler, stats);

        let mut l = SampledSpectrum::zero();
        let max_depth = self.max_depth as usize;
        // s = 1 samples its own light point, so it runs even when no light subpath started.
        for t in 1..=cam.len() {
            for s in 0..=light_path.len().max(1) {
                let depth = (s + t) as isize - 2;
                if (s == 1 && t == 1) || depth < 0 || depth as usize > max_depth {
                    continue;
                }
                let light = &light_path[..s.min(light_path.len())];
                let (p_raster, c, weight) = if t > 1 {
                    let (c, weight) = self.connect(scene, camera, time, light, s, &cam[..t], w, sampler, stats);
                    l += c * weight;
                    (None, c, weight)
                } else if light.len() == s {
                    let Some((p, c, weight)) =
                        self.connect_to_lens(scene, camera, time, light, &cam, w, sampler, stats)
                    else {
                        continue;
                    };
                    splats.push(SplatSample { p_raster: Some(p), l: c * weight, lambdas: *w, strategy: None });
                    (Some(p), c, weight)
                } else {
                    continue;
                };
                let image = match self.strategy_images {
                    StrategyImageKind::Off => continue,
                    StrategyImageKind::Unweighted => c,
                    StrategyImageKind::Weighted => c * weight,
                };
                if weight > 0.0 && !image.is_black() {
                    splats.push(SplatSample { p_raster, l: image, lambdas: *w, strategy: Some((s, t)) });
                }
            }
        }
        l
    }

    /// A light subpath of at most `max_vertices` vertices into the empty `light_path`: a light
    /// chosen in proportion to power, a point and direction on it (from a disk of the scene's
    /// bounding sphere for a light at infinity), and the walk from there. It stays empty when
    /// no light emits there.
    #[allow(clippy::too_many_arguments)]
    fn light_subpath<'s>(
        &self,
        scene: &'s Scene,
        time: f32,
        max_vertices: usize,
        light_path: &mut Vec<Vertex<'s>>,
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) {
        let emitter = scene.sample_emitter(sampler.get_1d());
        let (u_pos, u_dir) = (sampler.get_2d(), sampler.get_2d());
        let Some((id, light, pmf, _)) = emitter else { return };
        let Some(les) = light.sample_le(u_pos, u_dir, &scene.sphere(), w) else { return };
        let p0 = pmf * les.pdf_pos;
        let mut x0 = Vertex::point(Kind::Light(id), les.p, les.n, TransportMode::Importance, les.le / p0, p0);
        if light.is_at_infinity() {
            x0 = x0.at_infinity(les.d);
        }
        light_path.push(x0);
        let cos = if les.n == Vec3::ZERO { 1.0 } else { les.n.dot(les.d).abs() };
        let beta = les.le * (cos / (p0 * les.pdf_dir));
        let origin = offset_ray_origin(les.p, light_point_error(les.p), les.n, les.d);
        let ray = Ray::new(origin, les.d).at_time(time);
        let mode = TransportMode::Importance;
        let medium = scene.light_medium(id, les.n, les.d);
        self.subpath_walk(
            scene,
            ray,
            medium,
            beta,
            les.pdf_dir,
            mode,
            max_vertices,
            light_path,
            None,
            w,
            sampler,
            stats,
        );
        if light_path[0].infinite {
            // From infinity the first vertex is a direction and the second a point of the
            // disk's density projected onto it.
            if let Some(x1) = light_path.get_mut(1) {
                x1.pdf_fwd = les.pdf_pos * if x1.ng == Vec3::ZERO { 1.0 } else { x1.ng.dot(les.d).abs() };
            }
            light_path[0].pdf_fwd = light_path[0].pdf_light_origin(scene, &light_path[0]);
        }
    }

    /// The contribution of strategy (s, t ≥ 2) and its MIS weight: the light subpath's first s
    /// vertices `light` joined to the camera subpath `cam` (t vertices); s = 1 samples a new
    /// point on a light (and `light` may then be empty).
    #[allow(clippy::too_many_arguments)]
    fn connect(
        &self,
        scene: &Scene,
        camera: &Camera,
        time: f32,
        light: &[Vertex],
        s: usize,
        cam: &[Vertex],
        w: &SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> (SampledSpectrum, f32) {
        let t = cam.len();
        let pt = &cam[t - 1];
        if s == 0 {
            // The camera subpath found a light: a surface's, or the sky's.
            let le = match (pt.kind, pt.si.as_ref()) {
                (Kind::Sky, _) => escaped_radiance(scene, &Ray::new(pt.p, -pt.wo), w),
                (_, Some(si)) if si.area_light().is_some() => si.emitted(w),
                _ => return NOTHING,
            };
            if le.is_black() {
                return NOTHING;
            }
            return (
                spectral_mis(pt.beta * le, pt.r_u),
                self.mis_weight(scene, camera, time, light, 0, cam, None, None),
            );
        }
        if !pt.connectible() {
            return NOTHING;
        }
        if s == 1 {
            // A new point on a light, chosen and sampled as light subpaths start.
            let Some((id, light_src, pmf, _)) = scene.sample_emitter(sampler.get_1d()) else {
                return NOTHING;
            };
            let u_pos = sampler.get_2d();
            if light_src.is_at_infinity() {
                return self.connect_to_infinity(
                    scene,
                    camera,
                    time,
                    cam,
                    (id, light_src, pmf),
                    u_pos,
                    w,
                    sampler,
                    stats,
                );
            }
            let Some(les) = light_src.sample_le_point(u_pos, &scene.sphere(), w) else {
                return NOTHING;
            };
            let to_light = les.p - pt.p;
            let d2 = to_light.length_squared();
            if d2 == 0.0 {
                return NOTHING;
            }
            let wi = to_light / d2.sqrt();
            let le = light_src.emitted_toward(&les, -wi, w);
            let p0 = pmf * les.pdf_pos;
            let cos_light = if les.n == Vec3::ZERO { 1.0 } else { les.n.dot(wi).abs() };
            let c = pt.beta * pt.f_toward(wi) * le * (pt.cos(wi) * cos_light / (d2 * p0));
            if c.is_black() {
                return NOTHING;
            }
            let ray = pt.ray_to(les.p, time);
            let Some((tr, r_l)) = segment_transmittance(scene, ray, pt.medium_toward(wi), w, sampler, stats) else {
                return NOTHING;
            };
            let c = spectral_mis(c * tr, pt.r_u * r_l);
            if c.is_black() {
                return NOTHING;
            }
            let vertex = Vertex::point(Kind::Light(id), les.p, les.n, TransportMode::Importance, le / p0, p0);
            return (c, self.mis_weight(scene, camera, time, light, 1, cam, Some(&vertex), None));
        }
        let qs = &light[s - 1];
        if !qs.connectible() {
            return NOTHING;
        }
        let d = pt.p - qs.p;
        let d2 = d.length_squared();
        if d2 == 0.0 {
            return NOTHING;
        }
        let wd = d / d2.sqrt();
        let g = qs.cos(wd) * pt.cos(wd) / d2;
        let c = qs.beta * qs.f(pt) * pt.f(qs) * pt.beta * g;
        if c.is_black() {
            return NOTHING;
        }
        let ray = pt.ray_to(qs.p, time);
        let Some((tr, r_l)) = segment_transmittance(scene, ray, pt.medium_toward(-wd), w, sampler, stats) else {
            return NOTHING;
        };
        let c = spectral_mis(c * tr, qs.r_u * pt.r_u * r_l);
        if c.is_black() {
            return NOTHING;
        }
        (c, self.mis_weight(scene, camera, time, light, s, cam, None, None))
    }

    /// Strategy s = 1 with a light at infinity `light` (its id, the light and the probability
    /// of choosing it): a direction toward it sampled from the camera subpath's last vertex as
    /// light sampling does, with `u`: the contribution and its MIS weight.
    #[allow(clippy::too_many_arguments)]
    fn connect_to_infinity(
        &self,
        scene: &Scene,
        camera: &Camera,
        time: f32,
        cam: &[Vertex],
        (id, light, pmf): (LightId, &Light, f32),
        u: Vec2,
        w: &SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> (SampledSpectrum, f32) {
        let pt = &cam[cam.len() - 1];
        let ctx = match pt.kind {
            Kind::Medium(_) => LightSampleContext::medium(pt.p),
            _ => LightSampleContext::surface(pt.p, pt.ns),
        };
        let Some(ls) = light.sample_li(&ctx, u, w).filter(|ls| ls.pdf > 0.0) else { return NOTHING };
        let c = pt.beta * pt.f_toward(ls.wi) * ls.li * (pt.cos(ls.wi) / (pmf * ls.pdf));
        if c.is_black() {
            return NOTHING;
        }
        let ray = pt.ray_toward(ls.wi, time);
        let Some((tr, r_l)) = segment_transmittance(scene, ray, pt.medium_toward(ls.wi), w, sampler, stats) else {
            return NOTHING;
        };
        let c = spectral_mis(c * tr, pt.r_u * r_l);
        if c.is_black() {
            return NOTHING;
        }
        let mut vertex =
            Vertex::point(Kind::Light(id), pt.p, Vec3::ZERO, TransportMode::Importance, c, 0.0).at_infinity(-ls.wi);
        vertex.pdf_fwd = vertex.pdf_light_origin(scene, pt);
        (c, self.mis_weight(scene, camera, time, &[], 1, cam, Some(&vertex), None))
    }

    /// Strategy (s ≥ 2, t = 1): the light subpath's last vertex connected to a new point on the
    /// lens; its film position, contribution and MIS weight.
    #[allow(clippy::too_many_arguments)]
    fn connect_to_lens(
        &self,
        scene: &Scene,
        camera: &Camera,
        time: f32,
        light: &[Vertex],
        cam: &[Vertex],
        w: &SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> Option<(Vec2, SampledSpectrum, f32)> {
        let qs = light.last()?;
        if !qs.connectible() || !matches!(qs.kind, Kind::Surface | Kind::Medium(_)) {
            return None;
        }
        let cs = camera.sample_wi(qs.p, sampler.get_2d(), time)?;
        let c = qs.beta * qs.f_toward(cs.wi) * (qs.cos(cs.wi) * cs.we / cs.pdf);
        if c.is_black() {
            return None;
        }
        let ray = qs.ray_to(cs.p_lens, time);
        let (tr, r_l) = segment_transmittance(scene, ray, qs.medium_toward(cs.wi), w, sampler, stats)?;
        let c = spectral_mis(c * tr, qs.r_u * r_l);
        if c.is_black() {
            return None;
        }
        let mut lens =
            Vertex::point(Kind::Camera, cs.p_lens, Vec3::ZERO, TransportMode::Radiance, SampledSpectrum::one(), 1.0);
        lens.ns = cs.n_lens;
        let weight = self.mis_weight(scene, camera, time, light, light.len(), &cam[..1], None, Some(&lens));
        Some((cs.p_raster, c, weight))
    }

    /// The balance-heuristic weight of joining the light subpath's first s vertices `light`
    /// (the first replaced by `new_light` when given, s = 1) to `cam` (t vertices, the first
    /// replaced by `new_lens` when given, t = 1): the densities of the full path for every
    /// strategy, the ones at and next to the connection recomputed for it (pbrt `MISWeight`).
    #[allow(clippy::too_many_arguments)]
    fn mis_weight(
        &self,
        scene: &Scene,
        camera: &Camera,
        time: f32,
        light: &[Vertex],
        s: usize,
        cam: &[Vertex],
        new_light: Option<&Vertex>,
        new_lens: Option<&Vertex>,
    ) -> f32 {
        let t = cam.len();
        // (`light` is empty when s = 1 and no light subpath started.)
        let light_at = |i: usize| match (i, new_light) {
            (0, Some(v)) => v,
            _ => &light[i],
        };
        let cam_at = |i: usize| match (i, new_lens) {
            (0, Some(v)) => v,
            _ => &cam[i],
        };
        // The full path, light end first: light[0..s], then cam[t-1..0].
        let n = s + t;
        let mut path = DensityPath::new(n);
        for (i, d) in path.iter_mut().enumerate().take(s) {
            let v = light_at(i);
            *d = VertexDensity { from_light: v.pdf_fwd, from_camera: v.pdf_rev, delta: v.delta };
        }
        for (j, d) in path.iter_mut().rev().enumerate().take(t) {
            let v = cam_at(j);
            *d = VertexDensity { from_light: v.pdf_rev, from_camera: v.pdf_fwd, delta: v.delta };
        }
        // The connection's ends and their neighbours.
        let pt = cam_at(t - 1);
        let pt_minus = (t >= 2).then(|| cam_at(t - 2));
        let qs = (s >= 1).then(|| light_at(s - 1));
        let qs_minus = (s >= 2).then(|| light_at(s - 2));
        let at_pt = n - t; // index of pt in the full path
        path[at_pt].delta = false;
        path[at_pt].from_light = match qs {
            Some(qs) => qs.pdf(scene, camera, time, qs_minus, pt),
            None => pt.pdf_light_origin(scene, pt_minus.expect("s = 0 needs t ≥ 2")),
        };
        if let Some(pm) = pt_minus {
            path[at_pt + 1].from_light = match qs {
                Some(qs) => pt.pdf(scene, camera, time, Some(qs), pm),
                None => pt.pdf_light(scene, pm),
            };
        }
        if let Some(qs) = qs {
            path[s - 1].delta = false;
            path[s - 1].from_camera = pt.pdf(scene, camera, time, pt_minus, qs);
            if let Some(qm) = qs_minus {
                path[s - 2].from_camera = qs.pdf(scene, camera, time, Some(pt), qm);
            }
        }
        // A light found by the camera subpath (s = 0) has a surface or is the sky.
        let point_light = s > 0 && light_at(0).light(scene).is_some_and(|(_, l)| l.is_delta());
        balance_weight(&path, s, point_light)
    }
}

impl Integrator {
    /// Strategy (s, t) alone for the camera ray `ray` with its `differentials`, if any
    /// (pbrt-v4 `MLTIntegrator::L` after the camera ray): a camera subpath of exactly t
    /// vertices, then — from the sampler's light stream — a light subpath of exactly s, then
    /// — from its connection stream — their connection, weighted by the balance heuristic
    /// over all strategies of its path. Returns the contribution and, for t = 1, the film
    /// position it lands at; `None` when either subpath ends early or the connection carries
    /// nothing.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn bdpt_strategy(
        &self,
        scene: &Scene,
        camera: &Camera,
        ray: Ray,
        differentials: Option<&RayDifferentials>,
        (s, t): (usize, usize),
        w: &mut SampledWavelengths,
        sampler: &mut Sampler,
        stats: &mut Stats,
    ) -> Option<(SampledSpectrum, Option<Vec2>)> {
        let time = ray.time;
        let mut cam: Vec<Vertex> = Vec::with_capacity(t);
        cam.push(Vertex::point(Kind::Camera, ray.o, Vec3::ZERO, TransportMode::Radiance, SampledSpectrum::one(), 1.0));
        cam[0].ns = camera.axis(time);
        let pdf_dir = camera.pdf_we(ray.o, ray.d, time).1;
        if t > 1 && pdf_dir > 0.0 {
            let beta = SampledSpectrum::one();
            let mode = TransportMode::Radiance;
            let medium = scene.camera_medium();
            self.subpath_walk(scene, ray, medium, beta, pdf_dir, mode, t, &mut cam, differentials, w, sampler, stats);
        }
        if cam.len() != t {
            return None;
        }
        sampler.start_stream(PssStream::Light);
        let mut light_path: Vec<Vertex> = Vec::with_capacity(s);
        if s > 0 {
            self.light_subpath(scene, time, s, &mut light_path, w, sampler, stats);
        }
        if light_path.len() != s {
            return None;
        }
        sampler.start_stream(PssStream::Connection);
        if t > 1 {
            let (c, weight) = self.connect(scene, camera, time, &light_path, s, &cam, w, sampler, stats);
            let l = c * weight;
            (!l.is_black()).then_some((l, None))
        } else {
            let (p, c, weight) = self.connect_to_lens(scene, camera, time, &light_path, &cam, w, sampler, stats)?;
            Some((c * weight, Some(p)))
        }
    }
}
