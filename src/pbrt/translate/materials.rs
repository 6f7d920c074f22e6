//! pbrt-v4's metals, coated materials and mixes → [`Material`], with the parameters and
//! defaults of pbrt-v4's `ConductorMaterial`, `CoatedDiffuseMaterial`,
//! `CoatedConductorMaterial` and `MixMaterial::Create`.

use super::{param_error, Ctx};
use crate::bsdf::{MeasuredBrdf, MeasuredError};
use crate::material::{
    melanin_sigma_a, CoatedConductorMaterial, CoatedDiffuseMaterial, ConductorIor, HairAbsorption, HairMaterial, Ior,
    LayerSpec, Material, MixMaterial, NormalMap, NormalPerturbation, Roughness,
};
use crate::pbrt::desc::MaterialDesc;
use crate::pbrt::error::{Location, SceneError};
use crate::pbrt::params::ParamSet;
use crate::spectrum::RgbKind;
use crate::texture::Texture;
use crate::texture::{rgb_texels, ColorEncoding};
use std::sync::Arc;

/// How deep mixes may nest: deeper means a mix names itself through others.
const MAX_MIX_NESTING: usize = 32;
/// Materials one mix tree may hold.
const MAX_MIX_NODES: usize = 4096;

impl Ctx<'_> {
    /// A material's "string normalmap" (an RGB image, read with linear encoding) or, without
    /// one, its "float displacement" (pbrt-v4 reads both for every material but mix and
    /// interface, and uses the normal map when both are given).
    pub(super) fn normal_perturbation(
        &mut self,
        p: &ParamSet,
        loc: &Location,
    ) -> Result<Option<NormalPerturbation>, SceneError> {
        let has_displacement = p.has("displacement");
        if let Some(file) = p.filename("normalmap") {
            if has_displacement {
                let _ = p.get("displacement");
            }
            if let Some(map) = self.textures.normal_maps.get(&file) {
                return Ok(Some(NormalPerturbation::NormalMap(map.clone())));
            }
            let bad = |reason: String| param_error(p, "normalmap", loc, format!("{}: {reason}", file.display()));
            let img = crate::image::read(&file).map_err(|e| bad(format!("cannot read the image: {e}")))?;
            if img.channels < 3 {
                return Err(bad(format!("a normal map needs RGB channels, the image has {}", img.channels)));
            }
            let integer = crate::image::FileFormat::from_path(&file).is_ok_and(|f| !f.is_linear());
            let texels = rgb_texels(&img, integer.then_some(ColorEncoding::Linear));
            let map = NormalMap::new(img.width as usize, img.height as usize, texels)
                .ok_or_else(|| bad("the image is empty".to_string()))?;
            let map = Arc::new(map);
            self.textures.normal_maps.insert(file, map.clone());
            return Ok(Some(NormalPerturbation::NormalMap(map)));
        }
        if !has_displacement {
            return Ok(None);
        }
        Ok(Some(NormalPerturbation::Displacement(self.float_texture(p, "displacement", 0.0)?)))
    }

    /// "conductor": `eta`/`k` (default copper) or `reflectance`, and roughness.
    pub(super) fn conductor(&mut self, p: &ParamSet, loc: &Location) -> Result<Material, SceneError> {
        let ior = self.conductor_ior(p, ["eta", "k", "reflectance"], loc)?;
        Ok(Material::Conductor { ior, roughness: self.prefixed_roughness(p, "")? })
    }

    /// A metal's index from `names` = [η, k, reflectance]; giving both forms is an error, as in
    /// pbrt-v4.
    fn conductor_ior(&mut self, p: &ParamSet, names: [&str; 3], loc: &Location) -> Result<ConductorIor, SceneError> {
        let [eta, k, reflectance] = names;
        if p.has(reflectance) {
            if p.has(eta) || p.has(k) {
                let message = format!("give either \"{reflectance}\" or \"{eta}\" and \"{k}\", not both");
                return Err(param_error(p, reflectance, loc, message));
            }
            return Ok(ConductorIor::Reflectance(self.spectrum_texture(p, reflectance, 0.0, loc)?));
        }
        Ok(ConductorIor::EtaK {
            eta: self.unbounded(p, eta, "metal-Cu-eta", loc)?,
            k: self.unbounded(p, k, "metal-Cu-k", loc)?,
        })
    }

    /// An index of refraction given as a float or a spectrum (default `default`).
    pub(super) fn ior(&mut self, p: &ParamSet, name: &str, default: f32, loc: &Location) -> Result<Ior, SceneError> {
        Ok(match (p.float(name), p.spectrum(name)) {
            (Some(e), _) => Ior::Constant(e),
            (None, Some(s)) => {
                let s = s.clone();
                Ior::Spectral(
                    self.spectrum(&s, RgbKind::Unbounded, p)
                        .map_err(|e| super::param_error(p, name, loc, e.to_string()))?,
                )
            }
            (None, None) => Ior::Constant(default),
        })
    }

    /// Roughness from `{prefix}roughness` and its u/v forms, remapped unless
    /// "remaproughness" is false.
    pub(super) fn prefixed_roughness(&mut self, p: &ParamSet, prefix: &str) -> Result<Roughness, SceneError> {
        let (iso, u, v) = (format!("{prefix}roughness"), format!("{prefix}uroughness"), format!("{prefix}vroughness"));
        let base = self.float_texture(p, &iso, 0.0)?;
        let u = if p.has(&u) { self.float_texture(p, &u, 0.0)? } else { base.clone() };
        let v = if p.has(&v) { self.float_texture(p, &v, 0.0)? } else { base };
        Ok(Roughness { u, v, remap: p.bool_or("remaproughness", true) })
    }

    /// The slab of a coated material: thickness, albedo, g, maxdepth, nsamples.
    fn layer(&mut self, p: &ParamSet, loc: &Location) -> Result<LayerSpec, SceneError> {
        let count = |name: &str, default: i32, min: i32| match p.int(name) {
            Some(n) if n < min => Err(param_error(p, name, loc, format!("\"{name}\" must be at least {min}, got {n}"))),
            n => Ok(n.unwrap_or(default) as u32),
        };
        Ok(LayerSpec {
            thickness: self.float_texture(p, "thickness", 0.01)?,
            albedo: self.spectrum_texture(p, "albedo", 0.0, loc)?,
            g: self.float_texture(p, "g", 0.0)?,
            max_depth: count("maxdepth", 10, 0)?,
            n_samples: count("nsamples", 1, 1)?,
        })
    }

    /// "coateddiffuse"; prism's `"string model" "analytic"` selects the closed-form coat.
    pub(super) fn coated_diffuse(&mut self, p: &ParamSet, loc: &Location) -> Result<Material, SceneError> {
        let analytic = match p.string("model") {
            None | Some("layered") => false,
            Some("analytic") => true,
            Some(other) => {
                let message = format!("unknown coateddiffuse model \"{other}\"; valid models: analytic, layered");
                return Err(param_error(p, "model", loc, message));
            }
        };
        Ok(Material::CoatedDiffuse(Box::new(CoatedDiffuseMaterial {
            reflectance: self.spectrum_texture(p, "reflectance", 0.5, loc)?,
            roughness: self.prefixed_roughness(p, "")?,
            eta: self.ior(p, "eta", 1.5, loc)?,
            layer: self.layer(p, loc)?,
            analytic,
        })))
    }

    /// "hair" (pbrt-v4's `HairMaterial::Create`): σa from "sigma_a", else from "reflectance" (or,
    /// without it, "color"), else from "eumelanin" (1.3 when none is given) and "pheomelanin"
    /// (0). What the chosen one overrides is read and said to be ignored, as pbrt-v4 does.
    pub(super) fn hair(&mut self, p: &ParamSet, loc: &Location) -> Result<Material, SceneError> {
        let colour = ["reflectance", "color"].into_iter().find(|n| p.has(n));
        let absorption = if p.has("sigma_a") {
            if p.texture("sigma_a").is_some() {
                self.unsupported(loc, "a textured hair \"sigma_a\"".into(), "uses eumelanin 1.3");
                HairAbsorption::SigmaA(melanin_sigma_a(1.3, 0.0))
            } else {
                HairAbsorption::SigmaA(self.unbounded_or(p, "sigma_a", [0.0; 3], loc)?)
            }
        } else if let Some(name) = colour {
            HairAbsorption::Reflectance(self.spectrum_texture(p, name, 0.5, loc)?)
        } else {
            let eumelanin = self.float_texture(p, "eumelanin", if p.has("eumelanin") { 0.0 } else { 1.3 })?;
            let pheomelanin = self.float_texture(p, "pheomelanin", 0.0)?;
            match (&eumelanin, &pheomelanin) {
                (Texture::Constant(ce), Texture::Constant(cp)) => HairAbsorption::SigmaA(melanin_sigma_a(*ce, *cp)),
                _ => HairAbsorption::Melanin { eumelanin, pheomelanin },
            }
        };
        if let Some(chosen) = if p.has("sigma_a") { Some("sigma_a") } else { colour } {
            for ignored in ["reflectance", "color", "eumelanin", "pheomelanin"] {
                if ignored != chosen && p.has(ignored) {
                    p.mark_used(ignored);
                    self.warn(loc, format!("hair: \"{ignored}\" is ignored since \"{chosen}\" was given"));
                }
            }
        }
        Ok(Material::Hair(Box::new(HairMaterial {
            absorption,
            eta: self.float_texture(p, "eta", 1.55)?,
            beta_m: self.float_texture(p, "beta_m", 0.3)?,
            beta_n: self.float_texture(p, "beta_n", 0.3)?,
            alpha: self.float_texture(p, "alpha", 2.0)?,
        })))
    }

    /// "measured": the RGL `.bsdf` file of "string filename", relative to the scene file that
    /// names it; each file is read once.
    pub(super) fn measured(&mut self, p: &ParamSet, loc: &Location) -> Result<Material, SceneError> {
        let Some(file) = p.filename("filename") else {
            return Err(SceneError::syntax(loc, "measured", "a measured material needs a \"string filename\""));
        };
        if let Some(brdf) = self.textures.measured.get(&file) {
            return Ok(Material::Measured(brdf.clone()));
        }
        let at = p.get("filename").map_or(loc, |v| &v.loc).clone();
        let brdf = match MeasuredBrdf::read(&file) {
            Ok(b) => Arc::new(b),
            Err(MeasuredError::Io(e)) => return Err(SceneError::Io { loc: at, path: file, reason: e.to_string() }),
            Err(e) => return Err(param_error(p, "filename", loc, format!("{}: {e}", file.display()))),
        };
        self.textures.measured.insert(file, brdf.clone());
        Ok(Material::Measured(brdf))
    }

    /// "coatedconductor": `interface.*` for the coat, `conductor.*` (or `reflectance`) for the
    /// metal.
    pub(super) fn coated_conductor(&mut self, p: &ParamSet, loc: &Location) -> Result<Material, SceneError> {
        Ok(Material::CoatedConductor(Box::new(CoatedConductorMaterial {
            interface_roughness: self.prefixed_roughness(p, "interface.")?,
            interface_eta: self.ior(p, "interface.eta", 1.5, loc)?,
            conductor: self.conductor_ior(p, ["conductor.eta", "conductor.k", "reflectance"], loc)?,
            conductor_roughness: self.prefixed_roughness(p, "conductor.")?,
            layer: self.layer(p, loc)?,
        })))
    }

    /// "mix": two named materials (`"string materials"`) and `amount`, the probability of the
    /// second.
    pub(super) fn mix(&mut self, m: &MaterialDesc) -> Result<Material, SceneError> {
        let mut nodes = 0;
        self.mix_tree(m, 0, &mut nodes)
    }

    /// A mix `nesting` mixes down; `nodes` counts the materials built for the whole tree (each
    /// use of a named material is a copy, so a chain of mixes naming the previous one twice
    /// doubles per link).
    fn mix_tree(&mut self, m: &MaterialDesc, nesting: usize, nodes: &mut usize) -> Result<Material, SceneError> {
        let (p, loc) = (&m.params, &m.loc);
        if nesting >= MAX_MIX_NESTING {
            let message = format!("mix materials nest more than {MAX_MIX_NESTING} deep (does a mix name itself?)");
            return Err(SceneError::syntax(loc, "materials", message));
        }
        let names = p.strings("materials").unwrap_or(&[]);
        let [a, b] = names else {
            let message = format!("a mix needs two \"string materials\", got {}", names.len());
            return Err(param_error(p, "materials", loc, message));
        };
        let mut pick = |name: &str| -> Result<Material, SceneError> {
            let Some((_, d)) = self.defs.named_material(name) else {
                return Err(param_error(p, "materials", loc, format!("no named material \"{name}\"")));
            };
            *nodes += 1;
            if *nodes > MAX_MIX_NODES {
                let message = format!("a mix tree of more than {MAX_MIX_NODES} materials");
                return Err(param_error(p, "materials", loc, message));
            }
            if d.kind == "mix" {
                self.mix_tree(d, nesting + 1, nodes)
            } else {
                self.make_material(d)
            }
        };
        let materials = [pick(a)?, pick(b)?];
        let amount = self.float_texture(p, "amount", 0.5)?;
        Ok(Material::Mix(Box::new(MixMaterial { amount, materials })))
    }
}

#[cfg(test)]
mod tests {
    use crate::material::{HairAbsorption, Material};
    use crate::pbrt::{parse_str, ParseOptions};

    fn hair(params: &str) -> (HairAbsorption, usize) {
        let text = format!("Camera \"perspective\"\nWorldBegin\nMaterial \"hair\" {params}\nShape \"sphere\"\n");
        let (desc, mut w) = parse_str(&text, &ParseOptions::default()).unwrap();
        let (b, _) = super::super::build(&desc, &mut w).unwrap();
        let scene = b.build(crate::accel::AccelKind::Obvhs).unwrap();
        let Material::Hair(m) = &scene.materials()[0] else { panic!("{:?}", scene.materials()[0]) };
        (m.absorption.clone(), w.len())
    }

    #[test]
    fn hair_absorption_follows_pbrt_v4s_precedence() {
        let eumelanin = |c: f32| crate::material::melanin_sigma_a(c, 0.0).eval(550.0);
        // Nothing given: eumelanin 1.3.
        let (HairAbsorption::SigmaA(s), 0) = hair("") else { panic!() };
        assert!((s.eval(550.0) - eumelanin(1.3)).abs() < 1e-6);
        let (HairAbsorption::SigmaA(s), 0) = hair("\"float eumelanin\" [ 0.3 ]") else { panic!() };
        assert!((s.eval(550.0) - eumelanin(0.3)).abs() < 1e-6);
        // σa wins over a colour, a colour over melanin, each overridden one with a note.
        let (HairAbsorption::SigmaA(s), 1) = hair("\"rgb sigma_a\" [ 2 2 2 ] \"rgb reflectance\" [ 0.5 0.5 0.5 ]")
        else {
            panic!()
        };
        assert!((s.eval(550.0) - 2.0).abs() < 0.02, "{}", s.eval(550.0));
        assert!(matches!(
            hair("\"rgb reflectance\" [ 0.5 0.3 0.2 ] \"float eumelanin\" [ 1 ]"),
            (HairAbsorption::Reflectance(_), 1)
        ));
        // "color" stands for "reflectance" when that is absent (pbrt-v3's name).
        let reflectance_of = |params: &str| match hair(params) {
            (HairAbsorption::Reflectance(crate::texture::Texture::Constant(c)), n) => (c.eval(650.0), n),
            other => panic!("{other:?}"),
        };
        let (grey, 0) = reflectance_of("\"rgb color\" [ 0.5 0.5 0.5 ]") else { panic!() };
        assert!((grey - 0.5).abs() < 0.01, "{grey}");
        let (red, 1) = reflectance_of("\"rgb color\" [ 0.1 0.1 0.1 ] \"rgb reflectance\" [ 0.8 0.1 0.1 ]") else {
            panic!()
        };
        assert!(red > 0.6, "{red}");
    }
}
