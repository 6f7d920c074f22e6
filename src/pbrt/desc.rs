//! `SceneDesc`: what a scene file says, independent of the renderer's materials and lights.
//!
//! Transforms follow pbrt-v4: `world_from_object` maps object space to world space; glam
//! matrices are column-major like the numbers of pbrt's `Transform` directive.

use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use std::path::PathBuf;
use std::sync::Arc;

use glam::Mat4;

use super::error::{Location, Warning};
use super::params::ParamSet;
use crate::geometry::{AnimatedTransform, Mesh, Quadric};

/// A directive that is just a type and parameters (Film, Sampler, Integrator, PixelFilter, ...).
#[derive(Clone, Debug)]
pub struct Directive {
    /// The type name ("rgb", "zsobol", "path", "gaussian").
    pub kind: String,
    /// Its parameters.
    pub params: ParamSet,
    /// Where it was written (for defaults: the WorldBegin that applied them).
    pub loc: Location,
}

/// The Camera directive.
#[derive(Clone, Debug)]
pub struct CameraDesc {
    /// Type and parameters ("perspective": fov, lensradius, focaldistance, screenwindow, ...).
    pub directive: Directive,
    /// The current transform at the Camera directive: camera space from world space (the start
    /// one when the camera moves).
    pub camera_from_world: Mat4,
    /// World space from camera space between the start and end CTMs over `TransformTimes`,
    /// when they differ (a moving camera, pbrt-v4's camera `AnimatedTransform`).
    pub motion: Option<AnimatedTransform>,
    /// The medium the camera sits in: the current outside medium at the directive ("": vacuum).
    pub medium: String,
}

/// The media named by `MediumInterface` for the shapes that follow ("": vacuum).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MediumNames {
    /// The medium behind the surface (opposite its normal).
    pub inside: String,
    /// The medium in front of it.
    pub outside: String,
}

/// A MakeNamedMedium directive.
#[derive(Clone, Debug)]
pub struct MediumDesc {
    /// Its name.
    pub name: String,
    /// "homogeneous", "uniformgrid", ...
    pub kind: String,
    /// Its parameters (without "type").
    pub params: ParamSet,
    /// World from medium space: the current transform at the directive.
    pub world_from_medium: Mat4,
    /// Where it was written.
    pub loc: Location,
}

/// Which material a shape uses.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MaterialRef {
    /// No Material directive yet: pbrt-v4's default, a "diffuse" material with reflectance 0.5.
    Default,
    /// An anonymous `Material` directive: index into [`SceneDesc::materials`].
    Anonymous(usize),
    /// `NamedMaterial "name"`: the name (checked to exist; the text its definition holds when
    /// the definition came first) and the index of its definition in
    /// [`SceneDesc::named_materials`].
    Named(Arc<str>, usize),
}

/// A Material or MakeNamedMaterial directive.
#[derive(Clone, Debug)]
pub struct MaterialDesc {
    /// Material type ("diffuse", "conductor", "dielectric", "coateddiffuse").
    pub kind: &'static str,
    /// Its parameters (for MakeNamedMaterial, without "type").
    pub params: ParamSet,
    /// Where it was written.
    pub loc: Location,
}

/// A named material.
#[derive(Clone, Debug)]
pub struct NamedMaterial {
    /// The name given to MakeNamedMaterial (shared by the shapes that use it).
    pub name: Arc<str>,
    /// The material.
    pub material: MaterialDesc,
}

/// Whether a texture yields floats or spectra.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureClass {
    /// "float"
    Float,
    /// "spectrum" (also pbrt-v3's "color")
    Spectrum,
}

/// A Texture directive.
#[derive(Clone, Debug)]
pub struct TextureDesc {
    /// Name that "texture" parameters refer to (shared with the parser's index of names, with
    /// every definition of the name and with the parameters written after the first).
    pub name: Arc<str>,
    /// Which of the scene's texture names this is: names are numbered from 0 in the order of
    /// their first definitions, whatever their class.
    pub name_id: u32,
    /// Float or spectrum.
    pub class: TextureClass,
    /// Texture type ("imagemap", "checkerboard", ...).
    pub kind: &'static str,
    /// Its parameters.
    pub params: ParamSet,
    /// World space from texture space (the current transform at the directive).
    pub world_from_texture: Mat4,
    /// Where it was written.
    pub loc: Location,
}

/// The geometry of a shape, loaded and checked by the parser, in object space.
#[derive(Clone, Debug)]
pub enum ShapeGeometry {
    /// A triangle mesh (trianglemesh, plymesh, objmesh, bilinearmesh, loopsubdiv limit surface).
    Mesh(Arc<Mesh>),
    /// A pbrt-v4 quadric (sphere, disk, cylinder) about the object-space origin, tessellated
    /// where the scene is built (`geometry::Quadric::tessellate`).
    Quadric(Quadric),
    /// pbrt-v4 curves: cubic Bézier segments in object space.
    Curves(Arc<crate::geometry::Curves>),
}

/// An AreaLightSource in effect for a shape.
#[derive(Clone, Debug)]
pub struct AreaLightDesc {
    /// "diffuse".
    pub kind: &'static str,
    /// Its parameters ("L", "scale", "twosided", "power", "filename").
    pub params: ParamSet,
    /// Where it was written.
    pub loc: Location,
}

/// A Shape directive.
#[derive(Clone, Debug)]
pub struct ShapeDesc {
    /// Shape type as written ("plymesh", "sphere", ...).
    pub kind: &'static str,
    /// Its parameters (geometry parameters are already marked used; "alpha" etc. remain).
    pub params: ParamSet,
    /// The loaded geometry in object space.
    pub geometry: ShapeGeometry,
    /// World from object (inside ObjectBegin: instance space from object); for a moving shape,
    /// at the start time.
    pub world_from_object: Mat4,
    /// The motion from `world_from_object` to the end transform, for a moving shape (boxed: most
    /// shapes do not move, and a description holds one `ShapeDesc` per Shape directive).
    pub motion: Option<Box<AnimatedTransform>>,
    /// ReverseOrientation was in effect: flip the normals (pbrt-v4 semantics).
    pub reverse_orientation: bool,
    /// The material in effect.
    pub material: MaterialRef,
    /// The area light in effect, if any (never set inside object definitions; boxed like
    /// `motion`, as most shapes emit nothing).
    pub area_light: Option<Box<AreaLightDesc>>,
    /// The media on either side.
    pub media: MediumNames,
    /// Where it was written.
    pub loc: Location,
}

/// A LightSource directive.
#[derive(Clone, Debug)]
pub struct LightDesc {
    /// Light type ("point", "spot", "distant", "infinite").
    pub kind: &'static str,
    /// Its parameters.
    pub params: ParamSet,
    /// World from light space.
    pub world_from_light: Mat4,
    /// The medium it sits in: the current outside medium at the directive ("": vacuum).
    pub medium: String,
    /// Where it was written.
    pub loc: Location,
}

/// An ObjectBegin/ObjectEnd block.
#[derive(Clone, Debug)]
pub struct ObjectDesc {
    /// The object's name.
    pub name: String,
    /// Its shapes; their `world_from_object` maps to instance space.
    pub shapes: Vec<ShapeDesc>,
    /// Where ObjectBegin was written.
    pub loc: Location,
}

/// An ObjectInstance directive.
#[derive(Clone, Debug)]
pub struct InstanceDesc {
    /// The instanced object's name.
    pub object: String,
    /// Index into [`SceneDesc::objects`].
    pub object_index: usize,
    /// World from instance space: a shape's world transform is
    /// `world_from_instance * shape.world_from_object`.
    pub world_from_instance: Mat4,
    /// The motion from `world_from_instance` to the end transform, for a moving instance.
    pub motion: Option<AnimatedTransform>,
    /// Where it was written.
    pub loc: Location,
}

/// Everything a scene file describes.
#[derive(Clone, Debug)]
pub struct SceneDesc {
    /// Camera (default: "perspective", identity transform).
    pub camera: CameraDesc,
    /// Film (default "rgb").
    pub film: Directive,
    /// Sampler (default "zsobol").
    pub sampler: Directive,
    /// Integrator (default "path"; pbrt-v4 names prism lacks become "path").
    pub integrator: Directive,
    /// PixelFilter (default "gaussian").
    pub filter: Directive,
    /// Accelerator, if given (prism picks its own BVH; kept for reference).
    pub accelerator: Option<Directive>,
    /// The ColorSpace in effect at WorldBegin ("srgb" by default).
    pub color_space: String,
    /// All Option directives merged (e.g. "bool disablepixeljitter", "integer seed").
    pub options: ParamSet,
    /// Shapes outside object definitions.
    pub shapes: Vec<ShapeDesc>,
    /// Non-area lights.
    pub lights: Vec<LightDesc>,
    /// Anonymous materials, referenced by [`MaterialRef::Anonymous`].
    pub materials: Vec<MaterialDesc>,
    /// Named materials in definition order.
    pub named_materials: Vec<NamedMaterial>,
    /// Textures in definition order (a later one with the same name and class replaces).
    pub textures: Vec<TextureDesc>,
    /// Object definitions.
    pub objects: Vec<ObjectDesc>,
    /// Object instances.
    pub instances: Vec<InstanceDesc>,
    /// Named media in definition order (a later one with the same name replaces).
    pub media: Vec<MediumDesc>,
    /// The scene files read: the one parsed, then every Include/Import (empty for parsed text).
    pub scene_files: Vec<PathBuf>,
}

impl SceneDesc {
    /// The named material `name` (a scan of every definition; translating a whole scene
    /// resolves names through an index instead).
    pub fn named_material(&self, name: &str) -> Option<&MaterialDesc> {
        self.named_materials.iter().find(|m| *m.name == *name).map(|m| &m.material)
    }

    /// The material a reference points at (`None` for [`MaterialRef::Default`]).
    pub fn material(&self, r: &MaterialRef) -> Option<&MaterialDesc> {
        match r {
            MaterialRef::Default => None,
            MaterialRef::Anonymous(i) => self.materials.get(*i),
            MaterialRef::Named(_, i) => self.named_materials.get(*i).map(|m| &m.material),
        }
    }

    /// The object definition called `name` (a scan; [`InstanceDesc::object_index`] is direct).
    pub fn object(&self, name: &str) -> Option<&ObjectDesc> {
        self.objects.iter().find(|o| o.name == name)
    }

    /// The texture `name` of class `class` (the last definition wins, as in pbrt-v4; a scan of
    /// every definition).
    pub fn texture(&self, name: &str, class: TextureClass) -> Option<&TextureDesc> {
        self.textures.iter().rev().find(|t| *t.name == *name && t.class == class)
    }

    /// Every file rendering this scene reads, each once in first-use order: the scene files,
    /// then the data files parameters name (meshes, images, spectra, media). The Film's "filename" is
    /// where the image goes, so it is left out.
    pub fn input_files(&self) -> Vec<PathBuf> {
        let shapes = self.shapes.iter().chain(self.objects.iter().flat_map(|o| o.shapes.iter()));
        let materials = self.materials.iter().chain(self.named_materials.iter().map(|n| &n.material));
        let sets = [&self.camera.directive.params, &self.sampler.params, &self.integrator.params, &self.filter.params]
            .into_iter()
            .chain(shapes.flat_map(|s| std::iter::once(&s.params).chain(s.area_light.as_ref().map(|a| &a.params))))
            .chain(self.lights.iter().map(|l| &l.params))
            .chain(materials.map(|m| &m.params))
            .chain(self.textures.iter().map(|t| &t.params))
            .chain(self.media.iter().map(|m| &m.params));
        let mut seen: HashSet<PathBuf> = self.scene_files.iter().cloned().collect();
        let mut files = self.scene_files.clone();
        for f in sets.flat_map(ParamSet::named_files) {
            if seen.insert(f.clone()) {
                files.push(f);
            }
        }
        files
    }

    /// Warnings for parameters nothing read; call after the scene builder has consumed the desc.
    pub fn report_unused(&self) -> Vec<Warning> {
        let mut w = Vec::new();
        let mut d =
            |ps: &ParamSet, what: &str, kind: &str| w.extend(ps.report_unused(format_args!("{what} \"{kind}\"")));
        d(&self.camera.directive.params, "Camera", &self.camera.directive.kind);
        for (name, x) in [
            ("Film", &self.film),
            ("Sampler", &self.sampler),
            ("Integrator", &self.integrator),
            ("PixelFilter", &self.filter),
        ] {
            d(&x.params, name, &x.kind);
        }
        let shapes = self.shapes.iter().chain(self.objects.iter().flat_map(|o| o.shapes.iter()));
        // Every shape under one AreaLightSource carries its own copy of the parameters: report
        // each directive once, naming only parameters that no shape's copy used.
        let mut area_lights: Vec<(&AreaLightDesc, Vec<&ParamSet>)> = Vec::new();
        let mut area_light_at: HashMap<&Location, usize> = HashMap::default();
        for s in shapes {
            d(&s.params, "Shape", s.kind);
            if let Some(a) = &s.area_light {
                match area_light_at.get(&a.loc) {
                    Some(&i) => area_lights[i].1.push(&a.params),
                    None => {
                        area_light_at.insert(&a.loc, area_lights.len());
                        area_lights.push((a, vec![&a.params]));
                    }
                }
            }
        }
        for (a, copies) in area_lights {
            let mut unused = ParamSet::new(a.params.color_space);
            for (j, p) in a.params.iter().enumerate() {
                if copies.iter().all(|c| c.iter().nth(j).is_some_and(|q| !q.is_used())) {
                    unused.push(p.clone()).expect("names are unique in the original set");
                }
            }
            d(&unused, "AreaLightSource", a.kind);
        }
        for l in &self.lights {
            d(&l.params, "LightSource", l.kind);
        }
        // Materials no shape uses are never built (a shared library of named materials is
        // normal, and an anonymous Material may be replaced before any shape), so only
        // referenced ones can have unread parameters worth reporting.
        let all_shapes = self.shapes.iter().chain(self.objects.iter().flat_map(|o| o.shapes.iter()));
        let (mut used, mut used_anonymous) = (vec![false; self.named_materials.len()], HashSet::default());
        for s in all_shapes {
            match &s.material {
                MaterialRef::Named(_, i) => {
                    if let Some(u) = used.get_mut(*i) {
                        *u = true;
                    }
                }
                MaterialRef::Anonymous(i) => {
                    used_anonymous.insert(*i);
                }
                MaterialRef::Default => {}
            }
        }
        for (i, m) in self.materials.iter().enumerate() {
            if used_anonymous.contains(&i) {
                d(&m.params, "Material", m.kind);
            }
        }
        for (m, used) in self.named_materials.iter().zip(used) {
            if used {
                d(&m.material.params, "MakeNamedMaterial", &m.name);
            }
        }
        for t in &self.textures {
            d(&t.params, "Texture", &t.name);
        }
        for m in &self.media {
            d(&m.params, "MakeNamedMedium", &m.name);
        }
        w
    }
}
