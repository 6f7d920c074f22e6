//! Materials: what a surface is made of, turned into a BSDF at each hit by evaluating textures and
//! spectra at the path's wavelengths. Materials hold spectra, never RGB triplets.

mod bump;
mod conductor;
mod hair;
mod layered;
mod mix;
mod subsurface;

pub use crate::texture::{FloatTexture, SpectrumTexture, TextureEvalContext};
pub use bump::{BumpedMaterial, NormalMap, NormalPerturbation, ShadingDerivatives};
pub use conductor::ConductorIor;
pub use hair::{melanin_sigma_a, HairAbsorption, HairMaterial};
pub use layered::{CoatedConductorMaterial, CoatedDiffuseMaterial, LayerSpec};
pub use mix::{hit_key, MixMaterial};
pub use subsurface::{ScatteringSpec, SubsurfaceMaterial};

use crate::bsdf::{
    Bsdf, Bxdf, Conductor, Dielectric, Diffuse, DiffuseTransmission, Measured, MeasuredBrdf, ThinDielectric,
    TrowbridgeReitz,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;

/// The pbrt-v4 `Material` types prism renders.
pub const PBRT_NAMES: &[&str] = &[
    "diffuse",
    "conductor",
    "dielectric",
    "coateddiffuse",
    "coatedconductor",
    "diffusetransmission",
    "thindielectric",
    "subsurface",
    "mix",
    "interface",
    "hair",
    "measured",
];

/// Index of refraction: constant, or a spectrum η(λ) (dispersive when it varies).
#[derive(Clone, Debug)]
pub enum Ior {
    /// The same η at every wavelength.
    Constant(f32),
    /// η(λ) (Sellmeier/Cauchy glasses, tabulated data).
    Spectral(Spectrum),
}

impl Ior {
    /// True when η varies with wavelength, so refraction separates wavelengths.
    pub fn is_dispersive(&self) -> bool {
        match self {
            Ior::Constant(_) => false,
            Ior::Spectral(s) => (s.eval(400.0) - s.eval(700.0)).abs() > 1e-6,
        }
    }

    /// η at the hero wavelength; a dispersive index terminates the secondary wavelengths
    /// (they would refract elsewhere). A tabulated η is 0 outside its table (pbrt-v4's glass
    /// tables start at 350–380 nm), where it is taken as 1, as pbrt-v4's dielectric does.
    pub fn hero(&self, w: &mut SampledWavelengths) -> f32 {
        match self {
            Ior::Constant(e) => *e,
            Ior::Spectral(s) => {
                if self.is_dispersive() {
                    w.terminate_secondary();
                }
                match s.eval(w.lambda[0]) {
                    0.0 => 1.0,
                    eta => eta,
                }
            }
        }
    }
}

/// Microfacet roughness of a material: per-direction values and whether they are "roughness"
/// (remapped to α as pbrt-v4's `remaproughness`) or α directly.
#[derive(Clone, Debug)]
pub struct Roughness {
    /// Roughness along u.
    pub u: FloatTexture,
    /// Roughness along v.
    pub v: FloatTexture,
    /// Map roughness → α with `TrowbridgeReitz::roughness_to_alpha`.
    pub remap: bool,
}

impl Roughness {
    /// Isotropic constant roughness (α = value, no remapping).
    pub fn alpha(a: f32) -> Self {
        Self { u: FloatTexture::Constant(a), v: FloatTexture::Constant(a), remap: false }
    }

    fn distribution(&self, ctx: &TextureEvalContext) -> TrowbridgeReitz {
        let (mut au, mut av) = (self.u.eval(ctx), self.v.eval(ctx));
        if self.remap {
            au = TrowbridgeReitz::roughness_to_alpha(au);
            av = TrowbridgeReitz::roughness_to_alpha(av);
        }
        TrowbridgeReitz::new(au, av)
    }
}

/// Every material prism renders (pbrt-v4 names in comments).
#[derive(Clone, Debug)]
pub enum Material {
    /// "diffuse": Lambertian reflectance ρ.
    Diffuse {
        /// Reflectance ρ(λ) ∈ [0, 1].
        reflectance: SpectrumTexture,
    },
    /// "diffusetransmission".
    DiffuseTransmission {
        /// Reflectance.
        reflectance: SpectrumTexture,
        /// Transmittance.
        transmittance: SpectrumTexture,
        /// Multiplier on both.
        scale: f32,
    },
    /// "conductor": Fresnel from complex η + ik over a Trowbridge–Reitz microfacet distribution.
    Conductor {
        /// The complex index (measured, or from a reflectance).
        ior: ConductorIor,
        /// Roughness.
        roughness: Roughness,
    },
    /// "dielectric": rough or smooth refracting interface.
    Dielectric {
        /// Index of refraction (inside over outside).
        eta: Ior,
        /// Roughness.
        roughness: Roughness,
    },
    /// "thindielectric": a thin smooth slab (window pane).
    ThinDielectric {
        /// Index of refraction.
        eta: f32,
    },
    /// "coateddiffuse": a rough dielectric coat over a Lambertian base.
    CoatedDiffuse(Box<CoatedDiffuseMaterial>),
    /// "coatedconductor": a rough dielectric coat over a rough metal.
    CoatedConductor(Box<CoatedConductorMaterial>),
    /// "mix": one of two materials per hit, chosen at random ([`Material::resolve`]).
    Mix(Box<MixMaterial>),
    /// "subsurface": a dielectric boundary over a scattering medium; the integrator continues
    /// paths that refract into it (`integrator::subsurface`).
    Subsurface(Box<SubsurfaceMaterial>),
    /// "hair": a fibre of a curve (Chiang et al. 2016).
    Hair(Box<HairMaterial>),
    /// "measured": a tabulated BRDF read from an RGL `.bsdf` file, shared by every material
    /// that names the same file.
    Measured(std::sync::Arc<MeasuredBrdf>),
    /// Any other material with its shading normal perturbed by a displacement texture or a
    /// normal map ("float displacement", "string normalmap").
    Bumped(Box<BumpedMaterial>),
    /// "interface" (and pbrt-v4's deprecated `""`/`"none"`): no surface at all, only the
    /// boundary between two media. Rays and shadow rays pass through it unchanged.
    Interface,
}

/// The local geometry a material needs at a hit.
#[derive(Clone, Copy, Debug)]
pub struct ShadingPoint {
    /// Shading normal (unit).
    pub ns: Vec3,
    /// Geometric normal (unit).
    pub ng: Vec3,
    /// ∂p/∂u, for anisotropic frames (may be zero).
    pub dpdu: Vec3,
    /// What textures are evaluated at: point, normal, (u, v) and the pixel footprint.
    pub tex: TextureEvalContext,
}

impl Material {
    /// A Lambertian material with constant reflectance spectrum.
    pub fn diffuse(reflectance: Spectrum) -> Self {
        Material::Diffuse { reflectance: SpectrumTexture::Constant(reflectance) }
    }

    /// The subsurface material, when light refracted into this one scatters beneath the
    /// surface (pbrt-v4 `Material::HasSubsurfaceScattering`).
    pub fn subsurface(&self) -> Option<&SubsurfaceMaterial> {
        match self {
            Material::Subsurface(m) => Some(m),
            Material::Bumped(b) => b.base.subsurface(),
            _ => None,
        }
    }

    /// True when any lobe of this material can change a path's wavelengths' directions
    /// differently (so secondary wavelengths must be terminated at it).
    pub fn is_dispersive(&self) -> bool {
        match self {
            Material::Dielectric { eta, .. } => eta.is_dispersive(),
            Material::CoatedDiffuse(m) => m.eta.is_dispersive(),
            Material::CoatedConductor(m) => m.interface_eta.is_dispersive(),
            Material::Mix(m) => m.materials.iter().any(Material::is_dispersive),
            Material::Bumped(b) => b.base.is_dispersive(),
            _ => false,
        }
    }

    /// True when the BSDF may depend on where and at what footprint its textures are
    /// evaluated, so a hit on it needs its pixel footprint: any material with a texture that is
    /// not a constant (the layered, mix, subsurface and bumped materials are assumed to have
    /// one).
    pub fn is_textured(&self) -> bool {
        let rough = |r: &Roughness| r.u.varies() || r.v.varies();
        match self {
            Material::Diffuse { reflectance } => reflectance.varies(),
            Material::DiffuseTransmission { reflectance, transmittance, .. } => {
                reflectance.varies() || transmittance.varies()
            }
            Material::Conductor { ior: ConductorIor::EtaK { .. }, roughness } => rough(roughness),
            Material::Dielectric { roughness, .. } => rough(roughness),
            Material::ThinDielectric { .. } | Material::Measured(_) | Material::Interface => false,
            _ => true,
        }
    }

    /// True for an interface: no surface, so light passes through unscattered.
    #[inline]
    pub fn is_interface(&self) -> bool {
        matches!(self, Material::Interface)
    }

    /// True when a hit on this material may find no surface: an interface, or a mix that may
    /// choose one.
    pub fn may_be_interface(&self) -> bool {
        match self {
            Material::Interface => true,
            Material::Mix(m) => m.materials.iter().any(Material::may_be_interface),
            _ => false,
        }
    }

    /// The BSDF at a hit for the path's wavelengths (`None` for an interface). A dispersive
    /// dielectric terminates the secondary wavelengths (η is evaluated at the hero wavelength
    /// only). A mix should be [`Material::resolve`]d with its hit first; unresolved, it chooses
    /// by the shading point.
    pub fn bsdf(&self, sp: &ShadingPoint, w: &mut SampledWavelengths) -> Option<Bsdf> {
        let bxdf: Bxdf = match self {
            Material::Diffuse { reflectance } => Diffuse::new(clamp01(reflectance.eval(&sp.tex, w))).into(),
            Material::DiffuseTransmission { reflectance, transmittance, scale } => DiffuseTransmission::new(
                clamp01(reflectance.eval(&sp.tex, w) * *scale),
                clamp01(transmittance.eval(&sp.tex, w) * *scale),
            )
            .into(),
            Material::Conductor { ior, roughness } => {
                let (eta, k) = ior.eval(&sp.tex, w);
                Conductor::new(roughness.distribution(&sp.tex), eta, k).into()
            }
            Material::Dielectric { eta, roughness } => {
                Dielectric::new(eta.hero(w), roughness.distribution(&sp.tex)).into()
            }
            Material::ThinDielectric { eta } => ThinDielectric::new(*eta).into(),
            Material::CoatedDiffuse(m) => m.bxdf(&sp.tex, w),
            Material::CoatedConductor(m) => m.bxdf(&sp.tex, w),
            Material::Hair(m) => m.bxdf(&sp.tex, w),
            Material::Measured(brdf) => Measured::new(brdf.clone(), w.lambda).into(),
            Material::Mix(_) => return self.bsdf_of_unresolved_mix(sp, w),
            Material::Subsurface(m) => return Some(m.boundary_bsdf(sp)),
            // The perturbation needs the surface's derivatives, which
            // `SurfaceInteraction::bsdf` supplies; here the base material is used as it is.
            Material::Bumped(b) => return b.base.bsdf(sp, w),
            Material::Interface => return None,
        };
        Some(Bsdf::new(sp.ns, sp.dpdu, sp.ng, bxdf))
    }

    /// The BSDF of a mix not resolved with its hit: the choice keys on the shading point. Out
    /// of line, so that the key's hash is not computed speculatively for every other material.
    #[inline(never)]
    fn bsdf_of_unresolved_mix(&self, sp: &ShadingPoint, w: &mut SampledWavelengths) -> Option<Bsdf> {
        let key = hit_key(sp.ns, sp.tex.uv.extend(0.0));
        self.resolve(key, &sp.tex).bsdf(sp, w)
    }
}

fn clamp01(s: SampledSpectrum) -> SampledSpectrum {
    s.map(|x| x.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::named_spectra::named_spectrum;

    fn point() -> ShadingPoint {
        ShadingPoint { ns: Vec3::Z, ng: Vec3::Z, dpdu: Vec3::X, tex: TextureEvalContext::uv(glam::Vec2::ZERO) }
    }

    #[test]
    fn only_materials_with_varying_textures_ask_for_a_footprint() {
        use crate::texture::{Checkerboard, Mapping2D, Texture};
        use std::sync::Arc;
        let board = || -> SpectrumTexture {
            let c = |v: f32| Arc::new(Texture::Constant(Spectrum::constant(v)));
            Texture::Checkerboard { pattern: Checkerboard::Planar(Mapping2D::UV), tex: [c(0.2), c(0.8)] }
        };
        assert!(!Material::diffuse(Spectrum::constant(0.5)).is_textured());
        assert!(Material::Diffuse { reflectance: board() }.is_textured());
        let rough = |u: FloatTexture| Roughness { v: u.clone(), u, remap: true };
        let smooth = Material::Dielectric { eta: Ior::Constant(1.5), roughness: rough(FloatTexture::Constant(0.1)) };
        assert!(!smooth.is_textured());
        let fbm = FloatTexture::Source(crate::texture::FloatSource::Windy {
            mapping: crate::texture::Mapping3D { texture_from_world: glam::Mat4::IDENTITY },
        });
        assert!(Material::Dielectric { eta: Ior::Constant(1.5), roughness: rough(fbm) }.is_textured());
        assert!(!Material::ThinDielectric { eta: 1.5 }.is_textured());
    }

    #[test]
    fn only_a_dispersive_dielectric_terminates_the_secondary_wavelengths() {
        let smooth = Roughness::alpha(0.0);
        let bk7 = named_spectrum("glass-BK7").expect("BK7 is built in");
        let cases = [
            (Material::diffuse(Spectrum::constant(0.5)), false),
            (Material::Dielectric { eta: Ior::Constant(1.5), roughness: smooth.clone() }, false),
            (Material::Dielectric { eta: Ior::Spectral(Spectrum::constant(1.5)), roughness: smooth.clone() }, false),
            (Material::Dielectric { eta: Ior::Spectral(bk7), roughness: smooth }, true),
        ];
        for (m, dispersive) in cases {
            let mut w = SampledWavelengths::sample_uniform(0.37);
            let _ = m.bsdf(&point(), &mut w);
            assert_eq!(m.is_dispersive(), dispersive, "{m:?}");
            assert_eq!(w.secondary_terminated(), dispersive, "{m:?}");
        }
    }
}
