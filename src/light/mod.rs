//! Light sources in SI units (PBR 4th ed. §4.1). Spectral quantities are per nanometre:
//! radiance L [W/(sr·m²·nm)], intensity I [W/(sr·nm)], irradiance E [W/(m²·nm)], flux Φ [W/nm].
//! A light's `power` parameter is its radiometric flux integrated over 360–830 nm [W]; the
//! fluxes by which lights are chosen are pbrt-v4's (`selection_flux`).

mod area;
mod distant;
mod emission;
mod emission_image;
mod envmap;
mod goniometric;
mod infinite;
mod map_layout;
pub mod photometry;
mod point;
mod portal;
mod projection;
mod quadric;
mod rectangle;
mod sampler;
mod selection_flux;
mod sphere;
mod texel_spectrum;

pub use area::{AreaLight, TriangleLightLanes};
pub use distant::DistantLight;
pub use emission::{EmissionSample, SceneSphere};
pub use emission_image::{EmissionImage, ImageEmission};
pub use envmap::{image_upper_hemisphere_y, EnvMapLight};
pub use goniometric::GoniometricLight;
pub use infinite::UniformInfiniteLight;
pub use map_layout::MapLayout;
pub use point::{PointLight, SpotFalloff, SpotLight};
pub use portal::{is_rectangle, PortalLight};
pub use projection::ProjectionLight;
pub use quadric::QuadricLight;
pub use rectangle::RectangleLight;
pub use sampler::{LightBounds, LightSampleContext, LightSampler, LightSamplerKind};
pub use sphere::SphereLight;

use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// The pbrt-v4 `LightSource` types prism renders (area lights, `AreaLightSource "diffuse"`,
/// are attached to shapes instead).
pub const PBRT_NAMES: &[&str] = &["point", "spot", "goniometric", "projection", "distant", "infinite"];

/// A sample of incident light at a reference point, produced by [`Light::sample_li`].
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Incident radiance along `wi` (for delta lights, I/r² or E: the value the estimator
    /// multiplies by f·cos θ, with `pdf` = 1).
    pub li: SampledSpectrum,
    /// Unit direction from the reference point toward the light.
    pub wi: Vec3,
    /// Solid-angle density of `wi` [1/sr], or 1 for a delta light.
    pub pdf: f32,
    /// Point on the light (shadow-ray target); unused when `dist` is infinite.
    pub p_light: Vec3,
    /// Distance to `p_light`, or ∞ for lights at infinity.
    pub dist: f32,
}

/// Every light prism renders. A closed set: an enum, dispatched by `match`.
#[derive(Clone, Debug)]
pub enum Light {
    /// Isotropic point light.
    Point(PointLight),
    /// Spotlight (Warn's cos^s model or pbrt-v4's smoothstep cone).
    Spot(SpotLight),
    /// Point light with an equal-area intensity image.
    Goniometric(Box<GoniometricLight>),
    /// Point light projecting an image.
    Projection(Box<ProjectionLight>),
    /// One emissive triangle of a diffuse area light.
    Area(AreaLight),
    /// A diffuse area light on a rectangle, sampled by the solid angle it subtends.
    Rectangle(Box<RectangleLight>),
    /// A diffuse area light on a full sphere, sampled by the cone it subtends.
    Sphere(SphereLight),
    /// A diffuse area light on a disk, cylinder or partial sphere, sampled by area.
    Quadric(Box<QuadricLight>),
    /// Directional light at infinity.
    Distant(DistantLight),
    /// Constant radiance from every direction.
    UniformInfinite(UniformInfiniteLight),
    /// Radiance from an environment image (equal-area or latitude–longitude).
    EnvMap(EnvMapLight),
    /// An equal-area environment map seen only through a rectangular portal.
    Portal(Box<PortalLight>),
}

impl Light {
    /// True for lights described by a delta distribution (no MIS with BSDF sampling).
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point(_) | Light::Spot(_) | Light::Goniometric(_) | Light::Projection(_) | Light::Distant(_)
        )
    }

    /// Samples incident light at `ctx` (with `u` in [0,1)²); a surface point's normal lets
    /// lights that can shape their samples by the cosine there do so.
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2, w: &SampledWavelengths) -> Option<LightSample> {
        let p = ctx.p;
        match self {
            Light::Point(l) => l.sample_li(p, w),
            Light::Spot(l) => l.sample_li(p, w),
            Light::Goniometric(l) => l.sample_li(p, w),
            Light::Projection(l) => l.sample_li(p, w),
            Light::Area(l) => l.sample_li(p, u, w),
            Light::Rectangle(l) => l.sample_li(ctx, u, w),
            Light::Sphere(l) => l.sample_li(p, u, w),
            Light::Quadric(l) => l.sample_li(p, u, w),
            Light::Distant(l) => l.sample_li(w),
            Light::UniformInfinite(l) => l.sample_li(u, w),
            Light::EnvMap(l) => l.sample_li(u, w),
            Light::Portal(l) => l.sample_li(p, u, w),
        }
    }

    /// Solid-angle density [1/sr] with which `sample_li` at `ctx` picks the unit direction `wi`
    /// (pbrt-v4 `Light::PDF_Li(ctx, wi)`); 0 for delta lights.
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3) -> f32 {
        let p = ctx.p;
        match self {
            Light::Area(l) => l.pdf_li(p, wi),
            Light::Rectangle(l) => l.pdf_li(ctx, wi),
            Light::Sphere(l) => l.pdf_li(p, wi),
            Light::Quadric(l) => l.pdf_li(p, wi),
            Light::UniformInfinite(_) => infinite::uniform_sphere_pdf(),
            Light::EnvMap(l) => l.pdf_li(wi),
            Light::Portal(l) => l.pdf_li(p, wi),
            _ => 0.0,
        }
    }

    /// Emitted flux as pbrt-v4's power light sampler estimates it (`Light::Phi` at four visible
    /// wavelengths; see `selection_flux`), in any unit common to all lights: used only to
    /// choose lights.
    pub fn power(&self, scene_radius: f32) -> f32 {
        match self {
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Goniometric(l) => l.power(),
            Light::Projection(l) => l.power(),
            Light::Area(l) => l.power(),
            Light::Rectangle(l) => l.power(),
            Light::Sphere(l) => l.power(),
            Light::Quadric(l) => l.power(),
            Light::Distant(l) => l.power(scene_radius),
            Light::UniformInfinite(l) => l.power(scene_radius),
            Light::EnvMap(l) => l.power(scene_radius),
            Light::Portal(l) => l.power(),
        }
    }

    /// The flux the BVH light sampler weighs this light by: pbrt-v4's `LightBounds::phi` of the
    /// light (`Light::Bounds`; see `selection_flux`, in the unit of [`Light::power`]); 0 for
    /// lights at infinity.
    pub fn bound_flux(&self) -> f32 {
        match self {
            Light::Point(l) => l.bound_flux(),
            Light::Spot(l) => l.bound_flux(),
            Light::Goniometric(l) => l.bound_flux(),
            Light::Projection(l) => l.bound_flux(),
            Light::Area(l) => l.bound_flux(),
            Light::Rectangle(l) => l.bound_flux(),
            Light::Sphere(l) => l.bound_flux(),
            Light::Quadric(l) => l.bound_flux(),
            Light::Distant(_) | Light::UniformInfinite(_) | Light::EnvMap(_) | Light::Portal(_) => 0.0,
        }
    }

    /// Bounds for many-light sampling of this light with flux `phi` (as [`Light::bound_flux`]):
    /// its box, normal cone and emission angle, each light working out its own. `None` for
    /// lights at infinity (sampled apart from the tree) and for lights without finite flux
    /// (never chosen).
    pub fn bounds(&self, phi: f32) -> Option<LightBounds> {
        let bounds = match self {
            Light::Point(l) => l.bounds(phi),
            Light::Spot(l) => l.bounds(phi),
            Light::Goniometric(l) => l.bounds(phi),
            Light::Projection(l) => l.bounds(phi),
            Light::Area(l) => l.bounds(phi),
            Light::Rectangle(l) => l.bounds(phi),
            Light::Sphere(l) => l.bounds(phi),
            Light::Quadric(l) => l.bounds(phi),
            Light::Distant(_) | Light::UniformInfinite(_) | Light::EnvMap(_) | Light::Portal(_) => return None,
        };
        (bounds.phi > 0.0 && bounds.phi.is_finite()).then_some(bounds)
    }

    /// Radiance L_e an area light's surface with normal `n` (its emitting side) sends toward
    /// `wo` from the point with texture coordinates `uv` (pbrt-v4 `DiffuseAreaLight::L`); 0 for
    /// lights without a surface.
    #[inline]
    pub fn surface_radiance(&self, n: Vec3, wo: Vec3, uv: Vec2, w: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Light::Area(l) => l.radiance(wo, uv, w),
            Light::Rectangle(l) => l.radiance(wo, w),
            Light::Sphere(l) => l.radiance(n, wo, w),
            Light::Quadric(l) => l.radiance(n, wo, w),
            _ => SampledSpectrum::zero(),
        }
    }

    /// True for lights at infinity that rays escaping the scene see.
    pub fn is_infinite(&self) -> bool {
        matches!(self, Light::UniformInfinite(_) | Light::EnvMap(_) | Light::Portal(_))
    }

    /// True for lights at infinity: those escaping rays see and directional ones. They have no
    /// bounds, and a light sampler that chooses by bounds chooses them apart.
    pub fn is_at_infinity(&self) -> bool {
        self.is_infinite() || matches!(self, Light::Distant(_))
    }

    /// Radiance arriving along an escaping ray from `o` with direction `d` (0 for other lights).
    pub fn escaped_radiance(&self, o: Vec3, d: Vec3, w: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Light::UniformInfinite(l) => l.le(w),
            Light::EnvMap(l) => l.le(d, w),
            Light::Portal(l) => l.le(o, d, w),
            _ => SampledSpectrum::zero(),
        }
    }
}
