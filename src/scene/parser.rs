//! The directive parser: graphics state, transforms, includes, objects, materials, shapes.
//!
//! Semantics follow the pbrt-v4 file-format reference (pbrt.org/fileformat-v4) and
//! `BasicSceneBuilder` in pbrt-v4 (src/pbrt/scene.cpp): transforms post-multiply the current
//! transformation matrix (CTM); AttributeBegin/End push and pop the whole graphics state.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::desc::*;
use super::error::{Location, SceneError, Warning};
use super::names::{self, Lookup};
use super::params::{Param, ParamSet};
use super::shapes;
use super::source::Source;
use super::tokenizer::{Token, TokenKind};

/// Parser settings.
#[derive(Clone, Debug, Default)]
pub struct ParseOptions {
    /// Unsupported pbrt-v4 features (media, hair, measured BSDFs, ...) are errors, not warnings.
    pub strict: bool,
    /// Directory that relative paths in [`parse_str`] text resolve against (default: the
    /// current directory).
    pub base_dir: Option<PathBuf>,
}

/// Include/Import nesting deeper than this is an error (guards against runaway recursion that is
/// not a cycle, e.g. through symlinks).
pub const MAX_INCLUDE_DEPTH: usize = 64;

/// Parses the scene file at `path` (Include/Import resolve relative to the including file).
pub fn parse_file(path: &Path, opts: &ParseOptions) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
    let file: Arc<Path> = Arc::from(path);
    let loc = Location::new(file.clone(), 0, 0);
    let text = read_text(path, &loc)?;
    let mut p = Parser::new(opts);
    p.include_stack.push(canonical(path));
    p.parse_text(&text, file)?;
    p.finish()
}

/// Parses scene text; relative paths resolve against `opts.base_dir`.
pub fn parse_str(text: &str, opts: &ParseOptions) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
    let file: Arc<Path> = match &opts.base_dir {
        Some(d) => Arc::from(d.join("<string>")),
        None => Arc::from(Path::new("<string>")),
    };
    let mut p = Parser::new(opts);
    p.parse_text(text, file)?;
    p.finish()
}

fn canonical(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

fn read_text(path: &Path, loc: &Location) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|e| SceneError::Io {
        loc: loc.clone(),
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// Which transforms of a (start, end) motion pair directives affect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Active {
    Start,
    End,
    All,
}

/// The graphics state that AttributeBegin saves.
#[derive(Clone, Debug)]
struct GraphicsState {
    ctm: Mat4,
    active: Active,
    reverse_orientation: bool,
    material: MaterialRef,
    area_light: Option<AreaLightDesc>,
    color_space: String,
    /// `Attribute "shape" ...` etc.: defaults merged into later directives' parameters.
    defaults: HashMap<&'static str, ParamSet>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pushed {
    Attribute,
    Transform,
    Object,
}

struct Parser<'o> {
    opts: &'o ParseOptions,
    warnings: Vec<Warning>,
    gs: GraphicsState,
    stack: Vec<(GraphicsState, Pushed, Location)>,
    named_cs: HashMap<String, Mat4>,
    in_world: Option<Location>,
    camera: Option<CameraDesc>,
    film: Option<Directive>,
    sampler: Option<Directive>,
    integrator: Option<Directive>,
    filter: Option<Directive>,
    accelerator: Option<Directive>,
    color_space: String,
    options: ParamSet,
    shapes: Vec<ShapeDesc>,
    lights: Vec<LightDesc>,
    materials: Vec<MaterialDesc>,
    named_materials: Vec<NamedMaterial>,
    named_material_uses: Vec<(String, Location)>,
    textures: Vec<TextureDesc>,
    objects: Vec<ObjectDesc>,
    current_object: Option<ObjectDesc>,
    instances: Vec<(String, Mat4, Location)>,
    include_stack: Vec<PathBuf>,
    /// Entries of `stack` below this belong to an importing file: an imported file cannot pop them.
    stack_floor: usize,
    warned_motion: bool,
    last_loc: Option<Location>,
}

impl<'o> Parser<'o> {
    fn new(opts: &'o ParseOptions) -> Self {
        Self {
            opts,
            warnings: Vec::new(),
            gs: GraphicsState {
                ctm: Mat4::IDENTITY,
                active: Active::All,
                reverse_orientation: false,
                material: MaterialRef::Default,
                area_light: None,
                color_space: "srgb".into(),
                defaults: HashMap::new(),
            },
            stack: Vec::new(),
            named_cs: HashMap::new(),
            in_world: None,
            camera: None,
            film: None,
            sampler: None,
            integrator: None,
            filter: None,
            accelerator: None,
            color_space: "srgb".into(),
            options: ParamSet::new("srgb"),
            shapes: Vec::new(),
            lights: Vec::new(),
            materials: Vec::new(),
            named_materials: Vec::new(),
            named_material_uses: Vec::new(),
            textures: Vec::new(),
            objects: Vec::new(),
            current_object: None,
            instances: Vec::new(),
            include_stack: Vec::new(),
            stack_floor: 0,
            warned_motion: false,
            last_loc: None,
        }
    }

    fn warn(&mut self, loc: &Location, message: impl Into<String>) {
        self.warnings.push(Warning { loc: loc.clone(), message: message.into() });
    }

    /// A pbrt-v4 feature prism does not render: an error under `strict`, else a warning.
    fn unsupported(&mut self, loc: &Location, feature: &str, fallback: &str) -> Result<(), SceneError> {
        if self.opts.strict {
            return Err(SceneError::Unsupported {
                loc: loc.clone(),
                feature: feature.into(),
                fallback: fallback.into(),
            });
        }
        self.warn(loc, format!("unsupported feature: {feature}; prism {fallback}"));
        Ok(())
    }

    /// Checks a type name; `Some(type to use)` or `None` to skip the directive.
    fn resolve_type(
        &mut self,
        tok: &Token,
        kind: &'static str,
        supported: &[&str],
        pbrt_only: &[(&'static str, &'static str)],
        skip: bool,
    ) -> Result<Option<String>, SceneError> {
        match names::lookup(&tok.text, supported, pbrt_only) {
            Lookup::Supported => Ok(Some(tok.text.clone())),
            Lookup::Substitute(s) => {
                let feature = format!("{kind} \"{}\"", tok.text);
                if skip {
                    self.unsupported(&tok.loc, &feature, s)?;
                    Ok(None)
                } else {
                    self.unsupported(&tok.loc, &feature, &format!("uses \"{s}\" instead"))?;
                    Ok(Some(s.to_string()))
                }
            }
            Lookup::Unknown => Err(SceneError::UnknownType {
                loc: tok.loc.clone(),
                kind,
                name: tok.text.clone(),
                valid: names::valid_list(supported, pbrt_only),
            }),
        }
    }

    fn require_world(&self, tok: &Token) -> Result<(), SceneError> {
        if self.in_world.is_none() {
            return Err(SceneError::syntax(
                &tok.loc,
                &tok.text,
                format!("{} is not allowed before WorldBegin", tok.text),
            ));
        }
        Ok(())
    }

    fn require_options(&self, tok: &Token) -> Result<(), SceneError> {
        if self.in_world.is_some() {
            return Err(SceneError::syntax(
                &tok.loc,
                &tok.text,
                format!("{} is not allowed after WorldBegin", tok.text),
            ));
        }
        Ok(())
    }

    fn parse_text(&mut self, text: &str, file: Arc<Path>) -> Result<(), SceneError> {
        // Editors on Windows may prepend a UTF-8 byte-order mark.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut src = Source::new(text, file);
        while let Some(tok) = src.next()? {
            if tok.kind != TokenKind::Word {
                return Err(SceneError::syntax(&tok.loc, &tok.display(), "expected a directive"));
            }
            self.last_loc = Some(tok.loc.clone());
            self.directive(&tok, &mut src)?;
        }
        Ok(())
    }

    /// Applies `m` to the CTM (post-multiplied, as pbrt-v4 does) if the active transform allows.
    fn concat(&mut self, tok: &Token, m: Mat4) {
        self.set_ctm(tok, self.gs.ctm * m);
    }

    fn set_ctm(&mut self, tok: &Token, m: Mat4) {
        if self.gs.active == Active::End {
            if !self.warned_motion {
                self.warned_motion = true;
                self.warn(
                    &tok.loc,
                    "unsupported feature: motion blur (ActiveTransform EndTime); prism uses the start transform",
                );
            }
            return;
        }
        self.gs.ctm = m;
    }

    fn directive(&mut self, tok: &Token, src: &mut Source) -> Result<(), SceneError> {
        let cs = self.gs.color_space.clone();
        match tok.text.as_str() {
            "Identity" => self.set_ctm(tok, Mat4::IDENTITY),
            "Translate" => {
                let v = src.numbers(tok, 3)?;
                self.concat(tok, Mat4::from_translation(Vec3::new(v[0], v[1], v[2])));
            }
            "Scale" => {
                let v = src.numbers(tok, 3)?;
                self.concat(tok, Mat4::from_scale(Vec3::new(v[0], v[1], v[2])));
            }
            "Rotate" => {
                let v = src.numbers(tok, 4)?;
                let axis = Vec3::new(v[1], v[2], v[3]);
                if axis.length_squared() == 0.0 || !axis.length_squared().is_finite() {
                    return Err(SceneError::syntax(&tok.loc, &tok.text, "rotation axis has zero length"));
                }
                self.concat(tok, Mat4::from_axis_angle(axis.normalize(), v[0].to_radians()));
            }
            "LookAt" => {
                let v = src.numbers(tok, 9)?;
                let m = look_at(Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), Vec3::new(v[6], v[7], v[8]))
                    .ok_or_else(|| {
                        SceneError::syntax(
                            &tok.loc,
                            &tok.text,
                            "LookAt is degenerate: eye equals look, or up is parallel to the view direction",
                        )
                    })?;
                self.concat(tok, m);
            }
            "Transform" | "ConcatTransform" => {
                let v = src.numbers(tok, 16)?;
                let mut a = [0.0f32; 16];
                a.copy_from_slice(&v);
                // pbrt lists the matrix column by column (translation in elements 12–14),
                // which is glam's column-major order.
                let m = Mat4::from_cols_array(&a);
                if tok.text == "Transform" {
                    self.set_ctm(tok, m);
                } else {
                    self.concat(tok, m);
                }
            }
            "CoordinateSystem" => {
                let name = src.string(tok, "a coordinate system name")?;
                self.named_cs.insert(name.text, self.gs.ctm);
            }
            "CoordSysTransform" => {
                let name = src.string(tok, "a coordinate system name")?;
                match self.named_cs.get(&name.text) {
                    Some(&m) => self.set_ctm(tok, m),
                    None => self.warn(
                        &name.loc,
                        format!("unknown coordinate system \"{}\"; CoordSysTransform ignored", name.text),
                    ),
                }
            }
            "ActiveTransform" => {
                let t = src.expect(tok, "StartTime, EndTime or All")?;
                self.gs.active = match t.text.as_str() {
                    "StartTime" => Active::Start,
                    "EndTime" => Active::End,
                    "All" => Active::All,
                    _ => {
                        return Err(SceneError::syntax(
                            &t.loc,
                            &t.display(),
                            "ActiveTransform expects StartTime, EndTime or All",
                        ))
                    }
                };
            }
            "TransformTimes" => {
                let v = src.numbers(tok, 2)?;
                if v[1] < v[0] {
                    return Err(SceneError::syntax(&tok.loc, &tok.text, "TransformTimes end is before start"));
                }
            }
            "ReverseOrientation" => self.gs.reverse_orientation = !self.gs.reverse_orientation,
            "AttributeBegin" | "TransformBegin" => {
                self.require_world(tok)?;
                let kind = if tok.text == "AttributeBegin" { Pushed::Attribute } else { Pushed::Transform };
                if kind == Pushed::Transform {
                    self.warn(&tok.loc, "TransformBegin is deprecated in pbrt-v4; use AttributeBegin");
                }
                self.stack.push((self.gs.clone(), kind, tok.loc.clone()));
            }
            "AttributeEnd" | "TransformEnd" => {
                self.require_world(tok)?;
                let want = if tok.text == "AttributeEnd" { Pushed::Attribute } else { Pushed::Transform };
                self.pop(tok, want)?;
            }
            "Attribute" => {
                self.require_world(tok)?;
                let target = src.string(tok, "a target (shape, light, material, medium, texture)")?;
                let key: &'static str = match target.text.as_str() {
                    "shape" => "shape",
                    "light" => "light",
                    "material" => "material",
                    "medium" => "medium",
                    "texture" => "texture",
                    _ => {
                        return Err(SceneError::syntax(
                            &target.loc,
                            &target.display(),
                            "Attribute target must be one of shape, light, material, medium, texture",
                        ))
                    }
                };
                let ps = src.params(&cs)?;
                let entry = self.gs.defaults.entry(key).or_insert_with(|| ParamSet::new(&cs));
                // Later Attribute values override earlier ones.
                let mut merged = ps;
                merged.merge_defaults(entry);
                *entry = merged;
            }
            "Option" => {
                let ps = src.params(&cs)?;
                let mut merged = ps;
                merged.merge_defaults(&self.options);
                self.options = merged;
            }
            "ColorSpace" => {
                let name = src.string(tok, "a colour space name")?;
                if !names::COLOR_SPACES.contains(&name.text.as_str()) {
                    return Err(SceneError::UnknownType {
                        loc: name.loc,
                        kind: "color space",
                        name: name.text,
                        valid: names::COLOR_SPACES.join(", "),
                    });
                }
                self.gs.color_space = name.text.clone();
                if self.in_world.is_none() {
                    self.color_space = name.text;
                }
            }
            "Camera" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "a camera type")?;
                let params = src.params(&cs)?;
                let kind = self.resolve_type(&ty, "camera", names::PRISM_CAMERAS, names::PBRT_ONLY_CAMERAS, false)?;
                let ctm = self.gs.ctm;
                let det = ctm.determinant();
                if det == 0.0 || !det.is_finite() {
                    return Err(SceneError::syntax(&tok.loc, &tok.text, "the camera transform is not invertible"));
                }
                self.named_cs.insert("camera".into(), ctm.inverse());
                self.camera = Some(CameraDesc {
                    directive: Directive { kind: kind.unwrap_or_default(), params, loc: tok.loc.clone() },
                    camera_from_world: ctm,
                });
            }
            "Film" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "a film type")?;
                let params = src.params(&cs)?;
                let kind = self.resolve_type(&ty, "film", names::PRISM_FILMS, names::PBRT_ONLY_FILMS, false)?;
                self.film = Some(Directive { kind: kind.unwrap_or_default(), params, loc: tok.loc.clone() });
            }
            "Integrator" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "an integrator type")?;
                let params = src.params(&cs)?;
                let kind = self.resolve_type(
                    &ty,
                    "integrator",
                    names::PRISM_INTEGRATORS,
                    names::PBRT_ONLY_INTEGRATORS,
                    false,
                )?;
                self.integrator = Some(Directive { kind: kind.unwrap_or_default(), params, loc: tok.loc.clone() });
            }
            "Sampler" | "PixelFilter" | "Accelerator" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "a type name")?;
                let params = src.params(&cs)?;
                let (kind, valid): (&'static str, &[&str]) = match tok.text.as_str() {
                    "Sampler" => ("sampler", names::SAMPLERS),
                    "PixelFilter" => ("filter", names::FILTERS),
                    _ => ("accelerator", &["bvh", "kdtree"]),
                };
                if !valid.contains(&ty.text.as_str()) {
                    return Err(SceneError::UnknownType { loc: ty.loc, kind, name: ty.text, valid: valid.join(", ") });
                }
                let d = Directive { kind: ty.text, params, loc: tok.loc.clone() };
                match kind {
                    "sampler" => self.sampler = Some(d),
                    "filter" => self.filter = Some(d),
                    _ => self.accelerator = Some(d),
                }
            }
            "MakeNamedMedium" => {
                let name = src.string(tok, "a medium name")?;
                let _ = src.params(&cs)?;
                self.unsupported(&tok.loc, &format!("participating medium \"{}\"", name.text), "ignores the medium")?;
            }
            "MediumInterface" => {
                let inside = src.string(tok, "a medium name")?;
                // The outside name is optional (one name means both sides).
                let outside = match src.peek()? {
                    Some(t) if t.kind == TokenKind::Str && !t.text.contains(' ') => src.next()?.map(|t| t.text),
                    _ => None,
                };
                // `MediumInterface "" ""` (vacuum on both sides) is what prism renders anyway.
                if !inside.text.is_empty() || outside.is_some_and(|o| !o.is_empty()) {
                    self.unsupported(&tok.loc, "MediumInterface (inside/outside media)", "ignores the media names")?;
                }
            }
            "WorldBegin" => {
                self.require_options(tok)?;
                self.in_world = Some(tok.loc.clone());
                self.gs.ctm = Mat4::IDENTITY;
                self.named_cs.insert("world".into(), Mat4::IDENTITY);
            }
            "WorldEnd" => {
                self.require_world(tok)?;
                self.warn(&tok.loc, "WorldEnd is a pbrt-v3 directive; ignored");
            }
            "Include" | "Import" => {
                let name = src.string(tok, "a file name")?;
                if tok.text == "Import" {
                    self.require_world(tok)?;
                }
                self.include(tok, &name)?;
            }
            "ObjectBegin" => {
                self.require_world(tok)?;
                let name = src.string(tok, "an object name")?;
                if let Some(o) = &self.current_object {
                    return Err(SceneError::syntax(
                        &tok.loc,
                        &tok.text,
                        format!("ObjectBegin inside the definition of object \"{}\" ({})", o.name, o.loc),
                    ));
                }
                if let Some(o) = self.objects.iter().find(|o| o.name == name.text) {
                    return Err(SceneError::syntax(
                        &name.loc,
                        &name.display(),
                        format!("object \"{}\" redefined (first defined at {})", o.name, o.loc),
                    ));
                }
                self.stack.push((self.gs.clone(), Pushed::Object, tok.loc.clone()));
                self.current_object = Some(ObjectDesc { name: name.text, shapes: Vec::new(), loc: tok.loc.clone() });
            }
            "ObjectEnd" => {
                self.require_world(tok)?;
                self.pop(tok, Pushed::Object)?;
            }
            "ObjectInstance" => {
                self.require_world(tok)?;
                let name = src.string(tok, "an object name")?;
                if let Some(o) = &self.current_object {
                    return Err(SceneError::syntax(
                        &tok.loc,
                        &tok.text,
                        format!("ObjectInstance inside the definition of object \"{}\"", o.name),
                    ));
                }
                self.instances.push((name.text, self.gs.ctm, tok.loc.clone()));
            }
            "Material" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "a material type")?;
                let params = src.params(&cs)?;
                let m = self.material(&ty, params)?;
                self.materials.push(m);
                self.gs.material = MaterialRef::Anonymous(self.materials.len() - 1);
            }
            "MakeNamedMaterial" => {
                self.require_world(tok)?;
                let name = src.string(tok, "a material name")?;
                let params = src.params(&cs)?;
                if let Some(m) = self.named_materials.iter().find(|m| m.name == name.text) {
                    return Err(SceneError::syntax(
                        &name.loc,
                        &name.display(),
                        format!("named material \"{}\" redefined (first defined at {})", m.name, m.material.loc),
                    ));
                }
                let ty = match params.get("type") {
                    Some(Param { value: super::params::ParamValue::String(s), loc, .. }) if s.len() == 1 => {
                        Token { kind: TokenKind::Str, text: s[0].clone(), loc: loc.clone() }
                    }
                    _ => {
                        return Err(SceneError::syntax(
                            &name.loc,
                            &name.display(),
                            format!("MakeNamedMaterial \"{}\" needs a \"string type\" parameter", name.text),
                        ))
                    }
                };
                let mut m = self.material(&ty, params)?;
                m.loc = tok.loc.clone();
                self.named_materials.push(NamedMaterial { name: name.text, material: m });
            }
            "NamedMaterial" => {
                self.require_world(tok)?;
                let name = src.string(tok, "a material name")?;
                self.named_material_uses.push((name.text.clone(), name.loc.clone()));
                self.gs.material = MaterialRef::Named(name.text);
            }
            "Texture" => {
                self.require_world(tok)?;
                let name = src.string(tok, "a texture name")?;
                let class = src.string(tok, "a texture class (\"float\" or \"spectrum\")")?;
                let ty = src.string(tok, "a texture type")?;
                let mut params = src.params(&cs)?;
                let class = match class.text.as_str() {
                    "float" => TextureClass::Float,
                    "spectrum" | "color" => TextureClass::Spectrum,
                    _ => {
                        return Err(SceneError::syntax(
                            &class.loc,
                            &class.display(),
                            "texture class must be \"float\" or \"spectrum\"",
                        ))
                    }
                };
                if !names::TEXTURES.contains(&ty.text.as_str()) {
                    return Err(SceneError::UnknownType {
                        loc: ty.loc,
                        kind: "texture",
                        name: ty.text,
                        valid: names::TEXTURES.join(", "),
                    });
                }
                if let Some(d) = self.gs.defaults.get("texture") {
                    params.merge_defaults(d);
                }
                if self.textures.iter().any(|t| t.name == name.text && t.class == class) {
                    self.warn(&name.loc, format!("texture \"{}\" redefined; the later definition is used", name.text));
                }
                self.textures.push(TextureDesc {
                    name: name.text,
                    class,
                    kind: ty.text,
                    params,
                    world_from_texture: self.gs.ctm,
                    loc: tok.loc.clone(),
                });
            }
            "LightSource" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "a light type")?;
                let mut params = src.params(&cs)?;
                if let Some(kind) =
                    self.resolve_type(&ty, "light", names::PRISM_LIGHTS, names::PBRT_ONLY_LIGHTS, true)?
                {
                    if let Some(d) = self.gs.defaults.get("light") {
                        params.merge_defaults(d);
                    }
                    if self.current_object.is_some() {
                        self.warn(&tok.loc, "LightSource inside ObjectBegin is not instanced; it is added once");
                    }
                    self.lights.push(LightDesc { kind, params, world_from_light: self.gs.ctm, loc: tok.loc.clone() });
                }
            }
            "AreaLightSource" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "an area light type")?;
                let mut params = src.params(&cs)?;
                if let Some(kind) = self.resolve_type(&ty, "area light", names::PRISM_AREA_LIGHTS, &[], true)? {
                    if let Some(d) = self.gs.defaults.get("light") {
                        params.merge_defaults(d);
                    }
                    self.gs.area_light = Some(AreaLightDesc { kind, params, loc: tok.loc.clone() });
                }
            }
            "Shape" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "a shape type")?;
                let params = src.params(&cs)?;
                self.shape(tok, &ty, params)?;
            }
            _ => {
                return Err(SceneError::syntax(&tok.loc, &tok.text, format!("unknown directive \"{}\"", tok.text)));
            }
        }
        Ok(())
    }

    fn pop(&mut self, tok: &Token, want: Pushed) -> Result<(), SceneError> {
        let begin = match want {
            Pushed::Attribute => "AttributeBegin",
            Pushed::Transform => "TransformBegin",
            Pushed::Object => "ObjectBegin",
        };
        match self.stack.last().filter(|_| self.stack.len() > self.stack_floor) {
            None => Err(SceneError::syntax(&tok.loc, &tok.text, format!("{} without a matching {begin}", tok.text))),
            Some((_, got, loc)) if *got != want => Err(SceneError::syntax(
                &tok.loc,
                &tok.text,
                format!("{} does not match the open {:?}Begin at {loc}", tok.text, got),
            )),
            Some(_) => {
                let (gs, _, _) = self.stack.pop().expect("checked non-empty");
                if want == Pushed::Transform {
                    self.gs.ctm = gs.ctm;
                } else {
                    self.gs = gs;
                }
                if want == Pushed::Object {
                    let o = self.current_object.take().expect("ObjectBegin pushed an object");
                    self.objects.push(o);
                }
                Ok(())
            }
        }
    }

    fn material(&mut self, ty: &Token, mut params: ParamSet) -> Result<MaterialDesc, SceneError> {
        let kind = self
            .resolve_type(ty, "material", names::PRISM_MATERIALS, names::PBRT_ONLY_MATERIALS, false)?
            .unwrap_or_default();
        if kind != ty.text {
            // The replacement's parameters mean something else: start from its defaults.
            let mut fresh = ParamSet::new(&params.color_space);
            if ty.text == "interface" {
                let decl = Token { kind: TokenKind::Str, text: "float eta".into(), loc: ty.loc.clone() };
                let one = Token { kind: TokenKind::Word, text: "1".into(), loc: ty.loc.clone() };
                fresh.push(Param::parse(&decl, &[one])?)?;
            }
            params = fresh;
        } else if let Some(d) = self.gs.defaults.get("material") {
            params.merge_defaults(d);
        }
        Ok(MaterialDesc { kind, params, loc: ty.loc.clone() })
    }

    fn shape(&mut self, tok: &Token, ty: &Token, mut params: ParamSet) -> Result<(), SceneError> {
        let Some(kind) = self.resolve_type(ty, "shape", names::PRISM_SHAPES, names::PBRT_ONLY_SHAPES, true)? else {
            return Ok(());
        };
        if let Some(d) = self.gs.defaults.get("shape") {
            params.merge_defaults(d);
        }
        let geometry = shapes::load(&kind, &params, &tok.loc, &mut self.warnings)?;
        let mut area_light = self.gs.area_light.clone();
        if self.current_object.is_some() && area_light.is_some() {
            self.unsupported(&tok.loc, "area light on a shape inside ObjectBegin", "makes the shape non-emissive")?;
            area_light = None;
        }
        let s = ShapeDesc {
            kind,
            params,
            geometry,
            world_from_object: self.gs.ctm,
            reverse_orientation: self.gs.reverse_orientation,
            material: self.gs.material.clone(),
            area_light,
            loc: tok.loc.clone(),
        };
        match &mut self.current_object {
            Some(o) => o.shapes.push(s),
            None => self.shapes.push(s),
        }
        Ok(())
    }

    fn include(&mut self, tok: &Token, name: &Token) -> Result<(), SceneError> {
        let path = name.loc.base_dir().join(&name.text);
        let canon = canonical(&path);
        if let Some(i) = self.include_stack.iter().position(|p| *p == canon) {
            let mut chain: Vec<String> = self.include_stack[i..].iter().map(|p| p.display().to_string()).collect();
            chain.push(canon.display().to_string());
            return Err(SceneError::IncludeCycle { loc: tok.loc.clone(), chain: chain.join(" -> ") });
        }
        if self.include_stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(SceneError::syntax(
                &tok.loc,
                &name.display(),
                format!("includes nested deeper than {MAX_INCLUDE_DEPTH} files"),
            ));
        }
        let text = read_text(&path, &name.loc)?;
        self.include_stack.push(canon);
        // pbrt-v4 parses an Import'ed file with its own copy of the graphics state (it may run
        // in parallel): its transforms, materials, area lights and coordinate-system names do not
        // leak back, and it cannot close blocks the importer opened. Named materials, textures,
        // objects, shapes and lights it defines belong to the scene.
        let saved = (tok.text == "Import").then(|| (self.gs.clone(), self.named_cs.clone(), self.stack_floor));
        if saved.is_some() {
            self.stack_floor = self.stack.len();
        }
        self.parse_text(&text, Arc::from(path.as_path()))?;
        if let Some((gs, named_cs, floor)) = saved {
            if self.stack.len() != self.stack_floor {
                let (_, kind, loc) = self.stack.last().expect("deeper than the floor");
                return Err(SceneError::syntax(
                    &tok.loc,
                    &name.display(),
                    format!("the imported file leaves the {kind:?}Begin at {loc} open; an imported file must close every block it opens"),
                ));
            }
            self.gs = gs;
            self.named_cs = named_cs;
            self.stack_floor = floor;
        }
        self.include_stack.pop();
        Ok(())
    }

    fn finish(mut self) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
        let end = self.last_loc.clone().unwrap_or_else(|| Location::new(Arc::from(Path::new("<empty>")), 1, 1));
        while let Some((_, kind, loc)) = self.stack.pop() {
            if kind == Pushed::Object {
                let o = self.current_object.take().expect("ObjectBegin pushed an object");
                self.objects.push(o);
                self.warn(&loc, "ObjectBegin without ObjectEnd; closed at end of file");
            } else {
                self.warn(&loc, format!("{kind:?}Begin without a matching End"));
            }
        }
        for (name, loc) in &self.named_material_uses {
            if !self.named_materials.iter().any(|m| &m.name == name) {
                return Err(SceneError::syntax(loc, name, format!("named material \"{name}\" is not defined")));
            }
        }
        let mut instances = Vec::with_capacity(self.instances.len());
        for (object, m, loc) in self.instances.drain(..) {
            let Some(object_index) = self.objects.iter().position(|o| o.name == object) else {
                return Err(SceneError::syntax(&loc, &object, format!("object \"{object}\" is not defined")));
            };
            instances.push(InstanceDesc { object, object_index, world_from_instance: m, loc });
        }
        let textures = &self.textures;
        let check_textures = |ps: &ParamSet| -> Result<(), SceneError> {
            for p in ps.iter() {
                if let super::params::ParamValue::Texture(t) = &p.value {
                    if !textures.iter().any(|x| &x.name == t) {
                        return Err(SceneError::syntax(&p.loc, t, format!("texture \"{t}\" is not defined")));
                    }
                }
            }
            Ok(())
        };
        for m in self.materials.iter().chain(self.named_materials.iter().map(|n| &n.material)) {
            check_textures(&m.params)?;
        }
        for t in &self.textures {
            check_textures(&t.params)?;
        }
        let default_loc = self.in_world.clone().unwrap_or_else(|| end.clone());
        let cs = self.color_space.clone();
        let dflt = |kind: &str| Directive { kind: kind.into(), params: ParamSet::new(&cs), loc: default_loc.clone() };
        let desc = SceneDesc {
            camera: self
                .camera
                .unwrap_or_else(|| CameraDesc { directive: dflt("perspective"), camera_from_world: Mat4::IDENTITY }),
            film: self.film.unwrap_or_else(|| dflt("rgb")),
            sampler: self.sampler.unwrap_or_else(|| dflt("zsobol")),
            integrator: self.integrator.unwrap_or_else(|| dflt("path")),
            filter: self.filter.unwrap_or_else(|| dflt("gaussian")),
            accelerator: self.accelerator,
            color_space: self.color_space,
            options: self.options,
            shapes: self.shapes,
            lights: self.lights,
            materials: self.materials,
            named_materials: self.named_materials,
            textures: self.textures,
            objects: self.objects,
            instances,
        };
        Ok((desc, self.warnings))
    }
}

/// pbrt's LookAt: camera space from world space for a camera at `eye` looking at `look`, with
/// camera +x = up × dir, +y = the projected up vector, +z = the viewing direction (left-handed,
/// as in pbrt-v4 `LookAt`, src/pbrt/util/transform.cpp). `None` when degenerate.
pub fn look_at(eye: Vec3, look: Vec3, up: Vec3) -> Option<Mat4> {
    let dir = (look - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera =
        Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), Vec4::from((eye, 1.0)));
    Some(world_from_camera.inverse())
}
