//! pbrt-v4 Texture directives → [`Texture`]s, with pbrt-v4's parameters and defaults
//! (`textures.cpp`). A texture parameter is a value or the name of a texture of the same class
//! defined before it; a material parameter may name any texture of the file. Every texture is
//! built once, whether a material uses it or not (as pbrt-v4 does, so bad parameters are found
//! and every parameter is read).

use super::{param_error, Ctx};
use crate::pbrt::desc::{TextureClass, TextureDesc};
use crate::pbrt::error::{Location, SceneError};
use crate::pbrt::params::ParamSet;
use crate::spectrum::{ColorSpace, RgbKind, Spectrum};
use crate::texture::{
    rgb_texels, Checkerboard, ColorEncoding, FilterFunction, FloatImage, FloatSource, FloatTexture, Mapping2D,
    Mapping3D, Marble, MipMap, MipOptions, SpectrumImage, SpectrumSource, SpectrumTexture, Texture, TextureValue,
    WrapMode,
};
use glam::{Mat4, Vec2, Vec3};
use rustc_hash::FxHashMap as HashMap;
use std::sync::Arc;

/// The textures built so far, by index into the scene's texture list, and the image pyramids
/// by what they were made from.
#[derive(Default)]
pub(super) struct Built {
    float: Vec<Option<FloatTexture>>,
    spectrum: Vec<Option<SpectrumTexture>>,
    pyramids: HashMap<String, Arc<MipMap<[f32; 3]>>>,
    /// Normal maps by file.
    pub(super) normal_maps: HashMap<std::path::PathBuf, Arc<crate::material::NormalMap>>,
    /// Measured BRDFs by file, read once however many materials name them.
    pub(super) measured: HashMap<std::path::PathBuf, Arc<crate::bsdf::MeasuredBrdf>>,
    /// The depth and expanded size of each texture built, by class (float, spectrum) and index.
    costs: [Vec<Cost>; 2],
    /// The greatest depth among the textures the texture being built names, and the sum of
    /// their expanded sizes.
    children: Cost,
}

/// How deep a texture graph is and how many textures one evaluation of it may evaluate (its
/// size as a tree, shared textures counted once per use).
#[derive(Clone, Copy, Debug, Default)]
struct Cost {
    depth: u32,
    size: u64,
}

/// The deepest texture graph accepted: evaluation recurses once per level, so the scene must
/// not choose the depth (pbrt-v4's own texture graphs are a few levels deep).
pub const MAX_TEXTURE_DEPTH: u32 = 1000;

/// The most textures one evaluation of a texture may evaluate. A graph may use a texture more
/// than once, and is evaluated as the tree it expands to, so that tree's size is bounded:
/// n textures each using the previous one twice expand to 2^n − 1.
pub const MAX_TEXTURE_EXPANSION: u64 = 1 << 16;

/// A texture parameter's value: given in place, or the name of a texture.
enum Arg<'p, V> {
    Value(V),
    /// A texture's name, and its id when a texture of that name is defined before it.
    Named(&'p str, Option<u32>),
}

/// What building differs in between float and spectrum textures.
trait Kind: TextureValue + Sized {
    /// The texture class.
    const CLASS: TextureClass;
    /// The parameter `name` of `p`, if given.
    fn arg<'p>(ctx: &mut Ctx, p: &'p ParamSet, name: &str, loc: &Location)
        -> Result<Option<Arg<'p, Self>>, SceneError>;
    /// The constant `v`.
    fn constant(v: f32) -> Self;
    /// The built textures of this class.
    fn built<'c>(ctx: &'c mut Ctx) -> &'c mut Vec<Option<Texture<Self>>>;
    /// The types only this class has, or `None` for a type it does not have.
    fn own_type(ctx: &mut Ctx, t: &TextureDesc) -> Result<Option<Self::Source>, SceneError>;
}

impl Kind for f32 {
    const CLASS: TextureClass = TextureClass::Float;

    fn arg<'p>(_: &mut Ctx, p: &'p ParamSet, name: &str, _: &Location) -> Result<Option<Arg<'p, f32>>, SceneError> {
        if let Some((t, id)) = p.texture_ref(name) {
            return Ok(Some(Arg::Named(t, id)));
        }
        Ok(p.float(name).map(Arg::Value))
    }

    fn constant(v: f32) -> f32 {
        v
    }

    fn built<'c>(ctx: &'c mut Ctx) -> &'c mut Vec<Option<FloatTexture>> {
        &mut ctx.textures.float
    }

    fn own_type(ctx: &mut Ctx, t: &TextureDesc) -> Result<Option<FloatSource>, SceneError> {
        let p = &t.params;
        let octaves = |p: &ParamSet| p.int_or("octaves", 8).clamp(0, 64) as u32;
        Ok(Some(match t.kind {
            "fbm" => {
                FloatSource::Fbm { mapping: mapping_3d(t)?, omega: p.float_or("roughness", 0.5), octaves: octaves(p) }
            }
            "wrinkled" => FloatSource::Wrinkled {
                mapping: mapping_3d(t)?,
                omega: p.float_or("roughness", 0.5),
                octaves: octaves(p),
            },
            "windy" => FloatSource::Windy { mapping: mapping_3d(t)? },
            "imagemap" => {
                let image = ctx.image_map(t)?;
                FloatSource::Image(FloatImage::new(image.mapping, &image.pyramid, image.scale, image.invert))
            }
            _ => return Ok(None),
        }))
    }
}

impl Kind for Spectrum {
    const CLASS: TextureClass = TextureClass::Spectrum;

    fn arg<'p>(
        ctx: &mut Ctx,
        p: &'p ParamSet,
        name: &str,
        loc: &Location,
    ) -> Result<Option<Arg<'p, Spectrum>>, SceneError> {
        if let Some((t, id)) = p.texture_ref(name) {
            return Ok(Some(Arg::Named(t, id)));
        }
        Ok(match p.spectrum(name) {
            None => None,
            Some(s) => {
                let s = s.clone();
                let v =
                    ctx.spectrum(&s, RgbKind::Albedo, p).map_err(|e| SceneError::syntax(loc, name, e.to_string()))?;
                Some(Arg::Value(v))
            }
        })
    }

    fn constant(v: f32) -> Spectrum {
        Spectrum::constant(v)
    }

    fn built<'c>(ctx: &'c mut Ctx) -> &'c mut Vec<Option<SpectrumTexture>> {
        &mut ctx.textures.spectrum
    }

    fn own_type(ctx: &mut Ctx, t: &TextureDesc) -> Result<Option<SpectrumSource>, SceneError> {
        let p = &t.params;
        Ok(Some(match t.kind {
            "marble" => SpectrumSource::Marble(Marble::new(
                mapping_3d(t)?,
                p.int_or("octaves", 8).clamp(0, 64) as u32,
                p.float_or("roughness", 0.5),
                p.float_or("scale", 1.0),
                p.float_or("variation", 0.2),
            )),
            "imagemap" => {
                let image = ctx.image_map(t)?;
                let space = ColorSpace::by_name(p.color_space).unwrap_or_else(ColorSpace::srgb);
                SpectrumSource::Image(SpectrumImage::new(
                    image.mapping,
                    &image.pyramid,
                    image.scale,
                    image.invert,
                    space,
                ))
            }
            _ => return Ok(None),
        }))
    }
}

/// Texture space from world space for a texture directive (the inverse of the transform in
/// effect at it).
fn texture_from_world(t: &TextureDesc) -> Result<Mat4, SceneError> {
    let m = t.world_from_texture;
    if m.determinant() == 0.0 || !m.is_finite() {
        return Err(SceneError::syntax(&t.loc, &t.name, "the transform at this texture is singular"));
    }
    Ok(m.inverse())
}

/// The 3D mapping of a solid texture.
fn mapping_3d(t: &TextureDesc) -> Result<Mapping3D, SceneError> {
    Ok(Mapping3D { texture_from_world: texture_from_world(t)? })
}

/// An imagemap's parameters and its pyramid.
struct ImageMap {
    mapping: Mapping2D,
    pyramid: Arc<MipMap<[f32; 3]>>,
    scale: f32,
    invert: bool,
}

impl Ctx<'_> {
    /// Builds every texture of the scene.
    pub(super) fn all_textures(&mut self) -> Result<(), SceneError> {
        for (i, t) in self.desc.textures.iter().enumerate() {
            match t.class {
                TextureClass::Float => drop(self.texture_at::<f32>(i)?),
                TextureClass::Spectrum => drop(self.texture_at::<Spectrum>(i)?),
            }
        }
        Ok(())
    }

    /// A material's spectrum parameter `name` (albedo: RGB clamped to [0, 1]), `default` when
    /// not given.
    pub(super) fn spectrum_texture(
        &mut self,
        params: &ParamSet,
        name: &str,
        default: f32,
        loc: &Location,
    ) -> Result<SpectrumTexture, SceneError> {
        let all = self.desc.textures.len();
        self.argument::<Spectrum>(params, name, default, loc, all)
    }

    /// A material's float parameter `name`, `default` when not given.
    pub(super) fn float_texture(&mut self, p: &ParamSet, name: &str, default: f32) -> Result<FloatTexture, SceneError> {
        let (all, loc) = (self.desc.textures.len(), p.get(name).map(|q| q.loc.clone()));
        let loc = loc.unwrap_or_else(|| self.desc.camera.directive.loc.clone());
        self.argument::<f32>(p, name, default, &loc, all)
    }

    /// Parameter `name` of `p` as a texture: the value given, the texture it names (among the
    /// first `visible` textures of the file; the last so named wins), or `default`.
    fn argument<V: Kind>(
        &mut self,
        p: &ParamSet,
        name: &str,
        default: f32,
        loc: &Location,
        visible: usize,
    ) -> Result<Texture<V>, SceneError> {
        Ok(match V::arg(self, p, name, loc)? {
            None => Texture::Constant(V::constant(default)),
            Some(Arg::Value(v)) => Texture::Constant(v),
            Some(Arg::Named(t, id)) => {
                let Some(i) = self.defs.texture_before(t, id, V::CLASS, visible) else {
                    let class = if V::CLASS == TextureClass::Float { "float" } else { "spectrum" };
                    let message = format!("no {class} texture named \"{t}\" is defined before this");
                    return Err(param_error(p, name, loc, message));
                };
                let t = self.texture_at::<V>(i)?;
                let cost = self.textures.costs[V::CLASS as usize].get(i).copied().unwrap_or_default();
                let children = &mut self.textures.children;
                children.depth = children.depth.max(cost.depth);
                children.size = children.size.saturating_add(cost.size);
                t
            }
        })
    }

    /// The texture of directive `index` (built on first use).
    fn texture_at<V: Kind>(&mut self, index: usize) -> Result<Texture<V>, SceneError> {
        if let Some(Some(t)) = V::built(self).get(index) {
            return Ok(t.clone());
        }
        let outer = std::mem::take(&mut self.textures.children);
        let t = self.build_texture::<V>(index);
        let children = std::mem::replace(&mut self.textures.children, outer);
        let cost = Cost { depth: children.depth + 1, size: children.size.saturating_add(1) };
        let t = t?;
        let d = &self.desc.textures[index];
        if cost.depth > MAX_TEXTURE_DEPTH {
            let message = format!("texture graph is more than {MAX_TEXTURE_DEPTH} textures deep");
            return Err(SceneError::syntax(&d.loc, &d.name, message));
        }
        if cost.size > MAX_TEXTURE_EXPANSION {
            let message = format!(
                "texture graph expands to {} texture evaluations per lookup (its textures used more than once \
                 count each time), more than the limit of {MAX_TEXTURE_EXPANSION}",
                cost.size
            );
            return Err(SceneError::syntax(&d.loc, &d.name, message));
        }
        let n = self.desc.textures.len();
        let costs = &mut self.textures.costs[V::CLASS as usize];
        costs.resize(n, Cost::default());
        costs[index] = cost;
        let built = V::built(self);
        built.resize_with(n, || None);
        built[index] = Some(t.clone());
        Ok(t)
    }

    fn build_texture<V: Kind>(&mut self, index: usize) -> Result<Texture<V>, SceneError> {
        let desc = self.desc;
        let t = &desc.textures[index];
        let (p, loc) = (&t.params, &t.loc);
        let arg =
            |ctx: &mut Self, name: &str, default: f32| ctx.argument::<V>(p, name, default, loc, index).map(Arc::new);
        Ok(match t.kind {
            "constant" => self.argument::<V>(p, "value", 1.0, loc, index)?,
            "bilerp" => {
                let mut corner = |name: &str, default: f32| -> Result<V, SceneError> {
                    match V::arg(self, p, name, loc)? {
                        None => Ok(V::constant(default)),
                        Some(Arg::Value(v)) => Ok(v),
                        Some(Arg::Named(..)) => {
                            Err(param_error(p, name, loc, "bilerp corners are values, not textures".into()))
                        }
                    }
                };
                let corners = [corner("v00", 0.0)?, corner("v10", 0.0)?, corner("v01", 1.0)?, corner("v11", 1.0)?];
                Texture::Bilerp { mapping: self.mapping_2d(t)?, corners: Box::new(corners) }
            }
            "checkerboard" => {
                let tex = [arg(self, "tex1", 1.0)?, arg(self, "tex2", 0.0)?];
                let pattern = match p.int_or("dimension", 2) {
                    2 => Checkerboard::Planar(self.mapping_2d(t)?),
                    3 => Checkerboard::Solid(mapping_3d(t)?),
                    d => {
                        let message = format!("a checkerboard has dimension 2 or 3, not {d}");
                        return Err(param_error(p, "dimension", loc, message));
                    }
                };
                Texture::Checkerboard { pattern, tex }
            }
            "dots" => {
                let (inside, outside) = (arg(self, "inside", 1.0)?, arg(self, "outside", 0.0)?);
                // pbrt-v4 (at 5f7a606) hands "inside" and "outside" to the texture in the
                // order opposite to its constructor's, so "outside" paints the dots and
                // "inside" the background; its images show it, and prism matches them.
                Texture::Dots { mapping: self.mapping_2d(t)?, dots: outside, background: inside }
            }
            "mix" => {
                let tex = [arg(self, "tex1", 0.0)?, arg(self, "tex2", 1.0)?];
                Texture::Mix { tex, amount: Arc::new(self.argument::<f32>(p, "amount", 0.5, loc, index)?) }
            }
            "directionmix" => {
                let tex = [arg(self, "tex1", 0.0)?, arg(self, "tex2", 1.0)?];
                let dir = t.world_from_texture.transform_vector3(p.vector3("dir").unwrap_or(Vec3::Y));
                if !(dir.length_squared() > 0.0 && dir.is_finite()) {
                    return Err(param_error(p, "dir", loc, "directionmix needs a nonzero \"dir\"".into()));
                }
                Texture::DirectionMix { tex, dir: dir.normalize() }
            }
            "scale" => {
                let tex = arg(self, "tex", 1.0)?;
                Texture::Scale { tex, scale: Arc::new(self.argument::<f32>(p, "scale", 1.0, loc, index)?) }
            }
            "ptex" => {
                let _ = (p.string("filename"), p.string("encoding"), p.float("scale"));
                let feature =
                    "ptex textures (no Ptex library or file is available to check a reader against)".to_string();
                self.unsupported(loc, feature, "uses a constant 0.5");
                Texture::Constant(V::constant(0.5))
            }
            kind => match V::own_type(self, t)? {
                Some(s) => Texture::Source(s),
                None => {
                    let class = if V::CLASS == TextureClass::Float { "float" } else { "spectrum" };
                    let message = format!("pbrt-v4 has no {class} texture of type \"{kind}\"");
                    return Err(SceneError::syntax(loc, &t.name, message));
                }
            },
        })
    }

    /// The 2D mapping of a texture directive ("mapping": "uv" by default).
    fn mapping_2d(&mut self, t: &TextureDesc) -> Result<Mapping2D, SceneError> {
        let p = &t.params;
        let delta = || Vec2::new(p.float_or("udelta", 0.0), p.float_or("vdelta", 0.0));
        Ok(match p.string("mapping").unwrap_or("uv") {
            "spherical" => Mapping2D::Spherical { texture_from_world: texture_from_world(t)? },
            "cylindrical" => Mapping2D::Cylindrical { texture_from_world: texture_from_world(t)? },
            "planar" => Mapping2D::Planar {
                texture_from_world: texture_from_world(t)?,
                vs: p.vector3("v1").unwrap_or(Vec3::X),
                vt: p.vector3("v2").unwrap_or(Vec3::Y),
                delta: delta(),
            },
            other => {
                if other != "uv" {
                    let loc = p.get("mapping").map_or(t.loc.clone(), |q| q.loc.clone());
                    self.warn(&loc, format!("texture mapping \"{other}\" is unknown; \"uv\" is used"));
                }
                Mapping2D::Uv { scale: Vec2::new(p.float_or("uscale", 1.0), p.float_or("vscale", 1.0)), delta: delta() }
            }
        })
    }

    /// An imagemap's mapping, options and pyramid (each file, encoding and lookup built once).
    fn image_map(&mut self, t: &TextureDesc) -> Result<ImageMap, SceneError> {
        let (p, loc) = (&t.params, &t.loc);
        let mapping = self.mapping_2d(t)?;
        let file = p.filename("filename").ok_or_else(|| SceneError::syntax(loc, "imagemap", "missing \"filename\""))?;
        let mut options = MipOptions { max_anisotropy: p.float_or("maxanisotropy", 8.0), ..Default::default() };
        if let Some(f) = p.string("filter") {
            match FilterFunction::parse(f) {
                Some(f) => options.filter = f,
                None => self.warn(
                    &p.get("filter").map_or(loc.clone(), |q| q.loc.clone()),
                    format!("imagemap filter \"{f}\" is unknown (point, bilinear, trilinear, ewa); bilinear is used"),
                ),
            }
        }
        let wrap = p.string("wrap").unwrap_or("repeat");
        options.wrap = WrapMode::parse(wrap).ok_or_else(|| {
            let message = format!("wrap mode \"{wrap}\" is unknown (repeat, black, clamp, octahedralsphere)");
            param_error(p, "wrap", loc, message)
        })?;
        let png = file.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let encoding = match p.string("encoding") {
            None => {
                if png {
                    ColorEncoding::Srgb
                } else {
                    ColorEncoding::Linear
                }
            }
            Some(e) => ColorEncoding::parse(e).ok_or_else(|| {
                param_error(p, "encoding", loc, format!("encoding \"{e}\" is unknown (linear, sRGB, \"gamma G\")"))
            })?,
        };
        let (scale, invert) = (p.float_or("scale", 1.0), p.bool_or("invert", false));
        let key = format!("{}|{encoding}|{options:?}", file.display());
        let pyramid = match self.textures.pyramids.get(&key) {
            Some(m) => m.clone(),
            None => {
                let img = self.image(p, loc)?;
                // prism's reader decodes integer formats with the sRGB curve and leaves float
                // formats (whose "encoding" pbrt-v4 also ignores) as stored.
                let integer = crate::image::FileFormat::from_path(&file).is_ok_and(|f| !f.is_linear());
                let texels = rgb_texels(&img, integer.then_some(encoding));
                let m = Arc::new(MipMap::build(img.width as usize, img.height as usize, texels, options));
                self.textures.pyramids.insert(key, m.clone());
                m
            }
        };
        Ok(ImageMap { mapping, pyramid, scale, invert })
    }
}

#[cfg(test)]
mod tests {
    use crate::material::Material;
    use crate::pbrt::{parse_file, parse_str, ParseOptions};
    use crate::spectrum::SampledWavelengths;
    use crate::texture::{inside_polka_dot, SpectrumTexture, TextureEvalContext};
    use glam::{Vec2, Vec3};

    /// The materials a scene builds and its warnings, or the error.
    fn build(text: &str) -> Result<(Vec<Material>, Vec<String>), String> {
        let (desc, mut w) = parse_str(text, &ParseOptions::default()).map_err(|e| e.to_string())?;
        let (b, _) = super::super::build(&desc, &mut w).map_err(|e| e.to_string())?;
        w.extend(desc.report_unused());
        let scene = b.build(crate::accel::AccelKind::Obvhs).map_err(|e| e.to_string())?;
        Ok((scene.materials().to_vec(), w.iter().map(|w| w.to_string()).collect()))
    }

    /// The diffuse reflectance of a scene's one textured quad.
    fn reflectance(textures: &str) -> SpectrumTexture {
        let text = format!(
            "Camera \"perspective\"\nWorldBegin\n{textures}\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\n\
             Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0] \"integer indices\" [0 1 2]\n"
        );
        let (m, w) = build(&text).unwrap();
        assert!(w.is_empty(), "{w:?}");
        match m.into_iter().next() {
            Some(Material::Diffuse { reflectance }) => reflectance,
            other => panic!("{other:?}"),
        }
    }

    fn grey(t: &SpectrumTexture, ctx: &TextureEvalContext) -> f32 {
        let w = SampledWavelengths::sample_uniform(0.3);
        t.eval(ctx, &w).average()
    }

    #[test]
    fn dots_paint_outside_in_the_dots_as_pbrt_v4_does() {
        let t = reflectance("Texture \"t\" \"spectrum\" \"dots\" \"rgb inside\" [0.2 0.2 0.2] \"rgb outside\" [0.8 0.8 0.8] \"float uscale\" [1] \"float vscale\" [1]");
        let (mut dots, mut background) = (0, 0);
        for i in 0..400 {
            let uv = Vec2::new((i % 20) as f32 * 0.31, (i / 20) as f32 * 0.27);
            let v = grey(&t, &TextureEvalContext::uv(uv));
            if inside_polka_dot(uv) {
                assert!((v - 0.8).abs() < 1e-4, "{v}");
                dots += 1;
            } else {
                assert!((v - 0.2).abs() < 1e-4, "{v}");
                background += 1;
            }
        }
        assert!(dots > 20 && background > 20);
    }

    #[test]
    fn textures_nest_and_are_read_in_full() {
        // mix(amount = scale(bilerp, 0.5)) of a constant and a checkerboard: every parameter is
        // read (no warnings), and the value follows from the parts.
        let t = reflectance(
            "Texture \"b\" \"float\" \"bilerp\" \"float v00\" [0] \"float v10\" [1] \"float v01\" [0] \"float v11\" [1]\n\
             Texture \"half\" \"float\" \"scale\" \"texture tex\" \"b\" \"float scale\" [0.5]\n\
             Texture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" [2] \"float vscale\" [2] \"rgb tex1\" [1 1 1] \"rgb tex2\" [0 0 0]\n\
             Texture \"t\" \"spectrum\" \"mix\" \"rgb tex1\" [0.5 0.5 0.5] \"texture tex2\" \"c\" \"texture amount\" \"half\"",
        );
        // At (u, v) = (0.8, 0.2): amount = 0.5 · 0.8 = 0.4; the check (1, 0) is odd: 0.
        let v = grey(&t, &TextureEvalContext::uv(Vec2::new(0.8, 0.2)));
        assert!((v - 0.6 * 0.5).abs() < 1e-4, "{v}");
        // At (0.2, 0.2): amount 0.1, even check: 1 → 0.9 · 0.5 + 0.1.
        let v = grey(&t, &TextureEvalContext::uv(Vec2::new(0.2, 0.2)));
        assert!((v - 0.55).abs() < 1e-4, "{v}");
    }

    #[test]
    fn texture_space_follows_the_transform_at_the_directive() {
        // A 3D checkerboard of unit cubes defined under Scale 0.5: cubes of 0.5 in world space.
        let t = reflectance(
            "AttributeBegin\nScale 0.5 0.5 0.5\nTexture \"t\" \"spectrum\" \"checkerboard\" \"integer dimension\" [3] \"rgb tex1\" [1 1 1] \"rgb tex2\" [0 0 0]\nAttributeEnd",
        );
        let at = |p: Vec3| grey(&t, &TextureEvalContext::at(p, Vec3::Z, Vec2::ZERO));
        assert!((at(Vec3::new(0.2, 0.2, 0.2)) - 1.0).abs() < 1e-4);
        assert!(at(Vec3::new(0.7, 0.2, 0.2)).abs() < 1e-4);
        assert!((at(Vec3::new(0.7, 0.7, 0.2)) - 1.0).abs() < 1e-4);
    }

    #[test]
    fn bad_textures_are_errors_and_unsupported_ones_warn() {
        let scene = |tex: &str| {
            format!(
                "Camera \"perspective\"\nWorldBegin\n{tex}\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\n\
                 Shape \"sphere\"\n"
            )
        };
        for bad in [
            // A float type as a spectrum texture.
            "Texture \"t\" \"spectrum\" \"fbm\"",
            // A reference to a texture defined later.
            "Texture \"t\" \"spectrum\" \"scale\" \"texture tex\" \"u\"\nTexture \"u\" \"spectrum\" \"constant\"",
            // A texture naming itself.
            "Texture \"t\" \"spectrum\" \"mix\" \"texture tex1\" \"t\"",
            "Texture \"t\" \"spectrum\" \"checkerboard\" \"integer dimension\" [4]",
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"x.png\" \"string wrap\" \"mirror\"",
            "Texture \"t\" \"spectrum\" \"directionmix\" \"vector3 dir\" [0 0 0]",
        ] {
            let e = build(&scene(bad)).unwrap_err();
            assert!(e.contains("<string>:"), "{bad}: {e}");
        }
        let (_, w) = build(&scene("Texture \"t\" \"spectrum\" \"ptex\" \"string filename\" \"x.ptx\"")).unwrap();
        assert!(w.len() == 1 && w[0].contains("ptex"), "{w:?}");
        let (_, w) = build(&scene("Texture \"t\" \"spectrum\" \"constant\" \"string mapping\" \"uv\"")).unwrap();
        assert!(w.len() == 1 && w[0].contains("mapping"), "constant has no mapping: {w:?}");
    }

    #[test]
    fn the_compatibility_scene_reads_every_texture_parameter() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compat/textures.pbrt");
        let (desc, mut w) = parse_file(&path, &ParseOptions::default()).unwrap();
        super::super::build(&desc, &mut w).unwrap();
        w.extend(desc.report_unused());
        let texture_warnings: Vec<_> = w.iter().map(|w| w.to_string()).filter(|w| w.contains("Texture")).collect();
        assert!(texture_warnings.is_empty(), "{texture_warnings:?}");
    }

    /// A scene whose material uses texture "t", preceded by `textures`.
    fn textured(textures: &str) -> String {
        format!(
            "Camera \"perspective\"\nWorldBegin\n{textures}Material \"diffuse\" \"texture reflectance\" \"t\"\n\
             Shape \"sphere\"\n"
        )
    }

    #[test]
    fn texture_chains_deeper_than_the_limit_are_located_errors() {
        let chain = |n: usize| {
            let mut s = String::from("Texture \"t0\" \"spectrum\" \"constant\"\n");
            for i in 1..n {
                s += &format!("Texture \"t{i}\" \"spectrum\" \"scale\" \"texture tex\" \"t{}\"\n", i - 1);
            }
            s + &format!("Texture \"t\" \"spectrum\" \"scale\" \"texture tex\" \"t{}\"\n", n - 1)
        };
        let ok = super::MAX_TEXTURE_DEPTH as usize - 1;
        build(&textured(&chain(ok))).unwrap();
        let e = build(&textured(&chain(10_000))).unwrap_err();
        let line = super::MAX_TEXTURE_DEPTH + 3;
        assert!(e.contains(&format!("<string>:{line}:")), "{e}");
        assert!(e.contains(&super::MAX_TEXTURE_DEPTH.to_string()) && e.contains("deep"), "{e}");
        // Float chains (a scale's factor) count the same.
        let mut s = String::from("Texture \"f0\" \"float\" \"constant\"\n");
        for i in 1..10_000 {
            s += &format!("Texture \"f{i}\" \"float\" \"scale\" \"texture tex\" \"f{}\"\n", i - 1);
        }
        s += "Texture \"t\" \"spectrum\" \"scale\" \"texture scale\" \"f9999\"\n";
        assert!(build(&textured(&s)).unwrap_err().contains("deep"));
    }

    #[test]
    fn texture_graphs_expanding_past_the_limit_are_located_errors() {
        // Each mix uses the previous texture twice: evaluating the last one would evaluate
        // the first 2^26 times.
        let doubling = |n: usize| {
            let mut s = String::from("Texture \"m0\" \"spectrum\" \"checkerboard\"\n");
            for i in 1..n {
                let p = i - 1;
                s += &format!(
                    "Texture \"m{i}\" \"spectrum\" \"mix\" \"texture tex1\" \"m{p}\" \"texture tex2\" \"m{p}\"\n"
                );
            }
            s + &format!("Texture \"t\" \"spectrum\" \"scale\" \"texture tex\" \"m{}\"\n", n - 1)
        };
        build(&textured(&doubling(12))).unwrap();
        // On another thread, bounded in time: without the limit the build never ends.
        let (tx, rx) = std::sync::mpsc::channel();
        let text = textured(&doubling(27));
        std::thread::spawn(move || tx.send(build(&text).map(drop)));
        let e = rx.recv_timeout(std::time::Duration::from_secs(60)).expect("the build never ended").unwrap_err();
        // m16 is the first whose expansion (2^17 − 1 textures) exceeds 2^16.
        assert!(e.contains("<string>:19:"), "{e}");
        assert!(e.contains(&super::MAX_TEXTURE_EXPANSION.to_string()), "{e}");
    }
}
