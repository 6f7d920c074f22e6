//! pbrt-v4's "subsurface" material: a smooth or rough dielectric boundary over a homogeneous
//! scattering medium. The medium is given either by coefficients (σ_a, σ_s) × scale, or by a
//! diffuse reflectance colour and a mean free path, inverted to a single-scattering albedo
//! through the diffusion table (pbrt-v4 `SubsurfaceFromDiffuse`). The PBD table is built on
//! first use (`OnceLock`), so scenes that never need it never pay for it.

use super::{clamp01, Roughness, ShadingPoint, SpectrumTexture};
use crate::bsdf::{Bsdf, Dielectric, NormalizedFresnel};
use crate::bssrdf::BssrdfTable;
use crate::media::{HenyeyGreenstein, MediumPoint};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use std::sync::{Arc, OnceLock};

/// How the medium under the boundary is specified.
#[derive(Clone, Debug)]
pub enum ScatteringSpec {
    /// σ_a, σ_s [1/scene unit], both multiplied by `scale`.
    Coefficients {
        /// Absorption coefficient.
        sigma_a: Spectrum,
        /// Scattering coefficient.
        sigma_s: Spectrum,
        /// Multiplier (unit conversion, e.g. 1/mm → 1/m).
        scale: f32,
    },
    /// Diffuse reflectance colour ρ_eff and mean free path 1/σ_t [scene units] × `scale`.
    Reflectance {
        /// Total diffuse reflectance the medium should have.
        reflectance: SpectrumTexture,
        /// Mean free path.
        mfp: Spectrum,
        /// Multiplier on the mean free path.
        scale: f32,
    },
}

/// A dielectric boundary of index `eta` over a homogeneous medium with HG anisotropy `g`.
#[derive(Clone, Debug)]
pub struct SubsurfaceMaterial {
    /// The medium.
    pub spec: ScatteringSpec,
    /// Relative IOR of the boundary (inside over outside).
    pub eta: f32,
    /// Henyey–Greenstein asymmetry.
    pub g: f32,
    /// Boundary roughness (0: smooth).
    pub roughness: Roughness,
    sw_norm: f32,
    table: OnceLock<Arc<BssrdfTable>>,
}

impl SubsurfaceMaterial {
    /// A material; `eta` ≤ 0 or non-finite becomes 1.33, `g` is clamped to (−1, 1).
    pub fn new(spec: ScatteringSpec, eta: f32, g: f32, roughness: Roughness) -> Self {
        let eta = if eta.is_finite() && eta > 0.0 { eta } else { 1.33 };
        let g = HenyeyGreenstein::new(g).g;
        Self { spec, eta, g, roughness, sw_norm: NormalizedFresnel::normalization(eta), table: OnceLock::new() }
    }

    /// The PBD table for this material's (g, η), built on first call.
    pub fn table(&self) -> &BssrdfTable {
        self.table.get_or_init(|| Arc::new(BssrdfTable::new(self.g, self.eta)))
    }

    /// True once [`Self::table`] has been built.
    pub fn table_built(&self) -> bool {
        self.table.get().is_some()
    }

    /// The boundary BSDF at a hit (the dielectric; inside is −n).
    pub fn boundary_bsdf(&self, sp: &ShadingPoint) -> Bsdf {
        Bsdf::new(sp.ns, sp.dpdu, sp.ng, Dielectric::new(self.eta, self.roughness.distribution(&sp.tex)).into())
    }

    /// The entry-point lobe S_ω at a hit (diffusion method).
    pub fn entry_bsdf(&self, sp: &ShadingPoint) -> Bsdf {
        Bsdf::new(sp.ns, sp.dpdu, sp.ng, NormalizedFresnel::new(self.eta, self.sw_norm).into())
    }

    /// The longest mean free path 1/σ_t of the interior over 360–830 nm [scene units] (∞ where
    /// σ_t is 0), from its values every nanometre: where it exceeds an object's size, the object
    /// is optically thin.
    pub fn longest_mean_free_path(&self) -> f32 {
        let clean = |x: f32| if x.is_finite() { x.max(0.0) } else { 0.0 };
        (360..=830)
            .map(|nm| {
                let lambda = nm as f32;
                match &self.spec {
                    ScatteringSpec::Coefficients { sigma_a, sigma_s, scale } => {
                        (clean(sigma_a.eval(lambda) * scale) + clean(sigma_s.eval(lambda) * scale)).recip()
                    }
                    ScatteringSpec::Reflectance { mfp, scale, .. } => {
                        let m = mfp.eval(lambda) * scale;
                        if m > 0.0 && m.is_finite() {
                            m
                        } else {
                            f32::INFINITY
                        }
                    }
                }
            })
            .fold(0.0, f32::max)
    }

    /// The homogeneous medium inside, at the path's wavelengths: σ_a, σ_s [1/scene unit] (negative
    /// or non-finite values taken as 0), no emission, the phase function's g. The reflectance form
    /// builds the table (for the albedo inversion).
    pub fn medium(&self, sp: &ShadingPoint, w: &SampledWavelengths) -> MediumPoint {
        let (sigma_a, sigma_s) = match &self.spec {
            ScatteringSpec::Coefficients { sigma_a, sigma_s, scale } => {
                (sigma_a.sample(w) * *scale, sigma_s.sample(w) * *scale)
            }
            ScatteringSpec::Reflectance { reflectance, mfp, scale } => {
                let r = clamp01(reflectance.eval(&sp.tex, w));
                let mfp = mfp.sample(w) * *scale;
                let table = self.table();
                let mut sigma_a = SampledSpectrum::zero();
                let mut sigma_s = SampledSpectrum::zero();
                for c in 0..4 {
                    if mfp[c] > 0.0 && mfp[c].is_finite() {
                        let rho = table.invert_rho_eff(r[c]);
                        sigma_s[c] = rho / mfp[c];
                        sigma_a[c] = (1.0 - rho) / mfp[c];
                    }
                }
                (sigma_a, sigma_s)
            }
        };
        let clean = |s: SampledSpectrum| s.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
        MediumPoint { sigma_a: clean(sigma_a), sigma_s: clean(sigma_s), le: SampledSpectrum::zero(), g: self.g }
    }
}
