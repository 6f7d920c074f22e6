//! pbrt-v4's coated materials: a dielectric coat over a Lambertian base (`coateddiffuse`) or
//! over a metal (`coatedconductor`), with a homogeneous slab between them, rendered by the
//! stochastic layered BSDF ([`crate::bsdf::Layered`]).

use super::{clamp01, ConductorIor, FloatTexture, Ior, Roughness, SpectrumTexture, TextureEvalContext};
use crate::bsdf::{Bxdf, CoatedDiffuse, Conductor, Dielectric, Diffuse, Layered, Slab};
use crate::spectrum::SampledWavelengths;

/// The slab between a coat and its base, and the random walk's limits.
#[derive(Clone, Debug)]
pub struct LayerSpec {
    /// Thickness in mean free paths (pbrt-v4's default 0.01).
    pub thickness: FloatTexture,
    /// Single-scattering albedo of the slab (default 0: absorbing only).
    pub albedo: SpectrumTexture,
    /// Henyey–Greenstein asymmetry (default 0).
    pub g: FloatTexture,
    /// Scattering events per walk (default 10).
    pub max_depth: u32,
    /// Walks per evaluation (default 1).
    pub n_samples: u32,
}

impl Default for LayerSpec {
    fn default() -> Self {
        Self {
            thickness: FloatTexture::Constant(0.01),
            albedo: SpectrumTexture::Constant(crate::spectrum::Spectrum::constant(0.0)),
            g: FloatTexture::Constant(0.0),
            max_depth: 10,
            n_samples: 1,
        }
    }
}

impl LayerSpec {
    fn slab(&self, ctx: &TextureEvalContext, w: &SampledWavelengths) -> Slab {
        let albedo = clamp01(self.albedo.eval(ctx, w));
        Slab::new(self.thickness.eval(ctx), albedo, self.g.eval(ctx), self.max_depth, self.n_samples)
    }
}

/// The coat's index at the hero wavelength; 0 means 1 (pbrt-v4).
fn coat_eta(eta: &Ior, w: &mut SampledWavelengths) -> f32 {
    let e = eta.hero(w);
    if e == 0.0 {
        1.0
    } else {
        e
    }
}

/// "coateddiffuse": a rough dielectric coat over a Lambertian base.
#[derive(Clone, Debug)]
pub struct CoatedDiffuseMaterial {
    /// Base reflectance (default 0.5).
    pub reflectance: SpectrumTexture,
    /// Coat roughness.
    pub roughness: Roughness,
    /// Coat index of refraction (default 1.5).
    pub eta: Ior,
    /// The slab between coat and base.
    pub layer: LayerSpec,
    /// Use the closed-form coat model instead of the random walk (prism's `"string model"
    /// "analytic"`; it has no slab, so `layer` is ignored).
    pub analytic: bool,
}

impl CoatedDiffuseMaterial {
    /// pbrt-v4's layered model with default slab parameters.
    pub fn new(reflectance: SpectrumTexture, roughness: Roughness, eta: f32) -> Self {
        Self { reflectance, roughness, eta: Ior::Constant(eta), layer: LayerSpec::default(), analytic: false }
    }

    pub(super) fn bxdf(&self, ctx: &TextureEvalContext, w: &mut SampledWavelengths) -> Bxdf {
        let r = clamp01(self.reflectance.eval(ctx, w));
        let distrib = self.roughness.distribution(ctx);
        let eta = coat_eta(&self.eta, w);
        if self.analytic {
            return CoatedDiffuse::new(r, eta, distrib).into();
        }
        Layered::new(Dielectric::new(eta, distrib), Diffuse::new(r), self.layer.slab(ctx, w)).into()
    }
}

/// "coatedconductor": a rough dielectric coat over a rough metal.
#[derive(Clone, Debug)]
pub struct CoatedConductorMaterial {
    /// Coat roughness ("interface.roughness").
    pub interface_roughness: Roughness,
    /// Coat index of refraction ("interface.eta", default 1.5).
    pub interface_eta: Ior,
    /// The metal's index relative to the outside ("conductor.eta"/"conductor.k", or
    /// "reflectance").
    pub conductor: ConductorIor,
    /// Metal roughness ("conductor.roughness").
    pub conductor_roughness: Roughness,
    /// The slab between coat and metal.
    pub layer: LayerSpec,
}

impl CoatedConductorMaterial {
    pub(super) fn bxdf(&self, ctx: &TextureEvalContext, w: &mut SampledWavelengths) -> Bxdf {
        let eta = coat_eta(&self.interface_eta, w);
        let (ce, ck) = self.conductor.eval(ctx, w);
        // Under the coat the metal borders the coat's medium: its index relative to that.
        let metal = Conductor::new(self.conductor_roughness.distribution(ctx), ce / eta, ck / eta);
        let coat = Dielectric::new(eta, self.interface_roughness.distribution(ctx));
        Layered::new(coat, metal, self.layer.slab(ctx, w)).into()
    }
}
