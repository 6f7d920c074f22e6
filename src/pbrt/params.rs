//! Typed parameter lists (`"float radius" [2]`) with use tracking.
//!
//! Follows pbrt-v4's `ParameterDictionary` (src/pbrt/paramdict.h): each getter marks what it read,
//! and [`ParamSet::report_unused`] warns about the rest, so typos like `"float radisu"` are seen.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::error::{Location, SceneError, Warning};
use super::number_list::{read_float, read_int, NumberKind, Numbers};
use super::tokenizer::{Token, TokenKind};
use crate::spectrum::is_named_spectrum;

/// A spectrum as written; the scene builder turns it into a `Spectrum`.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumParam {
    /// An RGB triple in the parameter set's colour space.
    Rgb([f32; 3]),
    /// Several RGB triples (a grid medium's voxels), in the parameter set's colour space.
    RgbArray(Vec<[f32; 3]>),
    /// A blackbody emitter at this temperature [K] (normalised to peak 1 by pbrt-v4).
    Blackbody(f32),
    /// Piecewise-linear samples (wavelength [nm], value), wavelengths increasing.
    Samples(Vec<(f32, f32)>),
    /// One of pbrt-v4's built-in spectra ([`crate::spectrum::is_named_spectrum`]).
    Named(String),
    /// A text file of (λ, value) pairs, resolved relative to the file that named it.
    File(PathBuf),
}

/// The values of one parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    /// "float"
    Float(Vec<f32>),
    /// "integer"
    Integer(Vec<i32>),
    /// "bool"
    Bool(Vec<bool>),
    /// "string"
    String(Vec<String>),
    /// "texture": the name of a texture, and which of the scene's texture names it is
    /// ([`crate::pbrt::TextureDesc::name_id`]) when a texture of that name is defined before the
    /// parameter (whose text the parameter then shares); `None` when none is.
    Texture(Arc<str>, Option<u32>),
    /// "point3" / "point"
    Point3(Vec<Vec3>),
    /// "vector3" / "vector"
    Vector3(Vec<Vec3>),
    /// "normal" / "normal3"
    Normal(Vec<Vec3>),
    /// "point2"
    Point2(Vec<Vec2>),
    /// "vector2"
    Vector2(Vec<Vec2>),
    /// "rgb" / "color", "blackbody", "spectrum"
    Spectrum(SpectrumParam),
}

/// The parameter names one parse has read, each held once: every parameter of a name shares
/// its text.
#[derive(Debug, Default)]
pub struct ParamNames(rustc_hash::FxHashSet<Arc<str>>);

impl ParamNames {
    /// The shared text of `name`.
    pub fn intern(&mut self, name: &str) -> Arc<str> {
        if let Some(n) = self.0.get(name) {
            return n.clone();
        }
        let n: Arc<str> = Arc::from(name);
        self.0.insert(n.clone());
        n
    }
}

/// A parameter's type, as pbrt-v4 spells it canonically.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum ParamType {
    /// "float"
    Float,
    /// "integer"
    Integer,
    /// "bool"
    Bool,
    /// "string"
    String,
    /// "texture"
    Texture,
    /// "point3" (also "point")
    Point3,
    /// "vector3" (also "vector")
    Vector3,
    /// "normal" (also "normal3")
    Normal,
    /// "point2"
    Point2,
    /// "vector2"
    Vector2,
    /// "rgb" (also "color")
    Rgb,
    /// "blackbody"
    Blackbody,
    /// "spectrum"
    Spectrum,
}

impl ParamType {
    /// The canonical name ("float", "point3", "rgb", ...).
    pub fn name(self) -> &'static str {
        match self {
            Self::Float => "float",
            Self::Integer => "integer",
            Self::Bool => "bool",
            Self::String => "string",
            Self::Texture => "texture",
            Self::Point3 => "point3",
            Self::Vector3 => "vector3",
            Self::Normal => "normal",
            Self::Point2 => "point2",
            Self::Vector2 => "vector2",
            Self::Rgb => "rgb",
            Self::Blackbody => "blackbody",
            Self::Spectrum => "spectrum",
        }
    }
}

/// One named, typed parameter and where it was written.
#[derive(Debug)]
pub struct Param {
    /// Parameter name ("radius"), shared by the parameters of that name ([`ParamNames`]).
    pub name: Arc<str>,
    /// Its type.
    pub ty: ParamType,
    /// Values.
    pub value: ParamValue,
    /// Location of the `"type name"` declaration.
    pub loc: Location,
    used: AtomicBool,
    /// How many values it held when read as a single one (0: never; more than 1: the rest were
    /// ignored).
    read_as_one: AtomicU32,
}

impl Clone for Param {
    fn clone(&self) -> Self {
        Self {
            name: self.name.clone(),
            ty: self.ty,
            value: self.value.clone(),
            loc: self.loc.clone(),
            used: AtomicBool::new(self.used.load(Ordering::Relaxed)),
            read_as_one: AtomicU32::new(self.read_as_one.load(Ordering::Relaxed)),
        }
    }
}

impl Param {
    /// A parameter that has not been read yet.
    pub fn new(name: Arc<str>, ty: ParamType, value: ParamValue, loc: Location) -> Self {
        Self { name, ty, value, loc, used: AtomicBool::new(false), read_as_one: AtomicU32::new(0) }
    }

    /// Canonical type name as pbrt-v4 spells it ("float", "point3", "rgb", ...).
    pub fn type_name(&self) -> &'static str {
        self.ty.name()
    }

    /// True once a getter read it.
    pub fn is_used(&self) -> bool {
        self.used.load(Ordering::Relaxed)
    }

    fn mark(&self) -> &Self {
        self.used.store(true, Ordering::Relaxed);
        self
    }

    /// Parses a declaration (`"float radius"`) and its value tokens; the name is shared through
    /// `names`.
    pub fn parse(decl: &Token, values: &[Token], names: &mut ParamNames) -> Result<Self, SceneError> {
        let loc = &decl.loc();
        let (ty, name) = declaration(decl)?;
        let err = |tok: &Token, msg: String| SceneError::syntax(&tok.loc(), &tok.display(), msg);
        let decl_err = |msg: String| SceneError::syntax(loc, &decl.display(), msg);
        if values.is_empty() {
            return Err(decl_err(no_values(ty, name)));
        }
        if let Some(kind) = number_kind(ty) {
            let numbers = match kind {
                NumberKind::Integer => Numbers::Integers(each(values, parse_int)?),
                NumberKind::Float => Numbers::Floats(each(values, parse_float)?),
            };
            let (param_type, value) = numeric_value(ty, name, numbers).map_err(decl_err)?;
            return Ok(Self::new(names.intern(name), param_type, value, loc.clone()));
        }
        let floats = || each(values, parse_float);
        let not_multiple = |n: usize| {
            let len = values.len();
            decl_err(format!("parameter \"{ty} {name}\" has {len} values; a multiple of {n} is required"))
        };
        let not_exactly = |n: usize| {
            let len = values.len();
            decl_err(format!("parameter \"{ty} {name}\" has {len} values; exactly {n} are required"))
        };
        let exactly = |n: usize| -> Result<Vec<f32>, SceneError> {
            let v = floats()?;
            if v.len() != n {
                return Err(not_exactly(n));
            }
            Ok(v)
        };
        let strings = || {
            each(values, |t| match t.kind {
                TokenKind::Str => Ok(t.text.to_string()),
                _ => Err(err(t, format!("expected a quoted string for \"{ty} {name}\""))),
            })
        };
        let (param_type, value) = match ty {
            "bool" => (
                ParamType::Bool,
                ParamValue::Bool(each(values, |t| match &*t.text {
                    "true" => Ok(true),
                    "false" => Ok(false),
                    _ => Err(err(t, "expected true or false".into())),
                })?),
            ),
            "string" => (ParamType::String, ParamValue::String(strings()?)),
            "texture" if values.len() == 1 && values[0].kind == TokenKind::Str => {
                (ParamType::Texture, ParamValue::Texture(Arc::from(&*values[0].text), None))
            }
            "texture" => {
                let s = strings()?;
                if s.len() != 1 {
                    return Err(decl_err(format!("parameter \"{ty} {name}\" needs exactly one texture name")));
                }
                (ParamType::Texture, ParamValue::Texture(Arc::from(s.into_iter().next().unwrap_or_default()), None))
            }
            "rgb" | "color" if values.len() > 3 => (
                ParamType::Rgb,
                ParamValue::Spectrum(SpectrumParam::RgbArray(groups(values, |c| c, || not_multiple(3))?)),
            ),
            "rgb" | "color" => {
                // At most three values: read them into place, then check there were three.
                let mut c = [0.0; 3];
                for (x, t) in c.iter_mut().zip(values) {
                    *x = parse_float(t)?;
                }
                if values.len() != 3 {
                    return Err(not_exactly(3));
                }
                (ParamType::Rgb, ParamValue::Spectrum(SpectrumParam::Rgb(c)))
            }
            "blackbody" => {
                let t = exactly(1)?[0];
                if t <= 0.0 {
                    return Err(err(&values[0], "blackbody temperature must be positive [K]".into()));
                }
                (ParamType::Blackbody, ParamValue::Spectrum(SpectrumParam::Blackbody(t)))
            }
            "spectrum" => (ParamType::Spectrum, ParamValue::Spectrum(parse_spectrum(decl, values, ty, name)?)),
            _ => {
                return Err(decl_err(format!(
                    "unknown parameter type \"{ty}\"; valid types: blackbody, bool, float, integer, \
                     normal, point2, point3, rgb, spectrum, string, texture, vector2, vector3"
                )))
            }
        };
        Ok(Self::new(names.intern(name), param_type, value, loc.clone()))
    }

    /// The parameter declared by `decl` (a type [`number_kind_of`] accepts) with the values of a
    /// list read from the file's text ([`super::number_list`]).
    pub(super) fn from_numbers(decl: &Token, numbers: Numbers, names: &mut ParamNames) -> Result<Self, SceneError> {
        let loc = decl.loc();
        let (ty, name) = declaration(decl)?;
        let decl_err = |msg: String| SceneError::syntax(&loc, &decl.display(), msg);
        if numbers.is_empty() {
            return Err(decl_err(no_values(ty, name)));
        }
        let (param_type, value) = numeric_value(ty, name, numbers).map_err(decl_err)?;
        Ok(Self::new(names.intern(name), param_type, value, loc))
    }
}

/// The type and name of the declaration `decl` (`"float radius"`).
fn declaration<'t>(decl: &'t Token) -> Result<(&'t str, &'t str), SceneError> {
    let mut words = decl.text.split_whitespace();
    match (words.next(), words.next(), words.next()) {
        (Some(ty), Some(name), None) => Ok((ty, name)),
        _ => Err(SceneError::syntax(&decl.loc(), &decl.display(), "a parameter declaration must be \"type name\"")),
    }
}

fn no_values(ty: &str, name: &str) -> String {
    format!("parameter \"{ty} {name}\" has no values")
}

/// Which numbers a parameter of type `ty` holds; `None` for a type that holds anything else
/// (or, for "rgb", "blackbody" and "spectrum", numbers with rules of their own).
fn number_kind(ty: &str) -> Option<NumberKind> {
    match ty {
        "float" | "point3" | "point" | "vector3" | "vector" | "normal" | "normal3" | "point2" | "vector2" => {
            Some(NumberKind::Float)
        }
        "integer" => Some(NumberKind::Integer),
        _ => None,
    }
}

/// Which numbers the parameter declared by `decl` holds, if it is a well-formed declaration of
/// a [`number_kind`] type.
pub(super) fn number_kind_of(decl: &Token) -> Option<NumberKind> {
    declaration(decl).ok().and_then(|(ty, _)| number_kind(ty))
}

/// The value of a parameter of a [`number_kind`] type `ty` named `name` holding `numbers`
/// (integers for "integer", floats for the others); the message when their count does not fit
/// the type.
fn numeric_value(ty: &str, name: &str, numbers: Numbers) -> Result<(ParamType, ParamValue), String> {
    let v = match numbers {
        Numbers::Integers(v) => return Ok((ParamType::Integer, ParamValue::Integer(v))),
        Numbers::Floats(v) => v,
    };
    let not_multiple =
        |n: usize| format!("parameter \"{ty} {name}\" has {} values; a multiple of {n} is required", v.len());
    let vec3s = || match v.len() % 3 {
        0 => Ok(v.chunks_exact(3).map(Vec3::from_slice).collect()),
        _ => Err(not_multiple(3)),
    };
    let vec2s = || match v.len() % 2 {
        0 => Ok(v.chunks_exact(2).map(Vec2::from_slice).collect()),
        _ => Err(not_multiple(2)),
    };
    Ok(match ty {
        "point3" | "point" => (ParamType::Point3, ParamValue::Point3(vec3s()?)),
        "vector3" | "vector" => (ParamType::Vector3, ParamValue::Vector3(vec3s()?)),
        "normal" | "normal3" => (ParamType::Normal, ParamValue::Normal(vec3s()?)),
        "point2" => (ParamType::Point2, ParamValue::Point2(vec2s()?)),
        "vector2" => (ParamType::Vector2, ParamValue::Vector2(vec2s()?)),
        _ => (ParamType::Float, ParamValue::Float(v)),
    })
}

/// Each of `values` read by `read`, into a vector of exactly their number (collecting a
/// `Result` grows the vector as it goes, from room for four values).
fn each<T>(values: &[Token], read: impl FnMut(&Token) -> Result<T, SceneError>) -> Result<Vec<T>, SceneError> {
    let mut out = Vec::with_capacity(values.len());
    for v in values.iter().map(read) {
        out.push(v?);
    }
    Ok(out)
}

/// `values` read as numbers in groups of `N`, each made into a `T` by `make`; `not_multiple()`
/// when their count is not a multiple of `N`. Every number is read before the count is checked,
/// so a bad number is the error even when the count is wrong too.
fn groups<const N: usize, T>(
    values: &[Token],
    make: impl Fn([f32; N]) -> T,
    not_multiple: impl FnOnce() -> SceneError,
) -> Result<Vec<T>, SceneError> {
    let mut out = Vec::with_capacity(values.len() / N);
    let mut group = [0.0; N];
    for (i, t) in values.iter().enumerate() {
        group[i % N] = parse_float(t)?;
        if i % N == N - 1 {
            out.push(make(group));
        }
    }
    if !values.len().is_multiple_of(N) {
        return Err(not_multiple());
    }
    Ok(out)
}

fn parse_spectrum(decl: &Token, values: &[Token], ty: &str, name: &str) -> Result<SpectrumParam, SceneError> {
    if values[0].kind == TokenKind::Str {
        if values.len() != 1 {
            return Err(SceneError::syntax(
                &decl.loc(),
                &decl.display(),
                format!("parameter \"{ty} {name}\" takes one spectrum name or file name"),
            ));
        }
        let s = &values[0].text;
        return Ok(if is_named_spectrum(s) {
            SpectrumParam::Named(s.to_string())
        } else {
            SpectrumParam::File(values[0].loc().resolve(&**s))
        });
    }
    let v = each(values, parse_float)?;
    if !v.len().is_multiple_of(2) {
        return Err(SceneError::syntax(
            &decl.loc(),
            &decl.display(),
            format!("parameter \"{ty} {name}\" has {} values; (wavelength, value) pairs are required", v.len()),
        ));
    }
    let pairs: Vec<(f32, f32)> = v.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    for (i, w) in pairs.windows(2).enumerate() {
        if w[1].0 <= w[0].0 {
            let t = &values[2 * i + 2];
            return Err(SceneError::syntax(&t.loc(), &t.display(), "spectrum wavelengths must increase"));
        }
    }
    Ok(SpectrumParam::Samples(pairs))
}

/// Parses a finite number; NaN, ±Inf and overflow are errors.
pub fn parse_float(t: &Token) -> Result<f32, SceneError> {
    word_of(t, "expected a number").and_then(|w| read_float(w).map_err(|m| SceneError::syntax(&t.loc(), w, m)))
}

/// The text of `t` if it is a word; else the error `message` at it.
fn word_of<'t>(t: &'t Token, message: &str) -> Result<&'t str, SceneError> {
    match t.kind {
        TokenKind::Word => Ok(&t.text),
        _ => Err(SceneError::syntax(&t.loc(), &t.display(), message)),
    }
}

/// Parses a 32-bit integer.
pub fn parse_int(t: &Token) -> Result<i32, SceneError> {
    word_of(t, "expected an integer").and_then(|w| read_int(w).map_err(|m| SceneError::syntax(&t.loc(), w, m)))
}

/// A spectrum-valued input that may instead name a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumOrTexture<'a> {
    /// A constant spectrum.
    Spectrum(&'a SpectrumParam),
    /// A named "spectrum" texture.
    Texture(&'a str),
}

/// A float-valued input that may instead name a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum FloatOrTexture<'a> {
    /// A constant.
    Float(f32),
    /// A named "float" texture.
    Texture(&'a str),
}

/// The parameters of one directive.
#[derive(Clone, Debug, Default)]
pub struct ParamSet {
    params: Vec<Param>,
    /// Notes about the parameters as written (repeated names), reported with the unused ones.
    notes: Vec<Warning>,
    /// Colour space of "rgb" values (the ColorSpace in effect, one of
    /// [`crate::pbrt::names::COLOR_SPACES`]; "srgb" unless changed).
    pub color_space: &'static str,
}

macro_rules! getters {
    ($many:ident, $one:ident, $variant:ident, $t:ty) => {
        /// All values of this parameter, if present with this type (marks it used).
        pub fn $many(&self, name: &str) -> Option<&[$t]> {
            self.find(name, |v| match v {
                ParamValue::$variant(x) => Some(x.as_slice()),
                _ => None,
            })
        }
        /// The first value of this parameter, if present with this type (marks it used; more
        /// than one value is reported by [`ParamSet::report_unused`]).
        pub fn $one(&self, name: &str) -> Option<$t> {
            self.$many(name).and_then(|v| self.first(name, v)).cloned()
        }
    };
}

impl ParamSet {
    /// An empty set in colour space `color_space`.
    pub fn new(color_space: &'static str) -> Self {
        Self { params: Vec::new(), notes: Vec::new(), color_space }
    }

    /// An empty set in colour space `color_space` that collects its parameters in `buffer`
    /// (emptied first); [`ParamSet::compact`] hands the buffer back.
    pub(crate) fn with_buffer(mut buffer: Vec<Param>, color_space: &'static str) -> Self {
        buffer.clear();
        Self { params: buffer, notes: Vec::new(), color_space }
    }

    /// The set with its parameters moved into a vector of exactly their number, and the emptied
    /// vector they were in (to collect the next set in: a set grown one parameter at a time
    /// holds room for more than it has).
    pub(crate) fn compact(mut self) -> (Self, Vec<Param>) {
        let params = self.params.drain(..).collect();
        let buffer = std::mem::replace(&mut self.params, params);
        (self, buffer)
    }

    /// Adds a parameter. A second one of the same name and kind replaces the first with a note,
    /// as in pbrt-v4 (whose lookups find the last one written); one of another kind ("float
    /// eta" beside "spectrum eta") is kept beside it, and each getter finds its own.
    pub fn push(&mut self, p: Param) -> Result<(), SceneError> {
        let same = |q: &Param| q.name == p.name && std::mem::discriminant(&q.value) == std::mem::discriminant(&p.value);
        if let Some(i) = self.params.iter().position(same) {
            let old = self.params.remove(i);
            let message = format!(
                "parameter \"{} {}\" given again (first at {}); the last value is used, as in pbrt-v4",
                p.type_name(),
                p.name,
                old.loc
            );
            self.notes.push(Warning::note(&p.loc, message));
        }
        self.params.push(p);
        Ok(())
    }

    /// Adds `defaults` entries whose names are not already present (the `Attribute` directive).
    pub fn merge_defaults(&mut self, defaults: &ParamSet) {
        for p in &defaults.params {
            if !self.has(&p.name) {
                let mut q = p.clone();
                q.used = AtomicBool::new(false);
                self.params.push(q);
            }
        }
    }

    /// Drops the parameters already read that have nothing left to report (none read as one
    /// value of several, no spectra, whose negative RGB components are reported) and name no
    /// file: those a shape's mesh has taken its values from, so that the description holds them
    /// once.
    pub(crate) fn drop_consumed(&mut self) {
        self.params.retain(|p| {
            let reported = p.read_as_one.load(Ordering::Relaxed) > 1 || matches!(p.value, ParamValue::Spectrum(_));
            let names_file = matches!(&*p.name, "filename" | "lensfile");
            !p.is_used() || reported || names_file
        });
        if self.params.is_empty() {
            self.params = Vec::new();
        }
    }

    /// True when a parameter with this name exists (does not mark it used).
    pub fn has(&self, name: &str) -> bool {
        self.params.iter().any(|p| *p.name == *name)
    }

    /// Marks every parameter named `name` read, for one a directive reads only to ignore.
    pub fn mark_used(&self, name: &str) {
        self.params.iter().filter(|p| *p.name == *name).for_each(|p| p.used.store(true, Ordering::Relaxed));
    }

    /// All parameters.
    pub fn iter(&self) -> impl Iterator<Item = &Param> {
        self.params.iter()
    }

    /// All parameters, mutably.
    pub(crate) fn iter_mut(&mut self) -> impl Iterator<Item = &mut Param> {
        self.params.iter_mut()
    }

    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.params.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// The parameter `name` regardless of type, marking it used.
    pub fn get(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| *p.name == *name).map(Param::mark)
    }

    fn find<'a, T: ?Sized>(&'a self, name: &str, f: impl Fn(&'a ParamValue) -> Option<&'a T>) -> Option<&'a T> {
        let (p, v) = self.params.iter().filter(|p| *p.name == *name).find_map(|p| Some((p, f(&p.value)?)))?;
        p.mark();
        Some(v)
    }

    getters!(floats, float, Float, f32);
    getters!(ints, int, Integer, i32);
    getters!(bools, bool, Bool, bool);
    getters!(point3s, point3, Point3, Vec3);
    getters!(vector3s, vector3, Vector3, Vec3);
    getters!(normals, normal, Normal, Vec3);
    getters!(point2s, point2, Point2, Vec2);
    getters!(vector2s, vector2, Vector2, Vec2);

    /// `float(name)` or `default`.
    pub fn float_or(&self, name: &str, default: f32) -> f32 {
        self.float(name).unwrap_or(default)
    }

    /// `int(name)` or `default`.
    pub fn int_or(&self, name: &str, default: i32) -> i32 {
        self.int(name).unwrap_or(default)
    }

    /// `bool(name)` or `default`.
    pub fn bool_or(&self, name: &str, default: bool) -> bool {
        self.bool(name).unwrap_or(default)
    }

    /// All strings of a "string" parameter.
    pub fn strings(&self, name: &str) -> Option<&[String]> {
        self.find(name, |v| match v {
            ParamValue::String(x) => Some(x.as_slice()),
            _ => None,
        })
    }

    /// The first string of a "string" parameter.
    pub fn string(&self, name: &str) -> Option<&str> {
        self.strings(name).and_then(|v| self.first(name, v)).map(String::as_str)
    }

    /// The first of the values `v` of parameter `name`, noting when there were more.
    fn first<'a, T>(&self, name: &str, v: &'a [T]) -> Option<&'a T> {
        if v.len() > 1 {
            if let Some(p) = self.params.iter().find(|p| *p.name == *name) {
                p.read_as_one.store(u32::try_from(v.len()).unwrap_or(u32::MAX), Ordering::Relaxed);
            }
        }
        v.first()
    }

    /// A "string" parameter naming a file, resolved as [`Location::resolve`] does.
    pub fn filename(&self, name: &str) -> Option<PathBuf> {
        let s = self.string(name)?;
        let p = self.params.iter().find(|p| *p.name == *name)?;
        Some(p.loc.resolve(s))
    }

    /// The files this set's parameters name, resolved as [`ParamSet::filename`] does: every
    /// "string filename", a realistic camera's "string lensfile" and every spectrum read from a
    /// file. Does not mark them used.
    pub fn named_files(&self) -> impl Iterator<Item = PathBuf> + '_ {
        self.params.iter().flat_map(|p| match &p.value {
            ParamValue::String(v) if matches!(&*p.name, "filename" | "lensfile") => {
                v.iter().map(|s| p.loc.resolve(s)).collect()
            }
            ParamValue::Spectrum(SpectrumParam::File(f)) => vec![f.clone()],
            _ => Vec::new(),
        })
    }

    /// A "rgb"/"blackbody"/"spectrum" parameter.
    pub fn spectrum(&self, name: &str) -> Option<&SpectrumParam> {
        self.find(name, |v| match v {
            ParamValue::Spectrum(s) => Some(s),
            _ => None,
        })
    }

    /// A "texture" parameter: the texture's name.
    pub fn texture(&self, name: &str) -> Option<&str> {
        self.texture_ref(name).map(|(s, _)| s)
    }

    /// A "texture" parameter: the texture's name, and its id when a texture of that name is
    /// defined before the parameter.
    pub(crate) fn texture_ref(&self, name: &str) -> Option<(&str, Option<u32>)> {
        let (p, v) = self.params.iter().filter(|p| *p.name == *name).find_map(|p| match &p.value {
            ParamValue::Texture(s, id) => Some((p, (&**s, *id))),
            _ => None,
        })?;
        p.mark();
        Some(v)
    }

    /// A spectrum or a texture reference (material inputs such as "reflectance").
    pub fn spectrum_or_texture(&self, name: &str) -> Option<SpectrumOrTexture<'_>> {
        if let Some(t) = self.texture(name) {
            return Some(SpectrumOrTexture::Texture(t));
        }
        self.spectrum(name).map(SpectrumOrTexture::Spectrum)
    }

    /// A float or a texture reference (material inputs such as "roughness").
    pub fn float_or_texture(&self, name: &str) -> Option<FloatOrTexture<'_>> {
        if let Some(t) = self.texture(name) {
            return Some(FloatOrTexture::Texture(t));
        }
        self.float(name).map(FloatOrTexture::Float)
    }

    /// Warnings for every parameter no getter has read, read as one value of several, or given
    /// as RGB with negative components, naming the directive it belongs to (e.g. `Shape
    /// "sphere"`).
    pub fn report_unused(&self, context: impl std::fmt::Display) -> Vec<Warning> {
        let unused = self.params.iter().filter(|p| !p.is_used()).map(|p| {
            Warning::refused(&p.loc, format!("parameter \"{} {}\" of {context} was not used", p.type_name(), p.name))
        });
        let extra = self.params.iter().filter(|p| p.read_as_one.load(Ordering::Relaxed) > 1).map(|p| {
            let message = format!(
                "parameter \"{} {}\" of {context} takes one value, but {} were given; the rest were ignored",
                p.type_name(),
                p.name,
                p.read_as_one.load(Ordering::Relaxed)
            );
            Warning::refused(&p.loc, message)
        });
        // The RGB → spectrum conversion takes negative components as 0: say so (once: an unused
        // parameter is reported as unused only).
        let negative = self.params.iter().filter_map(|p| match &p.value {
            ParamValue::Spectrum(SpectrumParam::Rgb(c)) if p.is_used() && c.iter().any(|&x| x < 0.0) => {
                Some(Warning::note(
                    &p.loc,
                    format!(
                        "parameter \"{} {}\" of {context} has negative components {c:?}; they are taken as 0",
                        p.type_name(),
                        p.name
                    ),
                ))
            }
            _ => None,
        });
        self.notes.iter().cloned().chain(unused).chain(extra).chain(negative).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::tokenizer::{SourceFile, Tokenizer};
    use std::path::Path;
    use std::sync::Arc;

    fn toks(f: &SourceFile) -> Vec<Token<'_>> {
        let mut t = Tokenizer::new(f);
        let mut v = Vec::new();
        while let Some(x) = t.next_token().unwrap() {
            v.push(x);
        }
        v
    }

    fn param(decl: &str, vals: &str) -> Result<Param, SceneError> {
        let file = |s: String| SourceFile::new(Arc::from(Path::new("dir/p.pbrt")), None, s);
        let (d, v) = (file(format!("\"{decl}\"")), file(vals.to_string()));
        Param::parse(&toks(&d)[0], &toks(&v), &mut ParamNames::default())
    }

    #[test]
    fn each_type_parses() {
        assert_eq!(param("float r", "2.5").unwrap().value, ParamValue::Float(vec![2.5]));
        assert_eq!(param("integer n", "-3 4").unwrap().value, ParamValue::Integer(vec![-3, 4]));
        assert_eq!(param("bool b", "true \"false\"").unwrap().value, ParamValue::Bool(vec![true, false]));
        assert_eq!(param("string s", "\"x\"").unwrap().value, ParamValue::String(vec!["x".into()]));
        assert_eq!(param("texture t", "\"checks\"").unwrap().value, ParamValue::Texture("checks".into(), None));
        let p = param("point P", "0 1 2 3 4 5").unwrap();
        assert_eq!(p.type_name(), "point3");
        assert_eq!(p.value, ParamValue::Point3(vec![Vec3::new(0., 1., 2.), Vec3::new(3., 4., 5.)]));
        assert_eq!(param("normal3 N", "0 0 1").unwrap().type_name(), "normal");
        assert_eq!(param("vector3 v", "0 0 1").unwrap().type_name(), "vector3");
        assert_eq!(param("point2 uv", "0 1").unwrap().value, ParamValue::Point2(vec![Vec2::new(0., 1.)]));
        assert_eq!(param("color Kd", ".5 .5 .5").unwrap().value, ParamValue::Spectrum(SpectrumParam::Rgb([0.5; 3])));
        assert_eq!(param("blackbody L", "6500").unwrap().value, ParamValue::Spectrum(SpectrumParam::Blackbody(6500.)));
        assert_eq!(
            param("spectrum eta", "400 1.5 700 1.4").unwrap().value,
            ParamValue::Spectrum(SpectrumParam::Samples(vec![(400., 1.5), (700., 1.4)]))
        );
        assert_eq!(
            param("spectrum eta", "\"metal-Cu-eta\"").unwrap().value,
            ParamValue::Spectrum(SpectrumParam::Named("metal-Cu-eta".into()))
        );
        assert_eq!(
            param("spectrum k", "\"spd/cu.spd\"").unwrap().value,
            ParamValue::Spectrum(SpectrumParam::File(PathBuf::from("dir/spd/cu.spd")))
        );
    }

    #[test]
    fn values_are_held_in_vectors_of_their_length() {
        for (decl, values, n) in
            [("string s", "\"x\"", 1), ("integer i", "0 1 2", 3), ("float f", "1 2 3 4 5", 5), ("bool b", "true", 1)]
        {
            let capacity = match param(decl, values).unwrap().value {
                ParamValue::String(v) => v.capacity(),
                ParamValue::Integer(v) => v.capacity(),
                ParamValue::Float(v) => v.capacity(),
                ParamValue::Bool(v) => v.capacity(),
                v => panic!("{v:?}"),
            };
            assert_eq!(capacity, n, "{decl}");
        }
    }

    #[test]
    fn error_messages() {
        let e = |d, v| param(d, v).unwrap_err().to_string();
        assert_eq!(
            e("point3 P", "0 1 2 3"),
            "dir/p.pbrt:1:1: parameter \"point3 P\" has 4 values; a multiple of 3 is required (at \"\"point3 P\"\")"
        );
        assert_eq!(e("float x", "nan"), "dir/p.pbrt:1:1: number is not finite (at \"nan\")");
        assert_eq!(e("float x", "1 inf"), "dir/p.pbrt:1:3: number is not finite (at \"inf\")");
        assert_eq!(e("float x", "1e39"), "dir/p.pbrt:1:1: number is not finite (at \"1e39\")");
        assert_eq!(e("integer n", "1.5"), "dir/p.pbrt:1:1: expected an integer (at \"1.5\")");
        assert_eq!(e("integer n", "4294967296"), "dir/p.pbrt:1:1: integer out of range (at \"4294967296\")");
        assert_eq!(e("float", "1"), "dir/p.pbrt:1:1: a parameter declaration must be \"type name\" (at \"\"float\"\")");
        assert_eq!(
            e("rgb c", "1 1"),
            "dir/p.pbrt:1:1: parameter \"rgb c\" has 2 values; exactly 3 are required (at \"\"rgb c\"\")"
        );
        assert_eq!(e("spectrum s", "500 1 400 1"), "dir/p.pbrt:1:7: spectrum wavelengths must increase (at \"400\")");
        assert!(e("quaternion q", "1").contains("unknown parameter type \"quaternion\""));
        assert_eq!(e("bool b", "yes"), "dir/p.pbrt:1:1: expected true or false (at \"yes\")");
    }

    #[test]
    fn getters_mark_used_and_report_unused_lists_the_rest() {
        let mut ps = ParamSet::new("srgb");
        ps.push(param("float radius", "2").unwrap()).unwrap();
        ps.push(param("float radisu", "3").unwrap()).unwrap();
        ps.push(param("integer n", "3").unwrap()).unwrap();
        assert_eq!(ps.float_or("radius", 1.0), 2.0);
        // Wrong type: not found, not marked.
        assert_eq!(ps.float("n"), None);
        let w: Vec<String> = ps.report_unused("Shape \"sphere\"").iter().map(|w| w.to_string()).collect();
        assert_eq!(
            w,
            vec![
                "dir/p.pbrt:1:1: warning: parameter \"float radisu\" of Shape \"sphere\" was not used",
                "dir/p.pbrt:1:1: warning: parameter \"integer n\" of Shape \"sphere\" was not used",
            ]
        );
        // Given again: the last value wins, with a note; another kind of the same name stays.
        ps.push(param("float radius", "5").unwrap()).unwrap();
        ps.push(param("string radius", "\"r\"").unwrap()).unwrap();
        assert_eq!(ps.float("radius"), Some(5.0));
        assert_eq!(ps.string("radius"), Some("r"));
        assert!(ps.report_unused("Shape \"sphere\"").iter().any(|w| w.message.contains("given again")));
    }

    #[test]
    fn texture_takes_precedence_and_filenames_resolve() {
        let mut ps = ParamSet::new("srgb");
        ps.push(param("texture reflectance", "\"t\"").unwrap()).unwrap();
        ps.push(param("string filename", "\"m.ply\"").unwrap()).unwrap();
        assert_eq!(ps.spectrum_or_texture("reflectance"), Some(SpectrumOrTexture::Texture("t")));
        assert_eq!(ps.filename("filename"), Some(PathBuf::from("dir/m.ply")));
        assert!(ps.report_unused("x").is_empty());
    }
}
