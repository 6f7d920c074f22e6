//! pbrt-v4's "subsurface" material → [`Material::Subsurface`]. Parameters as pbrt-v4
//! `SubsurfaceMaterial::Create`: `eta` (1.33), `g` (0), `scale` (1), roughness as the
//! dielectric; the medium from `reflectance` + `mfp` (SubsurfaceFromDiffuse), else `sigma_a` +
//! `sigma_s` (defaults: pbrt's skin-like RGB (.0011, .0024, .014) and (2.55, 3.21, 3.77) per mm).
//! Named measured media (`name`) are not shipped: a warning, then the defaults.

use super::Ctx;
use crate::material::{Material, ScatteringSpec, SubsurfaceMaterial};
use crate::scene::desc::MaterialDesc;
use crate::scene::error::SceneError;
use crate::spectrum::{RgbKind, Spectrum};

impl Ctx<'_> {
    pub(super) fn subsurface(&mut self, m: &MaterialDesc) -> Result<Material, SceneError> {
        let p = &m.params;
        let loc = &m.loc;
        if let Some(name) = p.string("name") {
            let name = name.to_string();
            self.warn(
                loc,
                format!("subsurface: measured medium \"{name}\" is not shipped with prism; using sigma_a/sigma_s"),
            );
        }
        let scale = p.float_or("scale", 1.0);
        let spec = if p.has("reflectance") {
            let reflectance = self.spectrum_texture(p, "reflectance", 1.0, loc)?;
            let mfp = self.unbounded_or(p, "mfp", [1.0; 3], loc)?;
            ScatteringSpec::Reflectance { reflectance, mfp, scale }
        } else {
            let sigma_a = self.unbounded_or(p, "sigma_a", [0.0011, 0.0024, 0.014], loc)?;
            let sigma_s = self.unbounded_or(p, "sigma_s", [2.55, 3.21, 3.77], loc)?;
            ScatteringSpec::Coefficients { sigma_a, sigma_s, scale }
        };
        let eta = p.float_or("eta", 1.33);
        if !(eta.is_finite() && eta > 0.0) {
            return Err(SceneError::syntax(loc, "eta", format!("subsurface eta must be positive, got {eta}")));
        }
        let g = p.float_or("g", 0.0);
        if !(g.is_finite() && g.abs() < 1.0) {
            return Err(SceneError::syntax(loc, "g", format!("subsurface g must lie in (-1, 1), got {g}")));
        }
        let roughness = self.roughness(p)?;
        Ok(Material::Subsurface(Box::new(SubsurfaceMaterial::new(spec, eta, g, roughness))))
    }

    /// An unbounded spectrum parameter (RGB, spectrum or a float), else RGB `default`.
    fn unbounded_or(
        &mut self,
        p: &crate::scene::params::ParamSet,
        name: &str,
        default: [f32; 3],
        loc: &crate::scene::error::Location,
    ) -> Result<Spectrum, SceneError> {
        match p.spectrum(name) {
            Some(s) => {
                let s = s.clone();
                self.spectrum(&s, RgbKind::Unbounded, p).map_err(|e| SceneError::syntax(loc, name, e))
            }
            None => Ok(match p.float(name) {
                Some(v) => Spectrum::constant(v.max(0.0)),
                None => Spectrum::from_rgb(default, RgbKind::Unbounded, super::space_of(p)),
            }),
        }
    }
}
