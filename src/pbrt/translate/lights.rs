//! pbrt-v4 lights onto prism's: point, spot (pbrt-v4's cone or Warn's), distant, uniform and
//! image infinite lights, and the brightness targets (`scale`, pbrt-v4's `power`/`illuminance`,
//! prism's SI `lumens`/`lux`/`watts`/`irradiance`; docs/radiometry.md).

use super::{param_error, space_of, Ctx};
use crate::image::Image;
use crate::light::photometry::{lumens_per_unit_y, spectral_integral};
use crate::light::{
    image_upper_hemisphere_y, is_rectangle, DistantLight, EnvMapLight, GoniometricLight, Light, MapLayout, PointLight,
    PortalLight, ProjectionLight, SpotFalloff, SpotLight, UniformInfiniteLight,
};
use crate::pbrt::desc::LightDesc;
use crate::pbrt::error::{Location, SceneError};
use crate::pbrt::params::{ParamSet, SpectrumParam};
use crate::spectrum::{ColorSpace, RgbKind, Spectrum};
use glam::Vec3;
use std::sync::Arc;

impl Ctx<'_> {
    /// A light's spectrum and the factor that gives it unit luminance (pbrt-v4's normalisation;
    /// RGB illuminants are normalised by their illuminant alone so the RGB sets brightness).
    pub(super) fn light_spectrum(
        &mut self,
        p: &ParamSet,
        name: &str,
        loc: &Location,
    ) -> Result<(Spectrum, f32), SceneError> {
        let space = space_of(p);
        let white = Spectrum::from_rgb([1.0, 1.0, 1.0], RgbKind::Illuminant, space);
        let (s, reference) = match p.spectrum(name) {
            None => (white.clone(), white),
            Some(sp) => {
                let sp = sp.clone();
                let s =
                    self.spectrum(&sp, RgbKind::Illuminant, p).map_err(|e| param_error(p, name, loc, e.to_string()))?;
                let r = if matches!(sp, SpectrumParam::Rgb(_)) { white } else { s.clone() };
                (s, r)
            }
        };
        // Evaluated at every light sample: tabulated, as pbrt-v4 does.
        let s = s.densely_sampled();
        let y = reference.to_xyz_f64().y;
        let norm = if y > 0.0 { 1.0 / y } else { 0.0 };
        if (norm as f32).is_finite() || !matches!(p.spectrum(name), Some(q) if !matches!(q, SpectrumParam::Rgb(_))) {
            Ok((s, (norm as f32).min(f32::MAX)))
        } else {
            // A nearly invisible spectrum (a blackbody of a few hundred kelvin): its 1/Y overflows
            // f32, so fold it into the spectrum in double precision instead.
            Ok((s.scaled(norm), 1.0))
        }
    }

    /// pbrt "infinite" with "filename": a square image is pbrt-v4's equal-area octahedral map,
    /// any other shape prism's latitude–longitude map (+z up, u = φ/2π, v = θ/π; pbrt-v3's
    /// layout), its RGB an illuminant of the scene's colour space (pbrt-v4 reads the file's; prism
    /// does not read colour-space metadata from files), times `scale`. "illuminance" E scales
    /// the map as pbrt-v4 does, which on an equal-area map gives an upward-facing (+z) patch 2E
    /// ([`image_upper_hemisphere_y`]); prism's "lux" E gives it E. With "portal" (four corners
    /// of a rectangle, world space) it is pbrt-v4's portal light ([`PortalLight`]).
    ///
    /// Without "filename", "L" beside a portal becomes, as in pbrt-v4, a 1 × 1 map of L's colour
    /// in sRGB (its XYZ in the ∫ȳ normalisation; an RGB "L" keeps its colour exactly).
    pub(super) fn env_map(&mut self, l: &LightDesc) -> Result<Light, SceneError> {
        let p = &l.params;
        let (image, space) = if p.has("filename") {
            if p.has("L") {
                return Err(SceneError::syntax(
                    &l.loc,
                    "L",
                    "an infinite light takes either \"L\" or \"filename\", not both",
                ));
            }
            (self.image(p, &l.loc)?, space_of(p))
        } else {
            (Arc::new(self.constant_map(p, &l.loc)?), ColorSpace::srgb())
        };
        let rotation = orthonormal(glam::Mat3::from_mat4(l.world_from_light));
        let maps = pbrt_v4_direction_maps(l.world_from_light, self.render_origin(&l.loc)?);
        if maps.is_some() && !p.has("portal") {
            let message = "the infinite light's transform is not a rotation: pbrt-v4 turns sampled directions \
                           by it and looks escaped rays up through its inverse, which here disagree; prism does \
                           the same, so the image is pbrt-v4's rather than the map's"
                .to_string();
            self.warn(&l.loc, message);
        }
        // "illuminance" is met by the whole map, with or without a portal (as pbrt-v4).
        let k_e = if p.float(ILLUMINANCE.pbrt).is_some_and(|v| v > 0.0) {
            self.pbrt_v4_map_illuminance(p, &image, space, &l.loc)
        } else {
            image_upper_hemisphere_y(&image, space, None)
        };
        let scale = p.float_or("scale", 1.0) * brightness_factor(p, ILLUMINANCE, k_e as f32, None, &l.loc)?;
        let Some(portal) = p.get("portal") else {
            let light = EnvMapLight::new(&image, rotation, scale, space);
            return Ok(Light::EnvMap(match maps {
                Some((sample, lookup)) => light.with_pbrt_v4_direction_maps(sample, lookup),
                None => light,
            }));
        };
        // pbrt-v4: the four corners are in world space, whatever the light's transform.
        let corners = match p.point3s("portal") {
            Some(c) if c.len() == 4 => [c[0], c[1], c[2], c[3]],
            c => {
                let given = c.map_or(0, |c| c.len());
                return Err(SceneError::syntax(
                    &portal.loc,
                    "portal",
                    format!("a portal needs 4 corners, got {given}"),
                ));
            }
        };
        if MapLayout::for_size(image.width, image.height) != MapLayout::EqualArea {
            let message = "a portal needs a square (equal-area) environment map";
            return Err(SceneError::syntax(&portal.loc, "portal", message));
        }
        if !is_rectangle(&corners) {
            // pbrt-v4 reports this and goes on; the sky is then masked by the rectangle's
            // frame, not by the quadrilateral.
            self.warn(&portal.loc.clone(), "the portal's corners are not a rectangle".to_string());
        }
        Ok(Light::Portal(Box::new(PortalLight::new(&image, corners, rotation, scale, space))))
    }

    /// pbrt-v4's k_e for "illuminance" on the map `image` ([`image_upper_hemisphere_y`]). pbrt-v4
    /// weighs the first three channels of its (equal-area) map in the file's order as red,
    /// green and blue, and an OpenEXR file lists them by name (B, G, R): prism does the same,
    /// and says so when that changes the map's brightness.
    fn pbrt_v4_map_illuminance(&mut self, p: &ParamSet, image: &Image, space: &ColorSpace, loc: &Location) -> f64 {
        // pbrt-v4 has no latitude–longitude maps: there prism's own rule, in RGB order.
        let equal_area = MapLayout::for_size(image.width, image.height) == MapLayout::EqualArea;
        let channels =
            p.filename("filename").filter(|_| equal_area).and_then(|f| crate::image::exr_channels_in_file_order(&f));
        let in_rgb_order = image_upper_hemisphere_y(image, space, Some([0, 1, 2]));
        let Some(channels) = channels.filter(|&c| c != [0, 1, 2]) else {
            return in_rgb_order;
        };
        let k_e = image_upper_hemisphere_y(image, space, Some(channels));
        let factor = in_rgb_order / k_e;
        if (factor - 1.0).abs() > 0.005 {
            let names = channels.map(|c| ["R", "G", "B", "A"].get(c).copied().unwrap_or("?"));
            let message = format!(
                "pbrt-v4's \"illuminance\" takes this OpenEXR map's channels in the file's order ({}, {}, {}) \
                 as red, green and blue; prism does the same, which scales the map by {factor:.3} against \
                 its luminance in RGB order",
                names[0], names[1], names[2]
            );
            self.warn(loc, message);
        }
        k_e
    }

    /// The origin of pbrt-v4's rendering space in world space (`Option "string rendercoordsys"`):
    /// the camera's position (at the middle of its motion) for "cameraworld", pbrt-v4's default,
    /// and "camera"; the world's origin for "world".
    fn render_origin(&self, loc: &Location) -> Result<Vec3, SceneError> {
        let options = &self.desc.options;
        match options.string("rendercoordsys").unwrap_or("cameraworld") {
            "world" => Ok(Vec3::ZERO),
            "camera" | "cameraworld" => {
                let camera = &self.desc.camera;
                let position = |camera_from_world: glam::Mat4| camera_from_world.inverse().transform_point3(Vec3::ZERO);
                Ok(match &camera.motion {
                    Some(m) => 0.5 * (m.start.transform_point3(Vec3::ZERO) + m.end.transform_point3(Vec3::ZERO)),
                    None => position(camera.camera_from_world),
                })
            }
            other => {
                let message = format!("unknown rendering coordinate system \"{other}\" (camera, cameraworld, world)");
                Err(param_error(options, "rendercoordsys", loc, message))
            }
        }
    }

    /// A 1 × 1 RGB image (sRGB) of an infinite light's "L".
    fn constant_map(&mut self, p: &ParamSet, loc: &Location) -> Result<crate::image::Image, SceneError> {
        let srgb = ColorSpace::srgb();
        let rgb = match p.spectrum("L") {
            Some(SpectrumParam::Rgb(rgb)) => srgb.xyz_to_rgb(space_of(p).rgb_to_xyz(Vec3::from(*rgb).max(Vec3::ZERO))),
            Some(sp) => {
                let sp = sp.clone();
                let s =
                    self.spectrum(&sp, RgbKind::Illuminant, p).map_err(|e| param_error(p, "L", loc, e.to_string()))?;
                let at = p.get("L").map_or(loc, |q| &q.loc).clone();
                self.warn(&at, "the non-RGB \"L\" is converted to RGB for the portal light (as pbrt-v4)".into());
                srgb.xyz_to_rgb(s.to_xyz_f64().as_vec3())
            }
            None => Vec3::ONE,
        };
        let mut image = crate::image::Image::new(1, 1, 3);
        image.data.copy_from_slice(&rgb.max(Vec3::ZERO).to_array());
        Ok(image)
    }

    /// A spotlight's falloff: Warn's cos^s lobe given "exponent" s ≥ 0 (prism's extension; D. R.
    /// Warn, "Lighting Controls for Synthetic Images", SIGGRAPH 1983), else pbrt-v4's cone: full
    /// intensity out to "coneangle" − "conedeltaangle", smoothstep to zero at "coneangle" (degrees;
    /// 0 < coneangle ≤ 180, 0 ≤ delta ≤ coneangle).
    fn spot_falloff(&mut self, p: &ParamSet, loc: &Location) -> Result<SpotFalloff, SceneError> {
        if let Some(exponent) = p.float("exponent") {
            if !(exponent >= 0.0 && exponent.is_finite()) {
                let message = format!("\"exponent\" must be a finite number ≥ 0, got {exponent}");
                return Err(param_error(p, "exponent", loc, message));
            }
            return Ok(SpotFalloff::Warn { exponent });
        }
        let cone = p.float_or("coneangle", 30.0);
        if !(cone > 0.0 && cone <= 180.0) {
            let message = format!("\"coneangle\" must be in (0, 180] degrees, got {cone}");
            return Err(param_error(p, "coneangle", loc, message));
        }
        // pbrt-v4 spells it "conedeltaangle"; "conedelta" is accepted too.
        let name = if p.has("conedelta") && !p.has("conedeltaangle") { "conedelta" } else { "conedeltaangle" };
        let mut delta = p.float(name).unwrap_or(5.0);
        if delta.is_nan() || delta < 0.0 {
            return Err(param_error(p, name, loc, format!("\"{name}\" must be ≥ 0 degrees, got {delta}")));
        }
        if delta > cone {
            // pbrt-v4 takes cos(coneangle − delta) as it comes: its falloff then starts at
            // |coneangle − delta|, and from delta > 2 coneangle on it lights everything outside
            // the cone and nothing inside it.
            let at = p.get(name).map_or(loc, |q| &q.loc).clone();
            let given = if p.has(name) { "" } else { " (the default)" };
            let message = format!(
                "\"{name}\" {delta}{given} is larger than \"coneangle\" {cone}; the falloff spans the whole cone"
            );
            self.warn(&at, message);
            delta = cone;
        }
        Ok(SpotFalloff::Cone { cos_start: (cone - delta).to_radians().cos(), cos_end: cone.to_radians().cos() })
    }

    pub(super) fn light(&mut self, l: &LightDesc) -> Result<(), SceneError> {
        let p = &l.params;
        let m = l.world_from_light;
        let scale = p.float_or("scale", 1.0);
        match l.kind {
            "point" => {
                let (s, norm) = self.light_spectrum(p, "I", &l.loc)?;
                let pos = m.transform_point3(p.point3("from").unwrap_or(Vec3::ZERO));
                let k_e = 4.0 * crate::math::PI;
                let sc = scale * norm * brightness_factor(p, FLUX, k_e, Some((&s, norm)), &l.loc)?;
                let light = PointLight::new(pos, Arc::new(s), sc);
                self.b.add_light(Light::Point(light));
            }
            "spot" => {
                let (s, norm) = self.light_spectrum(p, "I", &l.loc)?;
                let from = m.transform_point3(p.point3("from").unwrap_or(Vec3::ZERO));
                let to = m.transform_point3(p.point3("to").unwrap_or(Vec3::Z));
                let falloff = self.spot_falloff(p, &l.loc)?;
                let k_e = falloff.solid_angle_integral();
                let sc = scale * norm * brightness_factor(p, FLUX, k_e, Some((&s, norm)), &l.loc)?;
                let light = SpotLight::new(from, to - from, Arc::new(s), sc, falloff);
                self.b.add_light(Light::Spot(light));
            }
            "goniometric" if p.filename("filename").is_none() => {
                // pbrt-v4 warns and the light emits nothing.
                self.warn(&l.loc, "goniometric light without a \"filename\" emits nothing; skipped".into());
            }
            "goniometric" => {
                let (s, norm) = self.light_spectrum(p, "I", &l.loc)?;
                let image = self.image(p, &l.loc)?;
                if image.width != image.height {
                    let message = format!(
                        "a goniometric image must be square (equal-area), got {}x{}",
                        image.width, image.height
                    );
                    return Err(param_error(p, "filename", &l.loc, message));
                }
                let pos = m.transform_point3(Vec3::ZERO);
                let frame = orthonormal(glam::Mat3::from_mat4(m));
                let mut light = GoniometricLight::new(pos, frame, &image, Arc::new(s.clone()), scale * norm);
                let k_e = 4.0 * crate::math::PI * light.mean_value();
                light.scale *= brightness_factor(p, FLUX, k_e, Some((&s, norm)), &l.loc)?;
                self.b.add_light(Light::Goniometric(Box::new(light)));
            }
            "projection" => {
                // The image's RGB is an illuminant of the colour space, normalised by its white.
                let (_, norm) = self.light_spectrum(p, "", &l.loc)?;
                let image = self.image(p, &l.loc)?;
                let pos = m.transform_point3(Vec3::ZERO);
                let frame = orthonormal(glam::Mat3::from_mat4(m));
                let fov = p.float_or("fov", 90.0);
                if !(fov > 0.0 && fov < 180.0) {
                    let message = format!("\"fov\" must be between 0 and 180 degrees, got {fov}");
                    return Err(param_error(p, "fov", &l.loc, message));
                }
                let mut light = ProjectionLight::new(pos, frame, fov, &image, space_of(p), scale * norm);
                light.scale *= brightness_factor(p, FLUX, light.k_e(), None, &l.loc)?;
                self.b.add_light(Light::Projection(Box::new(light)));
            }
            "distant" => {
                let (s, norm) = self.light_spectrum(p, "L", &l.loc)?;
                let from = p.point3("from").unwrap_or(Vec3::ZERO);
                let to = p.point3("to").unwrap_or(Vec3::Z);
                let to_light = m.transform_vector3(from - to).normalize_or_zero();
                // "illuminance" [lux] on a surface perpendicular to the light (pbrt-v4 measures it
                // on an upward-facing patch, k_e = −w.y, which is 0 for its default direction).
                let e = scale * norm * brightness_factor(p, ILLUMINANCE, 1.0, Some((&s, norm)), &l.loc)?;
                self.b.add_light(Light::Distant(DistantLight { to_light, spectrum: Arc::new(s), scale: e }));
            }
            "infinite" => {
                if p.has("filename") || (p.has("L") && p.has("portal")) {
                    let light = self.env_map(l)?;
                    self.b.add_light(light);
                } else {
                    if let Some(portal) = p.get("portal") {
                        // pbrt-v4 has no portal on the default sky (it needs "L" or "filename").
                        let message = "a portal needs \"L\" or an environment map (\"filename\")";
                        self.warn(&portal.loc.clone(), format!("{message}; ignored"));
                    }
                    // pbrt-v4: a uniform sky of illuminance E_v on any patch has k_e = π.
                    let (s, norm) = self.light_spectrum(p, "L", &l.loc)?;
                    let sc =
                        scale * norm * brightness_factor(p, ILLUMINANCE, crate::math::PI, Some((&s, norm)), &l.loc)?;
                    self.b.add_light(Light::UniformInfinite(UniformInfiniteLight { spectrum: Arc::new(s), scale: sc }));
                }
            }
            other => self.unsupported(&l.loc, format!("light \"{other}\""), "skips the light"),
        }
        Ok(())
    }
}

/// The rotation (or mirror) part of `m` by Gram–Schmidt, so scales and shears in the CTM do
/// not distort an environment's solid angles.
/// pbrt-v4's two direction maps of an image infinite light whose transform `world_from_light` is
/// not a rotation (mirrors count as rotations), `None` when it is one. pbrt-v4 works in a
/// rendering space that is world space moved to `render_origin` (its default "cameraworld": the
/// camera's position; "world": the origin). Sampled directions go through the upper 3 × 3 of
/// render-from-light, A − c pᵀ (A the upper 3 × 3 of `world_from_light`, pᵀ its projective
/// row, c = `render_origin`); escaped rays are looked up through the upper 3 × 3 of
/// light-from-render, which is that of `world_from_light`⁻¹ whatever c is. The two are each
/// other's inverse only when pᵀ = 0 or c = 0 (see [`EnvMapLight::with_pbrt_v4_direction_maps`]).
fn pbrt_v4_direction_maps(world_from_light: glam::Mat4, render_origin: Vec3) -> Option<(glam::Mat3, glam::Mat3)> {
    let a = glam::Mat3::from_mat4(world_from_light);
    let projective = world_from_light.row(3).truncate();
    let rotation = orthonormal(a);
    let is_rotation = projective.abs().max_element() < 1e-6
        && (0..3).all(|i| (a.col(i) - rotation.col(i)).abs().max_element() < 1e-4);
    let lookup = glam::Mat3::from_mat4(world_from_light.inverse());
    if is_rotation || !lookup.is_finite() {
        return None;
    }
    let c = render_origin;
    let sample = a - glam::Mat3::from_cols(c * projective.x, c * projective.y, c * projective.z);
    Some((sample, lookup))
}

fn orthonormal(m: glam::Mat3) -> glam::Mat3 {
    let x = m.x_axis.normalize_or(Vec3::X);
    let y = (m.y_axis - x * x.dot(m.y_axis)).normalize_or(Vec3::Y);
    let z = x.cross(y);
    let z = if z.dot(m.z_axis) < 0.0 { -z } else { z };
    glam::Mat3::from_cols(x, y, z)
}

/// How a light's brightness may be given besides `scale`: pbrt-v4's parameter, and prism's SI
/// photometric and radiometric ones.
pub(super) struct Target {
    /// pbrt-v4's name; q sets the film's Y (its luminance in the ∫ȳ normalisation of `spectrum::cie`) to q / k_e.
    pbrt: &'static str,
    /// In lm or lux: q sets K_m ∫ ȳ(λ) x(λ) dλ to q / k_e.
    photometric: &'static str,
    /// In W or W/m²: q sets ∫ x(λ) dλ over 360–830 nm to q / k_e.
    radiometric: &'static str,
}

/// Flux: pbrt-v4 `power`, prism `lumens` [lm] and `watts` [W].
pub(super) const FLUX: Target = Target { pbrt: "power", photometric: "lumens", radiometric: "watts" };
/// Irradiance on a perpendicular (distant) or any (uniform infinite) patch: `illuminance`,
/// `lux` [lx], `irradiance` [W/m²].
pub(super) const ILLUMINANCE: Target = Target { pbrt: "illuminance", photometric: "lux", radiometric: "irradiance" };

/// The factor for a unit-luminance spectrum `s` that meets a brightness target
/// (docs/radiometry.md). pbrt-v4 (`lights.cpp`) divides the spectrum by ∫ s ȳ dλ and multiplies
/// by q / k_e, k_e being the light's geometric factor, and its film reads Y = ∫ ȳ L dλ (no 1/∫ȳ):
/// so in the ∫ȳ normalisation (see `spectrum::cie`) `power` q is a flux whose Y is q. The SI targets divide by
/// what one unit gives: K_m ∫ȳ dλ lumens, or ∫ s dλ watts for the spectrum `s` × `norm`
/// (`None`: not offered). Without a target, 1.
pub(super) fn brightness_factor(
    p: &ParamSet,
    t: Target,
    k_e: f32,
    s: Option<(&Spectrum, f32)>,
    loc: &Location,
) -> Result<f32, SceneError> {
    let given: Vec<(&str, f32)> = [t.pbrt, t.photometric, t.radiometric]
        .into_iter()
        .filter_map(|n| p.float(n).filter(|&v| v > 0.0).map(|v| (n, v)))
        .collect();
    let (name, q) = match given.as_slice() {
        [] => return Ok(1.0),
        [one] => *one,
        [(a, _), (b, _), ..] => {
            return Err(SceneError::syntax(loc, b, format!("give one of \"{a}\" and \"{b}\", not both")));
        }
    };
    let per_unit = if name == t.pbrt {
        1.0
    } else if name == t.photometric {
        lumens_per_unit_y()
    } else {
        match s {
            Some((s, norm)) => spectral_integral(s) * norm,
            None => return Err(SceneError::syntax(loc, name, "this light does not take a radiometric target")),
        }
    };
    Ok(if k_e > 0.0 && per_unit > 0.0 { q / (k_e * per_unit) } else { 1.0 })
}
