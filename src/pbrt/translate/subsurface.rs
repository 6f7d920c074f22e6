//! pbrt-v4's "subsurface" material → [`Material::Subsurface`]. Parameters as pbrt-v4
//! `SubsurfaceMaterial::Create`: `eta` (1.33), `g` (0), `scale` (1), roughness as the
//! dielectric; the medium from `reflectance` + `mfp` (SubsurfaceFromDiffuse), else `sigma_a` +
//! `sigma_s` (defaults: pbrt's skin-like RGB (.0011, .0024, .014) and (2.55, 3.21, 3.77) per mm).
//! `name` picks a measured medium ([`crate::media::presets`]) for σ_a and σ_s, with g = 0 (the
//! tables give reduced scattering coefficients); an unknown name is an error, as in pbrt-v4.

use super::Ctx;
use crate::material::{Material, ScatteringSpec, SubsurfaceMaterial};
use crate::pbrt::desc::MaterialDesc;
use crate::pbrt::error::{SceneError, Warning};
use crate::spectrum::{RgbKind, Spectrum};

impl Ctx<'_> {
    pub(super) fn subsurface(&mut self, m: &MaterialDesc) -> Result<Material, SceneError> {
        let p = &m.params;
        let loc = &m.loc;
        let scale = p.float_or("scale", 1.0);
        let mut g = p.float_or("g", 0.0);
        let spec = if let Some(name) = p.string("name") {
            let Some((sigma_a, sigma_s)) = crate::media::presets::measured_coefficients(name) else {
                let message = format!("unknown measured medium \"{name}\"");
                return Err(SceneError::syntax(loc, "name", message));
            };
            if g != 0.0 {
                self.warnings.push(Warning::note(loc, "subsurface: g is ignored with a named medium (g = 0)"));
                g = 0.0;
            }
            ScatteringSpec::Coefficients { sigma_a, sigma_s, scale }
        } else if p.has("reflectance") {
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
        if !(g.is_finite() && g.abs() < 1.0) {
            return Err(SceneError::syntax(loc, "g", format!("subsurface g must lie in (-1, 1), got {g}")));
        }
        let roughness = self.roughness(p)?;
        Ok(Material::Subsurface(Box::new(SubsurfaceMaterial::new(spec, eta, g, roughness))))
    }

    /// An unbounded spectrum parameter (RGB, spectrum or a float), else RGB `default`.
    pub(super) fn unbounded_or(
        &mut self,
        p: &crate::pbrt::params::ParamSet,
        name: &str,
        default: [f32; 3],
        loc: &crate::pbrt::error::Location,
    ) -> Result<Spectrum, SceneError> {
        match p.spectrum(name) {
            Some(s) => {
                let s = s.clone();
                self.spectrum(&s, RgbKind::Unbounded, p).map_err(|e| super::param_error(p, name, loc, e.to_string()))
            }
            None => Ok(match p.float(name) {
                Some(v) => Spectrum::constant(v.max(0.0)),
                None => Spectrum::from_rgb(default, RgbKind::Unbounded, super::space_of(p)),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::pbrt::{parse_file, parse_str, ParseOptions};

    fn materials(text: &str) -> Result<(Vec<crate::material::Material>, usize), String> {
        let (desc, mut w) = parse_str(text, &ParseOptions::default()).map_err(|e| e.to_string())?;
        let (b, _) = super::super::build(&desc, &mut w).map_err(|e| e.to_string())?;
        let scene = b.build(crate::accel::AccelKind::Obvhs).map_err(|e| e.to_string())?;
        Ok((scene.materials().to_vec(), w.len()))
    }

    const HEAD: &str = "Camera \"perspective\"\nWorldBegin\n";
    const SHAPE: &str = "\nShape \"sphere\" \"float radius\" [ 1 ]\n";

    #[test]
    fn subsurface_parameters_map_and_bad_values_are_errors() {
        let ok = format!("{HEAD}Material \"subsurface\" \"float eta\" [ 1.4 ] \"float g\" [ 0.3 ] \"rgb mfp\" [ 1 2 3 ] \"rgb reflectance\" [ 0.5 0.6 0.7 ]{SHAPE}");
        let (m, warnings) = materials(&ok).unwrap();
        assert_eq!(warnings, 0);
        let crate::material::Material::Subsurface(s) = &m[0] else { panic!("{m:?}") };
        assert_eq!((s.eta, s.g), (1.4, 0.3));
        assert!(matches!(s.spec, crate::material::ScatteringSpec::Reflectance { .. }));
        assert!(!s.table_built(), "parsing must not build the table");
        // A named medium: the table's coefficients (Narasimhan et al. 2006's espresso), g = 0
        // with a warning, and `scale` still applies.
        let named = format!(
            "{HEAD}Material \"subsurface\" \"string name\" [ \"Espresso\" ] \"float g\" [ 0.4 ] \"float scale\" [ 10 ]{SHAPE}"
        );
        let (m, warnings) = materials(&named).unwrap();
        assert_eq!(warnings, 1, "g with a name warns");
        let crate::material::Material::Subsurface(s) = &m[0] else { panic!("{m:?}") };
        assert_eq!(s.g, 0.0);
        let crate::material::ScatteringSpec::Coefficients { sigma_a, sigma_s, scale } = &s.spec else { panic!() };
        let srgb = |c| {
            crate::spectrum::Spectrum::from_rgb(
                c,
                crate::spectrum::RgbKind::Unbounded,
                crate::spectrum::ColorSpace::srgb(),
            )
        };
        for l in [450.0, 550.0, 650.0] {
            assert_eq!(sigma_a.eval(l), srgb([4.7984, 6.5751, 8.8493]).eval(l));
            assert_eq!(sigma_s.eval(l), srgb([0.72378, 0.84557, 1.0247]).eval(l));
        }
        assert_eq!(*scale, 10.0);
        let unknown = format!("{HEAD}Material \"subsurface\" \"string name\" [ \"Mud\" ]{SHAPE}");
        assert!(materials(&unknown).unwrap_err().contains("unknown measured medium \"Mud\""));
        for bad in ["\"float g\" [ 1 ]", "\"float eta\" [ -1 ]"] {
            let text = format!("{HEAD}Material \"subsurface\" {bad}{SHAPE}");
            let e = materials(&text).unwrap_err();
            assert!(e.contains("<string>:3:"), "{e}");
        }
    }

    #[test]
    fn example_scenes_build_with_subsurface_materials() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/subsurface");
        for name in ["slab.pbrt", "sphere.pbrt", "jade.pbrt"] {
            let (desc, mut w) = parse_file(&dir.join(name), &ParseOptions::default()).unwrap();
            let (b, _) = super::super::build(&desc, &mut w).unwrap();
            assert!(w.is_empty(), "{name}: {w:?}");
            let scene = b.build(crate::accel::AccelKind::Obvhs).unwrap();
            assert!(scene.materials().iter().any(|m| matches!(m, crate::material::Material::Subsurface(_))), "{name}");
        }
    }
}
