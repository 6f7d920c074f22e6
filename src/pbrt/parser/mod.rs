//! The directive parser: the graphics state, Include/Import and the checks at the end of the
//! file; the directives themselves are in `transforms`, `options` (the options block) and
//! `world` (the world block).
//!
//! Semantics follow the pbrt-v4 file-format reference (pbrt.org/fileformat-v4) and
//! `BasicSceneBuilder` in pbrt-v4 (src/pbrt/scene.cpp): transforms post-multiply the current
//! transformation matrix (CTM); AttributeBegin/End push and pop the whole graphics state.

use rustc_hash::FxHashMap as HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod mesh_files;
mod options;
mod transforms;
mod world;

pub use transforms::look_at;

use glam::Mat4;

use crate::geometry::AnimatedTransform;

use super::desc::*;
use super::error::{check_strict, Location, SceneError, Warning};
use super::names::{self, Lookup};
use super::params::{ParamSet, ParamValue};
use super::source::Source;
use super::tokenizer::{SourceFile, SourceFiles, Token, TokenKind};

/// Parser settings.
#[derive(Clone, Debug, Default)]
pub struct ParseOptions {
    /// Unsupported pbrt-v4 features (media, hair, measured BSDFs, ...) are
    /// errors, not warnings: [`parse_file`] and [`parse_str`] fail with the first.
    pub strict: bool,
    /// Directory that relative paths in [`parse_str`] text resolve against (default: the
    /// current directory).
    pub base_dir: Option<PathBuf>,
    /// How quadrics are built ([`crate::pbrt::build_with`]).
    pub quadrics: super::QuadricMode,
}

/// Include/Import nesting deeper than this is an error (guards against runaway recursion that is
/// not a cycle, e.g. through symlinks).
pub const MAX_INCLUDE_DEPTH: usize = 64;

/// Most Include/Import directives one parse follows, a file counting each time it is read
/// (files that include one another more than once fan out exponentially); the environment
/// variable `PRISM_MAX_INCLUDES` raises it.
pub const MAX_INCLUDES: usize = 10_000;

/// Most bytes of scene text one parse reads over all its files, a file counting each time it is
/// read; the environment variable `PRISM_MAX_SCENE_BYTES` raises it.
pub const MAX_SCENE_TEXT_BYTES: u64 = 64 << 30;

/// A limit: the environment variable `var` when it holds a number, else `default`.
fn limit(var: &str, default: u64) -> u64 {
    std::env::var(var).ok().and_then(|v| v.trim().parse().ok()).unwrap_or(default)
}

/// Parses the scene file at `path`. Relative file names (Include, Import, meshes, images,
/// spectra...) resolve against `path`'s directory, as in pbrt-v4 ([`Location::resolve`]).
pub fn parse_file(path: &Path, opts: &ParseOptions) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
    let file: Arc<Path> = Arc::from(path);
    let loc = Location::new(file.clone(), 0, 0);
    let text = read_text(path, &loc)?;
    let mut p = Parser::new(opts);
    p.search_dir = Some(Arc::from(path.parent().unwrap_or(Path::new(""))));
    p.files_read.push(path.to_path_buf());
    if let Err(e) = p.parse_text(&SourceFiles::default(), text, file, canonical(path)) {
        return Err(p.first_error(e));
    }
    p.finish()
}

/// Parses scene text; relative paths resolve against `opts.base_dir`.
pub fn parse_str(text: &str, opts: &ParseOptions) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
    let file: Arc<Path> = match &opts.base_dir {
        Some(d) => Arc::from(d.join("<string>")),
        None => Arc::from(Path::new("<string>")),
    };
    let mut p = Parser::new(opts);
    p.search_dir = opts.base_dir.as_deref().map(Arc::from);
    if let Err(e) = p.parse_text(&SourceFiles::default(), text.to_string(), file.clone(), file.to_path_buf()) {
        return Err(p.first_error(e));
    }
    p.finish()
}

fn canonical(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

fn read_text(path: &Path, loc: &Location) -> Result<String, SceneError> {
    crate::pbrt::input::read_text(path).map_err(|e| SceneError::Io {
        loc: loc.clone(),
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// The index a `MaterialRef::Named` holds while its definition is still to come: the end of
/// the file sets it.
const DEFINED_LATER: usize = usize::MAX;

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
    /// The CTM at the start time of `TransformTimes`.
    ctm: Mat4,
    /// The CTM at its end time (equal to `ctm` unless the scene animates transforms).
    ctm_end: Mat4,
    active: Active,
    reverse_orientation: bool,
    material: MaterialRef,
    area_light: Option<AreaLightDesc>,
    color_space: &'static str,
    /// `Attribute "shape" ...` etc.: defaults merged into later directives' parameters.
    defaults: HashMap<&'static str, ParamSet>,
    /// The current MediumInterface.
    media: MediumNames,
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
    /// Named coordinate systems: their (start, end) CTMs.
    named_cs: HashMap<String, [Mat4; 2]>,
    /// `TransformTimes`: the times of the start and end CTMs (pbrt-v4's default 0 1).
    transform_times: (f32, f32),
    in_world: Option<Location>,
    camera: Option<CameraDesc>,
    film: Option<Directive>,
    sampler: Option<Directive>,
    integrator: Option<Directive>,
    filter: Option<Directive>,
    accelerator: Option<Directive>,
    color_space: &'static str,
    options: ParamSet,
    shapes: Vec<ShapeDesc>,
    lights: Vec<LightDesc>,
    materials: Vec<MaterialDesc>,
    named_materials: Vec<NamedMaterial>,
    /// Index into `named_materials` by name.
    named_material_index: HashMap<Arc<str>, usize>,
    /// NamedMaterial directives that named a material not defined before them.
    named_material_uses: Vec<(Arc<str>, Location)>,
    textures: Vec<TextureDesc>,
    /// The texture names defined so far, each with its id ([`TextureDesc::name_id`]) and whether
    /// a float texture and whether a spectrum texture of that name is: one shared text per
    /// name, whatever its class.
    texture_names: HashMap<Arc<str>, (u32, [bool; 2])>,
    /// A "texture" parameter named a texture not defined before it: whether the materials'
    /// and textures' names are defined is checked when the file ends.
    texture_named_ahead: bool,
    objects: Vec<ObjectDesc>,
    /// Index into `objects` by name.
    object_index: HashMap<String, usize>,
    current_object: Option<ObjectDesc>,
    instances: Vec<(String, Mat4, Option<AnimatedTransform>, Location)>,
    /// Every MakeNamedMedium in order, redefined ones included.
    media: Vec<MediumDesc>,
    /// Index into `media` of each name's latest definition (the one that counts).
    medium_index: HashMap<String, usize>,
    /// Canonical paths of the files whose reading an Import interrupted, outermost first.
    include_stack: Vec<PathBuf>,
    /// The directory relative file names resolve against: the main scene file's.
    search_dir: Option<Arc<Path>>,
    /// Every file read so far: the scene file, then each Include/Import in reading order.
    files_read: Vec<PathBuf>,
    /// Bytes of text read by Include/Import so far, repetitions included.
    text_bytes: u64,
    /// Entries of `stack` below this belong to an importing file: an imported file cannot pop them.
    stack_floor: usize,
    warned_motion: bool,
    last_loc: Option<Location>,
    /// Mesh files named so far, read when the parse ends ([`mesh_files`]).
    pending_meshes: Vec<mesh_files::PendingMesh>,
}

impl<'o> Parser<'o> {
    fn new(opts: &'o ParseOptions) -> Self {
        Self {
            opts,
            warnings: Vec::new(),
            gs: GraphicsState {
                ctm: Mat4::IDENTITY,
                ctm_end: Mat4::IDENTITY,
                active: Active::All,
                reverse_orientation: false,
                material: MaterialRef::Default,
                area_light: None,
                color_space: "srgb",
                defaults: HashMap::default(),
                media: MediumNames::default(),
            },
            stack: Vec::new(),
            named_cs: HashMap::default(),
            transform_times: (0.0, 1.0),
            in_world: None,
            camera: None,
            film: None,
            sampler: None,
            integrator: None,
            filter: None,
            accelerator: None,
            color_space: "srgb",
            options: ParamSet::new("srgb"),
            shapes: Vec::new(),
            lights: Vec::new(),
            materials: Vec::new(),
            named_materials: Vec::new(),
            named_material_index: HashMap::default(),
            named_material_uses: Vec::new(),
            textures: Vec::new(),
            texture_names: HashMap::default(),
            texture_named_ahead: false,
            objects: Vec::new(),
            object_index: HashMap::default(),
            current_object: None,
            instances: Vec::new(),
            media: Vec::new(),
            medium_index: HashMap::default(),
            include_stack: Vec::new(),
            search_dir: None,
            files_read: Vec::new(),
            text_bytes: 0,
            stack_floor: 0,
            warned_motion: false,
            pending_meshes: Vec::new(),
            last_loc: None,
        }
    }

    fn warn(&mut self, loc: &Location, message: impl Into<String>) {
        self.warnings.push(Warning::note(loc, message));
    }

    /// A pbrt-v4 feature prism does not render (an error in strict mode, when parsing ends).
    fn unsupported(&mut self, loc: &Location, feature: &str, fallback: &str) {
        self.warnings.push(Warning::unsupported(loc, feature, fallback));
    }

    /// Checks a type name; `Some(type to use)` or `None` to skip the directive.
    fn resolve_type(
        &mut self,
        name: &str,
        loc: impl FnOnce() -> Location,
        kind: &'static str,
        supported: &[&'static str],
        pbrt_only: &[(&'static str, &'static str)],
        skip: bool,
    ) -> Result<Option<&'static str>, SceneError> {
        match names::lookup(name, supported, pbrt_only) {
            Lookup::Supported(s) => Ok(Some(s)),
            Lookup::Substitute(s) => {
                let feature = format!("{kind} \"{name}\"");
                if skip {
                    self.unsupported(&loc(), &feature, s);
                    Ok(None)
                } else {
                    self.unsupported(&loc(), &feature, &format!("uses \"{s}\" instead"));
                    Ok(Some(s))
                }
            }
            Lookup::Unknown => Err(SceneError::UnknownType {
                loc: loc(),
                kind,
                name: name.to_string(),
                valid: names::valid_list(supported, pbrt_only),
            }),
        }
    }

    fn require_world(&self, tok: &Token) -> Result<(), SceneError> {
        if self.in_world.is_none() {
            return Err(SceneError::syntax(
                &tok.loc(),
                &tok.text,
                format!("{} is not allowed before WorldBegin", tok.text),
            ));
        }
        Ok(())
    }

    /// Objects do not nest, and an object cannot instance another (pbrt-v4 refuses both).
    fn require_outside_object(&self, tok: &Token) -> Result<(), SceneError> {
        match &self.current_object {
            Some(o) => Err(SceneError::syntax(
                &tok.loc(),
                &tok.text,
                format!("{} inside the definition of object \"{}\" ({})", tok.text, o.name, o.loc),
            )),
            None => Ok(()),
        }
    }

    fn require_options(&self, tok: &Token) -> Result<(), SceneError> {
        if self.in_world.is_some() {
            return Err(SceneError::syntax(
                &tok.loc(),
                &tok.text,
                format!("{} is not allowed after WorldBegin", tok.text),
            ));
        }
        Ok(())
    }

    fn parse_text(
        &mut self,
        store: &SourceFiles,
        text: String,
        file: Arc<Path>,
        canonical: PathBuf,
    ) -> Result<(), SceneError> {
        let mut src = Source::new(store, SourceFile::new(file, self.search_dir.clone(), text), canonical);
        // The last directive read, whose location is taken when the file ends (an Import's at
        // once: the imported file's directives come after it).
        let mut last = None;
        while let Some(tok) = src.next()? {
            if tok.kind != TokenKind::Word {
                return Err(SceneError::syntax(&tok.loc(), &tok.display(), "expected a directive"));
            }
            if tok.text == "Import" {
                self.last_loc = Some(tok.loc());
                last = None;
            } else {
                last = Some((tok.file, tok.offset));
            }
            self.directive(&tok, &mut src)?;
        }
        if let Some((file, offset)) = last {
            self.last_loc = Some(file.location(offset));
        }
        Ok(())
    }

    fn directive(&mut self, tok: &Token, src: &mut Source) -> Result<(), SceneError> {
        let cs = self.gs.color_space;
        if self.transform_directive(tok, src)?
            || self.options_directive(tok, src, cs)?
            || self.world_directive(tok, src, cs)?
        {
            return Ok(());
        }
        match &*tok.text {
            "Include" | "Import" => {
                let name = src.string(tok, "a file name")?;
                if tok.text == "Import" {
                    self.require_world(tok)?;
                }
                self.include(tok, &name, src)?;
            }
            _ => {
                return Err(SceneError::syntax(&tok.loc(), &tok.text, format!("unknown directive \"{}\"", tok.text)));
            }
        }
        Ok(())
    }

    /// Include splices the file's tokens into `src` (pbrt-v4); Import parses it on its own.
    fn include(&mut self, tok: &Token, name: &Token, src: &mut Source) -> Result<(), SceneError> {
        let path = name.loc().resolve(&*name.text);
        let canon = canonical(&path);
        let open: Vec<&PathBuf> = self.include_stack.iter().chain(src.chain()).collect();
        if let Some(i) = open.iter().position(|p| **p == canon) {
            let mut chain: Vec<String> = open[i..].iter().map(|p| p.display().to_string()).collect();
            chain.push(canon.display().to_string());
            return Err(SceneError::IncludeCycle { loc: tok.loc(), chain: chain.join(" -> ") });
        }
        if open.len() >= MAX_INCLUDE_DEPTH {
            return Err(SceneError::syntax(
                &tok.loc(),
                &name.display(),
                format!("includes nested deeper than {MAX_INCLUDE_DEPTH} files"),
            ));
        }
        let max_includes = limit("PRISM_MAX_INCLUDES", MAX_INCLUDES as u64);
        if self.files_read.len() as u64 > max_includes {
            let message = format!(
                "more than {max_includes} Include/Import directives followed (a file counts each time it is \
                 read); set PRISM_MAX_INCLUDES to allow more"
            );
            return Err(SceneError::syntax(&tok.loc(), &name.display(), message));
        }
        let text = read_text(&path, &name.loc())?;
        self.text_bytes += text.len() as u64;
        let max_bytes = limit("PRISM_MAX_SCENE_BYTES", MAX_SCENE_TEXT_BYTES);
        if self.text_bytes > max_bytes {
            let message = format!(
                "more than {max_bytes} bytes of scene text read over all included files (a file counts each \
                 time it is read); set PRISM_MAX_SCENE_BYTES to allow more"
            );
            return Err(SceneError::syntax(&tok.loc(), &name.display(), message));
        }
        self.files_read.push(path.clone());
        if tok.text == "Include" {
            src.include(SourceFile::new(Arc::from(path.as_path()), self.search_dir.clone(), text), canon);
            return Ok(());
        }
        let outer = self.include_stack.len();
        self.include_stack.extend(src.chain().cloned());
        // pbrt-v4 parses an Import'ed file with its own copy of the graphics state (it may run
        // in parallel): its transforms, materials, area lights and coordinate-system names do not
        // leak back, and it cannot close blocks the importer opened. Named materials, textures,
        // objects, shapes and lights it defines belong to the scene.
        let (gs, named_cs, floor) = (self.gs.clone(), self.named_cs.clone(), self.stack_floor);
        self.stack_floor = self.stack.len();
        // Its tokens never leave that parse: its text can go when it ends.
        self.parse_text(&SourceFiles::default(), text, Arc::from(path.as_path()), canon)?;
        if self.stack.len() != self.stack_floor {
            let (_, kind, loc) = self.stack.last().expect("deeper than the floor");
            return Err(SceneError::syntax(
                &tok.loc(),
                &name.display(),
                format!("the imported file leaves the {kind:?}Begin at {loc} open; an imported file must close every block it opens"),
            ));
        }
        self.gs = gs;
        self.named_cs = named_cs;
        self.stack_floor = floor;
        self.include_stack.truncate(outer);
        Ok(())
    }

    /// Gives each "texture" parameter of `params` that names a texture defined by now that
    /// texture's shared name and its id; notes when one names a texture not (yet) defined.
    fn share_texture_names(&mut self, params: &mut ParamSet) {
        for p in params.iter_mut() {
            if let ParamValue::Texture(t, id) = &mut p.value {
                match self.texture_names.get_key_value(&**t) {
                    Some((shared, &(i, _))) => (*t, *id) = (shared.clone(), Some(i)),
                    None => self.texture_named_ahead = true,
                }
            }
        }
    }

    /// Closes the object being defined: it joins the scene's objects.
    fn end_object(&mut self) {
        let o = self.current_object.take().expect("ObjectBegin pushed an object");
        self.object_index.insert(o.name.clone(), self.objects.len());
        self.objects.push(o);
    }

    fn finish(mut self) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
        let end = self.last_loc.clone().unwrap_or_else(|| Location::new(Arc::from(Path::new("<empty>")), 1, 1));
        while let Some((_, kind, loc)) = self.stack.pop() {
            if kind == Pushed::Object {
                self.end_object();
                self.warn(&loc, "ObjectBegin without ObjectEnd; closed at end of file");
            } else {
                self.warn(&loc, format!("{kind:?}Begin without a matching End"));
            }
        }
        self.read_mesh_files()?;
        for (name, loc) in &self.named_material_uses {
            if !self.named_material_index.contains_key(name) {
                return Err(SceneError::syntax(loc, name, format!("named material \"{name}\" is not defined")));
            }
        }
        if !self.named_material_uses.is_empty() {
            let index = &self.named_material_index;
            let shapes = self.shapes.iter_mut().chain(self.objects.iter_mut().flat_map(|o| o.shapes.iter_mut()));
            for s in shapes {
                if let MaterialRef::Named(name, i) = &mut s.material {
                    if *i == DEFINED_LATER {
                        *i = index[name];
                    }
                }
            }
        }
        let mut instances = Vec::with_capacity(self.instances.len());
        for (object, m, motion, loc) in self.instances.drain(..) {
            let Some(&object_index) = self.object_index.get(&object) else {
                return Err(SceneError::syntax(&loc, &object, format!("object \"{object}\" is not defined")));
            };
            instances.push(InstanceDesc { object, object_index, world_from_instance: m, motion, loc });
        }
        // Names defined before their use were found as they were read.
        if self.texture_named_ahead {
            let texture_names = &self.texture_names;
            let check_textures = |ps: &ParamSet| -> Result<(), SceneError> {
                for p in ps.iter() {
                    if let ParamValue::Texture(t, _) = &p.value {
                        if !texture_names.contains_key(&**t) {
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
        }
        let shapes = self.shapes.iter().chain(self.objects.iter().flat_map(|o| o.shapes.iter()));
        let used = shapes.flat_map(|s| [(&s.media.inside, &s.loc), (&s.media.outside, &s.loc)]);
        let camera = self.camera.as_ref().map(|c| (&c.medium, &c.directive.loc));
        let lights = self.lights.iter().map(|l| (&l.medium, &l.loc));
        for (name, loc) in used.chain(camera).chain(lights) {
            if !name.is_empty() && !self.medium_index.contains_key(name) {
                return Err(SceneError::syntax(loc, name, format!("medium \"{name}\" is not defined")));
            }
        }
        // A redefined medium replaces the earlier definition, which leaves the list.
        let medium_index = &self.medium_index;
        let mut position = 0;
        self.media.retain(|m| {
            position += 1;
            medium_index[&m.name] == position - 1
        });
        let default_loc = self.in_world.clone().unwrap_or_else(|| end.clone());
        let cs = self.color_space;
        let dflt = |kind: &str| Directive { kind: kind.into(), params: ParamSet::new(cs), loc: default_loc.clone() };
        let desc = SceneDesc {
            camera: self.camera.unwrap_or_else(|| CameraDesc {
                directive: dflt("perspective"),
                camera_from_world: Mat4::IDENTITY,
                motion: None,
                medium: String::new(),
            }),
            film: self.film.unwrap_or_else(|| dflt("rgb")),
            sampler: self.sampler.unwrap_or_else(|| dflt("zsobol")),
            integrator: self.integrator.unwrap_or_else(|| dflt("path")),
            filter: self.filter.unwrap_or_else(|| dflt("gaussian")),
            accelerator: self.accelerator,
            color_space: self.color_space.to_string(),
            options: self.options,
            shapes: self.shapes,
            lights: self.lights,
            materials: self.materials,
            named_materials: self.named_materials,
            textures: self.textures,
            objects: self.objects,
            instances,
            media: self.media,
            scene_files: self.files_read,
        };
        if self.opts.strict {
            check_strict(&self.warnings)?;
        }
        Ok((desc, self.warnings))
    }
}

#[cfg(test)]
mod limits_tests;
