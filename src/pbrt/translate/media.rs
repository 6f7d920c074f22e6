//! pbrt-v4's MakeNamedMedium → [`Medium`], with parameters and defaults as pbrt-v4's
//! `media.cpp`: "homogeneous" (`sigma_a`, `sigma_s` (default 1 each), `scale`, `g`, `preset`,
//! `Le`, `Lescale`) and "uniformgrid" (`density` with `nx`, `ny`, `nz`, bounds `p0`/`p1`, and
//! the same coefficients), "rgbgrid" (RGB grids of σ_a, σ_s and `Le`), "cloud" and "nanovdb"
//! (`nanovdb.rs`). Emission `Le` of homogeneous and density grids is normalised to unit
//! luminance like a light's, then multiplied by `Lescale`; an rgbgrid's `Le` grid is not
//! normalised, as pbrt-v4's.

use super::{param_error, space_of, Ctx};
use crate::media::presets::{measured_coefficients, measured_media_names};
use crate::media::{
    CloudMedium, CloudShape, DensityGrid, EmissionSource, GridEmission, GridMedium, Homogeneous, Medium, RgbGridMedium,
    SpectrumGrid,
};
use crate::pbrt::desc::{MediumDesc, MediumNames};
use crate::pbrt::error::SceneError;
use crate::pbrt::params::{ParamSet, SpectrumParam};
use crate::scene::MediumInterface;
use crate::spectrum::{RgbKind, Spectrum};
use glam::{UVec3, Vec3};
use rustc_hash::FxHashMap as HashMap;

/// Medium ids by name.
pub(super) type MediumIds = HashMap<String, u32>;

/// The largest extinction coefficient σ_t·scale·density a medium may reach [1/scene unit]:
/// free-flight sampling steps by about 1/σ_maj, which must stay resolvable in `f32` distances,
/// and the majorant must stay finite.
pub(super) const MAX_EXTINCTION: f32 = 1e15;

/// Checks densities: finite, and with `sigma_t` (the medium's largest σ·scale) within
/// [`MAX_EXTINCTION`]; the message names the first offending value.
pub(super) fn check_densities(values: impl IntoIterator<Item = f32>, sigma_t: f64) -> Result<(), String> {
    for v in values {
        let reach = f64::from(v) * sigma_t;
        if !v.is_finite() || reach > f64::from(MAX_EXTINCTION) {
            return Err(format!(
                "density {v:e} is out of range: densities must be finite and σ_t·scale·density at most \
                 {MAX_EXTINCTION:e} per unit length"
            ));
        }
    }
    Ok(())
}

impl Ctx<'_> {
    /// Builds every named medium the renderer supports (others were reported by the parser and
    /// are vacuum) and sets the camera's medium.
    pub(super) fn media(&mut self) -> Result<MediumIds, SceneError> {
        let mut ids = MediumIds::default();
        for m in &self.desc.media {
            if let Some(medium) = self.medium(m)? {
                ids.insert(m.name.clone(), self.b.add_medium(medium));
            }
        }
        self.b.set_camera_medium(ids.get(&self.desc.camera.medium).copied());
        Ok(ids)
    }

    fn medium(&mut self, m: &MediumDesc) -> Result<Option<Medium>, SceneError> {
        let p = &m.params;
        let (sigma_a, sigma_s) = if m.kind == "rgbgrid" {
            (Spectrum::constant(0.0), Spectrum::constant(0.0))
        } else {
            self.coefficients(m)?
        };
        let scale = p.float_or("scale", 1.0);
        let g = p.float_or("g", 0.0);
        if !(g.is_finite() && g.abs() < 1.0) {
            return Err(param_error(p, "g", &m.loc, format!("g must lie in (-1, 1), got {g}")));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(param_error(p, "scale", &m.loc, format!("scale must be ≥ 0, got {scale}")));
        }
        // σ_t·scale bounds every coefficient a medium scales by its density, so it must be finite
        // and leave room for the densities (checked against MAX_EXTINCTION where read).
        for (name, sigma) in [("sigma_a", &sigma_a), ("sigma_s", &sigma_s)] {
            let max = sigma.max_value() * f64::from(scale);
            if !(max.is_finite() && max <= f64::from(MAX_EXTINCTION)) {
                let message =
                    format!("{name}·scale reaches {max:e}; media are limited to {MAX_EXTINCTION:e} per unit length");
                return Err(param_error(p, name, &m.loc, message));
            }
        }
        Ok(match m.kind.as_str() {
            "homogeneous" => {
                let le = self.emission(p, &m.loc)?;
                Some(Medium::Homogeneous(Homogeneous { sigma_a, sigma_s, scale, le, g }))
            }
            "uniformgrid" => {
                let n = ["nx", "ny", "nz"].map(|k| p.int_or(k, 1));
                let density = p.floats("density").map(<[f32]>::to_vec).unwrap_or_default();
                let sigma_t = (sigma_a.max_value() + sigma_s.max_value()) * f64::from(scale);
                check_densities(density.iter().copied(), sigma_t).map_err(|e| param_error(p, "density", &m.loc, e))?;
                let expect = n.iter().map(|&k| k.max(0) as u64).product::<u64>();
                let grid = (n.iter().all(|&k| k > 0))
                    .then(|| DensityGrid::new(UVec3::new(n[0] as u32, n[1] as u32, n[2] as u32), density.clone()))
                    .flatten()
                    .ok_or_else(|| {
                        let message =
                            format!("uniformgrid \"density\" has {} values; nx·ny·nz = {expect}", density.len());
                        param_error(p, "density", &m.loc, message)
                    })?;
                let p0 = p.point3("p0").unwrap_or(Vec3::ZERO);
                let p1 = p.point3("p1").unwrap_or(Vec3::ONE);
                let coefficients = Homogeneous { sigma_a, sigma_s, scale, le: Spectrum::constant(0.0), g };
                let n = UVec3::new(n[0] as u32, n[1] as u32, n[2] as u32);
                let emission = self.grid_emission(m, n)?;
                let mut medium = GridMedium::new(m.world_from_medium, p0, p1, grid, coefficients).ok_or_else(|| {
                    param_error(p, "p0", &m.loc, "the grid's bounds are empty or its transform singular".into())
                })?;
                medium.emission = emission;
                Some(Medium::Grid(Box::new(medium)))
            }
            "rgbgrid" => {
                let n = ["nx", "ny", "nz"].map(|k| p.int_or(k, 1));
                let unbounded = RgbKind::Unbounded;
                for name in ["sigma_a", "sigma_s"] {
                    let rgbs = match p.spectrum(name) {
                        Some(SpectrumParam::RgbArray(v)) => v.as_slice(),
                        Some(SpectrumParam::Rgb(c)) => std::slice::from_ref(c),
                        _ => &[],
                    };
                    check_densities(rgbs.iter().flatten().copied(), f64::from(scale))
                        .map_err(|e| param_error(p, name, &m.loc, e))?;
                }
                let (a, s) = (self.rgb_grid(m, "sigma_a", n, unbounded)?, self.rgb_grid(m, "sigma_s", n, unbounded)?);
                let le = self.rgb_grid(m, "Le", n, RgbKind::Illuminant)?;
                let (p0, p1) = (p.point3("p0").unwrap_or(Vec3::ZERO), p.point3("p1").unwrap_or(Vec3::ONE));
                let medium = RgbGridMedium::new(m.world_from_medium, p0, p1, a, s, scale, g).ok_or_else(|| {
                    param_error(
                        p,
                        "p0",
                        &m.loc,
                        "rgbgrid needs sigma_a or sigma_s, non-empty bounds and an invertible transform".into(),
                    )
                })?;
                let medium = match le {
                    Some(le) => medium.with_emission(le, p.float_or("Lescale", 1.0)),
                    None => medium,
                };
                Some(Medium::RgbGrid(Box::new(medium)))
            }
            "cloud" => {
                let shape = CloudShape {
                    density: p.float_or("density", 1.0),
                    wispiness: p.float_or("wispiness", 1.0),
                    frequency: p.float_or("frequency", 5.0),
                };
                let (p0, p1) = (p.point3("p0").unwrap_or(Vec3::ZERO), p.point3("p1").unwrap_or(Vec3::ONE));
                let sigma_t = (sigma_a.max_value() + sigma_s.max_value()) * f64::from(scale);
                check_densities([shape.density], sigma_t).map_err(|e| param_error(p, "density", &m.loc, e))?;
                let coefficients = Homogeneous { sigma_a, sigma_s, scale, le: Spectrum::constant(0.0), g };
                let medium = CloudMedium::new(m.world_from_medium, p0, p1, shape, coefficients).ok_or_else(|| {
                    param_error(p, "p0", &m.loc, "the cloud's bounds are empty or its transform singular".into())
                })?;
                Some(Medium::Cloud(Box::new(medium)))
            }
            "nanovdb" => Some(self.nanovdb_medium(m, (sigma_a, sigma_s), scale, g)?),
            _ => None,
        })
    }

    /// A uniformgrid's emission (pbrt-v4 `GridMedium::Create`): `Le` (normalised to unit
    /// luminance) or a `temperature` grid (`temperatureoffset` or `temperaturecutoff`,
    /// `temperaturescale`), times the `Lescale` grid (one value per voxel; absent: 1).
    fn grid_emission(&mut self, m: &MediumDesc, n: UVec3) -> Result<Option<GridEmission>, SceneError> {
        let p = &m.params;
        let count = (n.x * n.y * n.z) as usize;
        let per_voxel = |name: &str| -> Result<Option<DensityGrid>, SceneError> {
            match p.floats(name) {
                None => Ok(None),
                Some(v) => DensityGrid::new(n, v.to_vec()).map(Some).ok_or_else(|| {
                    param_error(
                        p,
                        name,
                        &m.loc,
                        format!("uniformgrid \"{name}\" has {} values; nx·ny·nz = {count}", v.len()),
                    )
                }),
            }
        };
        let temperature = per_voxel("temperature")?;
        if temperature.is_some() && p.has("Le") {
            return Err(param_error(p, "Le", &m.loc, "uniformgrid takes \"Le\" or \"temperature\", not both".into()));
        }
        let (source, norm) = match temperature {
            Some(grid) => {
                let offset = temperature_offset(p);
                (EmissionSource::Temperature { grid, offset, scale: p.float_or("temperaturescale", 1.0) }, 1.0)
            }
            None if p.has("Le") => {
                let (s, norm) = self.light_spectrum(p, "Le", &m.loc)?;
                if s.max_value() <= 0.0 {
                    return Ok(None);
                }
                (EmissionSource::Spectrum(s), norm)
            }
            None => return Ok(None),
        };
        let mut scale = per_voxel("Lescale")?.unwrap_or_else(|| DensityGrid::new(UVec3::ONE, vec![1.0]).expect("one"));
        for v in scale.values.iter_mut() {
            *v *= norm;
        }
        Ok(Some(GridEmission { scale, source }))
    }

    /// An rgbgrid coefficient or emission: nx·ny·nz RGB triples, each lifted as `kind`.
    fn rgb_grid(
        &mut self,
        m: &MediumDesc,
        name: &str,
        n: [i32; 3],
        kind: RgbKind,
    ) -> Result<Option<SpectrumGrid>, SceneError> {
        let p = &m.params;
        let rgbs: Vec<[f32; 3]> = match p.spectrum(name) {
            None => return Ok(None),
            Some(SpectrumParam::RgbArray(v)) => v.clone(),
            Some(SpectrumParam::Rgb(c)) => vec![*c],
            Some(_) => return Err(param_error(p, name, &m.loc, format!("rgbgrid \"{name}\" must be RGB triples"))),
        };
        let count = n.iter().map(|&k| k.max(0) as u64).product::<u64>();
        if n.iter().any(|&k| k <= 0) || rgbs.len() as u64 != count {
            let message = format!("rgbgrid \"{name}\" has {} RGB values; nx·ny·nz = {count}", rgbs.len());
            return Err(param_error(p, name, &m.loc, message));
        }
        let space = space_of(p);
        let values = rgbs.iter().map(|&c| Spectrum::from_rgb(c.map(|x| x.max(0.0)), kind, space)).collect();
        let n = UVec3::new(n[0] as u32, n[1] as u32, n[2] as u32);
        Ok(Some(SpectrumGrid::new(n, values).expect("the count was checked")))
    }

    /// σ_a and σ_s: a named measured medium (`preset`), else `sigma_a`/`sigma_s` (default 1).
    /// An unknown preset is a warning and the defaults, as pbrt-v4 reads it.
    fn coefficients(&mut self, m: &MediumDesc) -> Result<(Spectrum, Spectrum), SceneError> {
        let p = &m.params;
        if let Some(name) = p.string("preset") {
            match measured_coefficients(name) {
                Some(coefficients) => return Ok(coefficients),
                None => {
                    let message = format!(
                        "unknown measured medium preset \"{name}\": sigma_a and sigma_s are used (known: {})",
                        measured_media_names().join(", ")
                    );
                    self.warnings.push(crate::pbrt::error::Warning::note(&m.loc, message));
                }
            }
        }
        let sigma = |ctx: &mut Self, name: &str| -> Result<Spectrum, SceneError> {
            if p.spectrum(name).is_some() || p.float(name).is_some() {
                ctx.unbounded(p, name, "", &m.loc)
            } else {
                Ok(Spectrum::constant(1.0))
            }
        };
        Ok((sigma(self, "sigma_a")?, sigma(self, "sigma_s")?))
    }

    /// `Le` normalised to unit luminance times `Lescale` (zero without `Le`).
    fn emission(&mut self, p: &ParamSet, loc: &crate::pbrt::error::Location) -> Result<Spectrum, SceneError> {
        let le_scale = p.float_or("Lescale", 1.0);
        if !p.has("Le") {
            return Ok(Spectrum::constant(0.0));
        }
        let (s, norm) = self.light_spectrum(p, "Le", loc)?;
        if s.max_value() <= 0.0 {
            return Ok(Spectrum::constant(0.0));
        }
        Ok(s.scaled((norm * le_scale) as f64))
    }
}

/// The ids of the media a shape names ("" and media prism does not build: vacuum).
pub(super) fn interface(ids: &MediumIds, names: &MediumNames) -> MediumInterface {
    MediumInterface { inside: ids.get(&names.inside).copied(), outside: ids.get(&names.outside).copied() }
}

/// The blackbody temperature offset [K]: `temperatureoffset`, else its older name
/// `temperaturecutoff`, else 0. Both are read, as pbrt-v4 reads both, so neither is reported unused.
pub(super) fn temperature_offset(p: &ParamSet) -> f32 {
    let (offset, cutoff) = (p.float("temperatureoffset"), p.float("temperaturecutoff"));
    offset.or(cutoff).unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use crate::media::Medium;
    use crate::pbrt::{parse_str, ParseOptions};
    use crate::scene::{MediumInterface, Scene};

    fn scene(text: &str) -> Result<(Scene, Vec<String>), String> {
        let (desc, mut w) = parse_str(text, &ParseOptions::default()).map_err(|e| e.to_string())?;
        let (b, _) = super::super::build(&desc, &mut w).map_err(|e| e.to_string())?;
        w.extend(desc.report_unused());
        let scene = b.build(crate::accel::AccelKind::Obvhs).map_err(|e| e.to_string())?;
        Ok((scene, w.iter().map(|w| w.to_string()).collect()))
    }

    const MEDIA: &str = "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [ 0.1 0.2 0.3 ] \
        \"float scale\" [ 2 ] \"float g\" [ 0.5 ]\n\
        MakeNamedMedium \"milk\" \"string type\" \"homogeneous\" \"string preset\" \"Wholemilk\"\n";

    #[test]
    fn medium_interfaces_bind_shapes_and_the_camera_to_media() {
        let text = format!(
            "{MEDIA}MediumInterface \"fog\"\nCamera \"perspective\"\nWorldBegin\n\
             Shape \"sphere\"\n\
             MediumInterface \"milk\" \"fog\"\nMaterial \"interface\"\nShape \"sphere\"\n\
             MediumInterface \"\" \"\"\nShape \"sphere\""
        );
        let (s, warnings) = scene(&text).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(s.media().len(), 2);
        assert_eq!(s.camera_medium(), Some(0), "the outside medium at Camera");
        let mi: Vec<MediumInterface> = s.primitives().iter().map(|p| p.medium_interface).collect();
        assert_eq!(mi[0], MediumInterface { inside: Some(0), outside: Some(0) }, "one name is both sides");
        assert_eq!(mi[1], MediumInterface { inside: Some(1), outside: Some(0) });
        assert_eq!(mi[2], MediumInterface::default());
        assert!(!mi[0].is_transition() && mi[1].is_transition());
        let w = crate::spectrum::SampledWavelengths::sample_uniform(0.5);
        let Medium::Homogeneous(fog) = &s.media()[0] else { panic!() };
        let p = fog.point(&w);
        assert_eq!(p.g, 0.5);
        assert!((p.sigma_s[0] - 2.0).abs() < 1e-6, "sigma_s defaults to 1, times scale: {:?}", p.sigma_s);
        let rgb = crate::spectrum::Spectrum::from_rgb(
            [0.1, 0.2, 0.3],
            crate::spectrum::RgbKind::Unbounded,
            crate::spectrum::ColorSpace::srgb(),
        );
        assert_eq!(p.sigma_a, rgb.sample(&w) * 2.0, "RGB σ_a as an unbounded spectrum, times scale");
    }

    #[test]
    fn a_grid_with_a_temperature_grid_emits() {
        let text = "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \
            \"float density\" [ 1 1 ] \"float temperature\" [ 1000 1200 ] \"float temperaturescale\" 2\n\
            Camera \"perspective\"\nWorldBegin";
        let (s, warnings) = scene(text).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        let Medium::Grid(g) = &s.media()[0] else { panic!() };
        let w = crate::spectrum::SampledWavelengths::sample_uniform(0.5);
        // Between the two samples (x = ½), T = 1100 · 2 K, and the one-sample Lescale grid is 1.
        let le = g.point(glam::Vec3::new(0.5, 0.5, 0.5), &w).le;
        let expect = crate::spectrum::Spectrum::blackbody(2200.0).sample(&w);
        assert!((le - expect).max_value().abs() < 1e-4 * expect.max_value(), "{le:?} vs {expect:?}");
    }

    #[test]
    fn instanced_shapes_keep_their_media() {
        let text = format!(
            "{MEDIA}Camera \"perspective\"\nWorldBegin\nObjectBegin \"o\"\nMaterial \"interface\"\n\
             MediumInterface \"fog\" \"\"\nShape \"sphere\"\nObjectEnd\nObjectInstance \"o\"\n"
        );
        let (s, _) = scene(&text).unwrap();
        assert_eq!(s.primitives()[0].medium_interface, MediumInterface { inside: Some(0), outside: None });
    }

    #[test]
    fn bad_media_are_errors_at_their_place() {
        let undefined = "Camera \"perspective\"\nWorldBegin\nMediumInterface \"smoke\"\nShape \"sphere\"";
        let e = scene(undefined).err().unwrap();
        assert!(e.contains("<string>:4:") && e.contains("medium \"smoke\" is not defined"), "{e}");
        // An unknown preset warns and keeps sigma_a/sigma_s, as pbrt-v4.
        let preset = "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" \"Mud\"\n\
            Camera \"perspective\"\nWorldBegin";
        let (_, w) = scene(preset).unwrap();
        assert!(w.len() == 1 && w[0].contains("<string>:1:") && w[0].contains("Wholemilk"), "{w:?}");
        let g = "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"float g\" [ 1 ]\nWorldBegin";
        assert!(scene(g).err().unwrap().contains("g must lie in (-1, 1)"));
        let grid = "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [ 1 ]\nWorldBegin";
        assert!(scene(grid).err().unwrap().contains("has 1 values; nx·ny·nz = 2"));
        let grid = "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ 1 ] \
            \"float temperature\" [ 900 ] \"blackbody Le\" 2000\nWorldBegin";
        assert!(scene(grid).err().unwrap().contains("not both"));
        let grid = "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [ 1 ] \
            \"blackbody Le\" 2000 \"float Lescale\" [ 1 2 ]\nWorldBegin";
        assert!(scene(grid).err().unwrap().contains("\"Lescale\" has 2 values"));
        let huge = "MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \
            \"rgb sigma_s\" [ 1 1 1 1 1e30 1 ]\nWorldBegin";
        let e = scene(huge).err().expect("a σ_s of 1e30 must not load");
        assert!(e.contains("<string>:1:") && e.contains("1e15"), "{e}");
        let untyped = "MakeNamedMedium \"m\" \"float g\" [ 0 ]\nWorldBegin";
        assert!(scene(untyped).err().unwrap().contains("needs a \"string type\""));
    }
}
