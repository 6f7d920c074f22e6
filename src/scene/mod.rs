//! Scenes: a builder that collects meshes, materials and lights (from the built-in Cornell box or
//! a pbrt-v4 file read by [`crate::pbrt`]), and the render-ready [`Scene`]: its accelerator over
//! [`Primitive`]s, which bind geometry to material, emission and media.

mod cornell;
mod interaction;
mod mesh_lights;
mod primitive;

pub use cornell::add_cornell_box;
pub use interaction::SurfaceInteraction;
pub use primitive::{MediumInterface, Primitive};

use crate::accel::{self, Accel, AccelKind};
use crate::camera::{Camera, Projection, RealisticLens};
use crate::geometry::{
    AnimatedTransform, Bounds3, Curves, Hit, Instance, InstanceSet, Mesh, Motion, PlacedQuadric, Prototype, Ray, Shape,
};
use crate::light::{
    EmissionImage, Light, LightSampleContext, LightSampler, LightSamplerKind, QuadricLight, SphereLight,
};
use crate::material::{FloatTexture, Material};
use crate::media::Medium;
use crate::spectrum::Spectrum;
use glam::{Mat4, Vec2, Vec3};
use mesh_lights::{push_mesh_lights, LightsOf};
use std::sync::Arc;

/// Emission of an area light attached to a mesh: radiance `scale · spectrum(λ)`, or `scale`
/// times an image looked up at the surface's (u, v) when [`SceneBuilder::set_emission_image`]
/// gives one (`spectrum` is then the colour space's white, for the power).
#[derive(Clone, Debug)]
pub struct Emission {
    /// Spectral shape.
    pub spectrum: Spectrum,
    /// Multiplier to radiance [W/(sr·m²·nm)].
    pub scale: f32,
    /// Emits from both sides.
    pub two_sided: bool,
}

/// Camera parameters independent of the image resolution.
#[derive(Clone, Debug)]
pub struct CameraDesc {
    /// Camera space → world space (for a moving camera: at the start of its motion).
    pub camera_to_world: Mat4,
    /// The camera's motion, camera space → world space over time (`None`: it does not move).
    pub motion: Option<AnimatedTransform>,
    /// Field of view along the shorter image axis [degrees].
    pub fov_deg: f32,
    /// Thin-lens radius (0: pinhole).
    pub lens_radius: f32,
    /// Focal distance.
    pub focal_distance: f32,
    /// Optional screen window.
    pub screen_window: Option<[f32; 4]>,
    /// Perspective, orthographic, spherical or realistic.
    pub projection: Projection,
    /// A realistic camera's lens (`None` for the others).
    pub lens: Option<Arc<RealisticLens>>,
}

impl CameraDesc {
    /// The matrices pbrt-v4 writes into an OpenEXR header, each mapping a point (a column
    /// vector) from world space: to camera space at `time` (`worldToCamera`), and, for the
    /// perspective and orthographic cameras, to [`crate::camera::ndc`] (`worldToNDC`).
    pub fn header_matrices(&self, time: f32) -> (Mat4, Option<Mat4>) {
        let camera_from_world =
            crate::camera::CameraTransform::new(self.camera_to_world, self.motion).camera_from_world(time);
        let ndc = crate::camera::ndc::ndc_from_camera(self.projection, self.fov_deg).map(|m| m * camera_from_world);
        (camera_from_world, ndc)
    }

    /// The camera for an image of `resolution`.
    pub fn camera(&self, resolution: (u32, u32)) -> Camera {
        let (m, lens, focus, window) =
            (self.camera_to_world, self.lens_radius, self.focal_distance, self.screen_window);
        let camera = match self.projection {
            Projection::Perspective => Camera::perspective(m, resolution, self.fov_deg, lens, focus, window),
            Projection::Orthographic => Camera::orthographic(m, resolution, lens, focus, window),
            Projection::Realistic => match &self.lens {
                Some(l) => Camera::realistic(m, resolution, l.clone()),
                None => Camera::perspective(m, resolution, self.fov_deg, lens, focus, window),
            },
            spherical => Camera::spherical(m, resolution, spherical),
        };
        camera.with_motion(self.motion)
    }

    /// True when the camera moves during the shutter.
    pub fn moves(&self) -> bool {
        self.motion.is_some_and(|m| m.is_animated())
    }
}

/// Why a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The accelerator failed (e.g. Embree device creation).
    #[error(transparent)]
    Accel(#[from] accel::AccelError),
    /// No camera was given.
    #[error("the scene has no camera")]
    NoCamera,
}

/// One primitive while the scene is collected: geometry, material and emission, and the
/// prototype it belongs to when it is instanced.
struct PendingPrimitive {
    /// Triangles, curves or a quadric with its placement.
    shape: Shape,
    material: u32,
    emission: Option<Emission>,
    /// Cut-out mask (`None`: opaque).
    alpha: Option<FloatTexture>,
    /// The media on either side.
    medium_interface: MediumInterface,
    /// Its prototype (`None`: placed in the world as it is).
    prototype: Option<u32>,
    /// The image its emission shows, if any.
    emission_image: Option<Arc<EmissionImage>>,
    /// Its emission's scale is per unit area: each triangle's is divided by its face's area.
    emission_per_area: bool,
}

/// Collects a scene's parts before the accelerator is built.
#[derive(Default)]
pub struct SceneBuilder {
    primitives: Vec<PendingPrimitive>,
    prototypes: Vec<Prototype>,
    instances: Vec<Instance>,
    materials: Vec<Material>,
    lights: Vec<Light>,
    /// The medium each light of `lights` sits in (`None`: vacuum).
    light_media: Vec<Option<u32>>,
    camera: Option<CameraDesc>,
    media: Vec<Medium>,
    camera_medium: Option<u32>,
    light_sampler: LightSamplerKind,
    /// Rays the render expects to trace, if known ([`SceneBuilder::expect_rays`]).
    expected_rays: Option<u64>,
    /// The camera's shutter open and close times (`None`: pbrt-v4's default 0 and 1).
    shutter: Option<(f32, f32)>,
    /// Warnings collected while building (degenerate geometry, …).
    pub warnings: Vec<String>,
}

impl SceneBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    /// The built-in default scene (the Cornell box).
    pub fn cornell_box() -> Self {
        let mut b = Self::new();
        add_cornell_box(&mut b);
        b
    }

    /// Chooses the light sampler the scene builds (pbrt-v4's Integrator "lightsampler").
    pub fn set_light_sampler(&mut self, kind: LightSamplerKind) {
        self.light_sampler = kind;
    }

    /// Tells the accelerator build how many rays the render will trace (about; an upper
    /// bound is best): with few rays over many triangles a faster build of a slower BVH takes
    /// less time in all (`accel::build_scene_shared`). Unset, the build assumes many.
    pub fn expect_rays(&mut self, rays: u64) {
        self.expected_rays = Some(rays);
    }

    /// Adds a material, returning its id.
    pub fn add_material(&mut self, m: Material) -> u32 {
        self.materials.push(m);
        self.materials.len() as u32 - 1
    }

    /// Adds a mesh with a material and optional area emission as a primitive, returning its id.
    /// Triangles with non-finite vertices or zero area are dropped with one warning naming it.
    pub fn add_mesh(&mut self, mut mesh: Mesh, material: u32, emission: Option<Emission>) -> u32 {
        let id = self.primitives.len() as u32;
        let dropped = mesh.remove_degenerate();
        if dropped > 0 {
            self.warnings
                .push(format!("mesh {id}: skipped {dropped} degenerate triangle(s) (zero or overflowing area, or vertices not finite or beyond ±1e18)"));
        }
        self.push_primitive(Shape::Mesh(mesh), material, emission)
    }

    /// Adds `shape` with a material and optional area emission as a primitive, returning its id.
    fn push_primitive(&mut self, shape: Shape, material: u32, emission: Option<Emission>) -> u32 {
        let id = self.primitives.len() as u32;
        self.primitives.push(PendingPrimitive {
            shape,
            material,
            emission,
            alpha: None,
            medium_interface: MediumInterface::default(),
            prototype: None,
            emission_image: None,
            emission_per_area: false,
        });
        id
    }

    /// Adds curves (world space) with a material as a primitive, returning its id. Curves do not
    /// emit.
    pub fn add_curves(&mut self, curves: Curves, material: u32) -> u32 {
        self.push_primitive(Shape::Curves(Arc::new(curves)), material, None)
    }

    /// Adds a quadric with its placement, a material and optional area emission as a
    /// primitive, returning its id. An emissive full sphere under a static similarity becomes
    /// one [`SphereLight`] sampled by solid angle; any other emissive quadric one
    /// [`QuadricLight`] sampled by area. (Emission images and moving emitters are not
    /// supported on quadrics: give those as meshes.)
    pub fn add_quadric(&mut self, quadric: PlacedQuadric, material: u32, emission: Option<Emission>) -> u32 {
        self.push_primitive(Shape::Quadric(Arc::new(quadric)), material, emission)
    }

    /// Gives primitive `id` a cut-out mask (pbrt-v4's shape `alpha`): where it evaluates to a < 1
    /// a ray passes through with probability 1 − a. A constant 1 (or more) is opaque and stores
    /// nothing.
    pub fn set_alpha(&mut self, id: u32, alpha: FloatTexture) {
        if matches!(alpha, FloatTexture::Constant(a) if a >= 1.0) {
            return;
        }
        if let Some(p) = self.primitives.get_mut(id as usize) {
            p.alpha = Some(alpha);
        }
    }

    /// Makes emissive primitive `id` show `image` at its surface's (u, v) in place of its
    /// emission's spectrum (pbrt-v4 `DiffuseAreaLight` with "filename").
    pub fn set_emission_image(&mut self, id: u32, image: Arc<EmissionImage>) {
        if let Some(p) = self.primitives.get_mut(id as usize) {
            p.emission_image = Some(image);
        }
    }

    /// Makes each triangle of emissive primitive `id` emit its emission's scale divided by the
    /// area of its face [scene units²] (`Mesh::faces`): pbrt-v4's `power` given to each face of a
    /// mesh, a triangle or a bilinear patch.
    pub fn set_emission_per_face_area(&mut self, id: u32) {
        if let Some(p) = self.primitives.get_mut(id as usize) {
            p.emission_per_area = true;
        }
    }

    /// Adds a participating medium, returning its id for [`MediumInterface`]s.
    pub fn add_medium(&mut self, m: Medium) -> u32 {
        self.media.push(m);
        self.media.len() as u32 - 1
    }

    /// Sets the media inside and outside primitive `id`.
    pub fn set_medium_interface(&mut self, id: u32, mi: MediumInterface) {
        if let Some(p) = self.primitives.get_mut(id as usize) {
            p.medium_interface = mi;
        }
    }

    /// Sets the medium the camera sits in (`None`: vacuum).
    pub fn set_camera_medium(&mut self, medium: Option<u32>) {
        self.camera_medium = medium;
    }

    /// The primitive ids of prototype `proto`'s meshes, in the order they were given.
    pub fn prototype_meshes(&self, proto: u32) -> &[u32] {
        self.prototypes.get(proto as usize).map_or(&[], |p| p.meshes.as_slice())
    }

    /// Adds a prototype: meshes in object space, each with its material (no emission: pbrt-v4
    /// does not instance area lights). Returns its id for [`SceneBuilder::add_instance`].
    pub fn add_prototype(&mut self, meshes: Vec<(Mesh, u32)>) -> u32 {
        let proto = self.new_prototype();
        for (mesh, material) in meshes {
            let id = self.add_mesh(mesh, material, None);
            self.add_to_prototype(proto, id);
        }
        proto
    }

    /// Adds an empty prototype, returning its id for [`SceneBuilder::add_to_prototype`].
    pub fn new_prototype(&mut self) -> u32 {
        self.prototypes.push(Prototype::default());
        self.prototypes.len() as u32 - 1
    }

    /// Moves primitive `id` — a mesh, curves or a static quadric, in object space — from the
    /// world into prototype `proto`. An emissive primitive (pbrt-v4 does not instance area
    /// lights), a moving quadric (a moving shape is a prototype of its own under a moving
    /// instance), one already in a prototype, or an unknown id stays where it is: false with a
    /// warning.
    pub fn add_to_prototype(&mut self, proto: u32, id: u32) -> bool {
        let refused = match self.primitives.get(id as usize) {
            _ if proto as usize >= self.prototypes.len() => Some("unknown prototype"),
            None => Some("unknown primitive"),
            Some(p) if p.emission.is_some() => Some("it emits"),
            Some(p) if matches!(&p.shape, Shape::Quadric(q) if q.moves()) => Some("it moves"),
            Some(p) if p.prototype.is_some() => Some("it is in a prototype already"),
            Some(_) => None,
        };
        if let Some(why) = refused {
            self.warnings.push(format!("primitive {id} not added to prototype {proto}: {why}"));
            return false;
        }
        self.primitives[id as usize].prototype = Some(proto);
        self.prototypes[proto as usize].meshes.push(id);
        true
    }

    /// Places prototype `prototype` at `world_from_object`. A singular or non-finite transform
    /// (or an unknown prototype) places nothing and returns false with a warning.
    pub fn add_instance(&mut self, prototype: u32, world_from_object: Mat4) -> bool {
        self.place(prototype, Instance::new(prototype, world_from_object))
    }

    /// Places prototype `prototype` moving by `motion` (static when it does not move); false
    /// with a warning as [`SceneBuilder::add_instance`].
    pub fn add_moving_instance(&mut self, prototype: u32, motion: impl Into<Motion>) -> bool {
        self.place(prototype, Instance::moving(prototype, motion.into()))
    }

    /// Sets the camera's shutter open and close times, in the time units of the instances'
    /// motions (rays sample times uniformly between them).
    pub fn set_shutter(&mut self, open: f32, close: f32) {
        self.shutter = Some((open, close.max(open)));
    }

    fn place(&mut self, prototype: u32, instance: Option<Instance>) -> bool {
        if prototype as usize >= self.prototypes.len() {
            self.warnings.push(format!("instance of unknown prototype {prototype} skipped"));
            return false;
        }
        match instance {
            Some(i) => {
                self.instances.push(i);
                true
            }
            None => {
                self.warnings.push(format!(
                    "instance {} of prototype {prototype}: singular or non-finite transform; skipped",
                    self.instances.len()
                ));
                false
            }
        }
    }

    /// Moves every non-emissive world primitive into one new prototype placed once at the
    /// identity (so that `transform` then moves it as an instance); returns the prototype, or
    /// `None` when there was nothing to move. Lets tests trace any scene through the instancing
    /// paths.
    pub fn instance_world_geometry(&mut self) -> Option<u32> {
        let proto = self.prototypes.len() as u32;
        let ids: Vec<u32> = (0..self.primitives.len() as u32)
            .filter(|&m| {
                let p = &self.primitives[m as usize];
                p.prototype.is_none() && p.emission.is_none() && matches!(p.shape, Shape::Mesh(_))
            })
            .collect();
        if ids.is_empty() {
            return None;
        }
        for &m in &ids {
            self.primitives[m as usize].prototype = Some(proto);
        }
        self.prototypes.push(Prototype { meshes: ids });
        self.add_instance(proto, Mat4::IDENTITY).then_some(proto)
    }

    /// Number of instances placed so far.
    pub fn instance_count(&self) -> usize {
        self.instances.len()
    }

    /// Replaces every instance by world-space copies of its prototype's primitives (the
    /// reference that instancing must reproduce): meshes, curves and quadrics, with their
    /// materials, alpha masks and media, each at its instance's start placement; the
    /// prototypes' own primitives become empty.
    pub fn flatten_instances(&mut self) {
        for inst in std::mem::take(&mut self.instances) {
            let m = inst.world_from_object;
            for &id in &self.prototypes[inst.prototype as usize].meshes.clone() {
                let p = &self.primitives[id as usize];
                let (material, mi, alpha) = (p.material, p.medium_interface, p.alpha.clone());
                let copy = match &p.shape {
                    Shape::Mesh(mesh) => {
                        let mesh = mesh.transformed(&m);
                        self.add_mesh(mesh, material, None)
                    }
                    Shape::Curves(c) => {
                        let c = c.transformed(&m);
                        self.add_curves(c, material)
                    }
                    Shape::Quadric(q) => match q.placed_by(&m) {
                        Some(q) => self.add_quadric(q, material, None),
                        None => continue,
                    },
                };
                self.set_medium_interface(copy, mi);
                self.primitives[copy as usize].alpha = alpha;
            }
        }
        for proto in std::mem::take(&mut self.prototypes) {
            for m in proto.meshes {
                let p = &mut self.primitives[m as usize];
                p.shape = Shape::default();
                p.prototype = None;
            }
        }
    }

    /// Adds a light that is not attached to geometry.
    pub fn add_light(&mut self, l: Light) {
        self.lights.push(l);
        self.light_media.push(None);
    }

    /// The number of lights not attached to geometry added so far.
    pub fn light_count(&self) -> usize {
        self.lights.len()
    }

    /// Places the lights added since the first `first` in `medium` (pbrt-v4: the current
    /// outside medium at the LightSource directive).
    pub fn set_medium_of_lights_from(&mut self, first: usize, medium: Option<u32>) {
        for m in self.light_media.iter_mut().skip(first) {
            *m = medium;
        }
    }

    /// Sets a pinhole camera.
    pub fn set_camera(&mut self, camera_to_world: Mat4, fov_deg: f32) {
        self.camera = Some(CameraDesc {
            camera_to_world,
            motion: None,
            fov_deg,
            lens_radius: 0.0,
            focal_distance: 1e6,
            screen_window: None,
            projection: Projection::Perspective,
            lens: None,
        });
    }

    /// Sets a full camera description.
    pub fn set_camera_desc(&mut self, c: CameraDesc) {
        self.camera = Some(c);
    }

    /// Applies `m` (a similarity: rotation, uniform scale, translation) to all geometry, lights
    /// and the camera. Used to test that nothing depends on the scene's scale or position.
    pub fn transform(&mut self, m: Mat4) {
        let scale = m.transform_vector3(Vec3::X).length();
        for p in self.primitives.iter_mut().filter(|p| p.prototype.is_none()) {
            match &mut p.shape {
                Shape::Mesh(mesh) => *mesh = mesh.transformed(&m),
                Shape::Curves(c) => *c = Arc::new(c.transformed(&m)),
                Shape::Quadric(q) => {
                    let mut placed = PlacedQuadric::clone(q);
                    placed.placement = placed.placement.then(m).expect("a similarity keeps it invertible");
                    *q = Arc::new(placed);
                }
            }
        }
        for inst in self.instances.iter_mut() {
            *inst = inst.then(m).expect("a similarity keeps it invertible");
        }
        if let Some(c) = self.camera.as_mut() {
            // Keep the camera frame orthonormal: move the origin, rotate the axes, do not scale.
            let unscale = Mat4::from_scale(Vec3::splat(1.0 / scale));
            c.camera_to_world = m * c.camera_to_world * unscale;
            c.motion = c
                .motion
                .map(|a| AnimatedTransform::new(m * a.start * unscale, a.start_time, m * a.end * unscale, a.end_time));
            c.focal_distance *= scale;
            c.lens_radius *= scale;
        }
        assert!(self.lights.is_empty(), "SceneBuilder::transform: transform lights before adding them");
    }

    /// Builds the accelerator, the area lights and the primitives.
    pub fn build(self, accel_kind: AccelKind) -> Result<Scene, BuildError> {
        let camera = self.camera.ok_or(BuildError::NoCamera)?;
        let world_meshes =
            (0..self.primitives.len() as u32).filter(|&m| self.primitives[m as usize].prototype.is_none()).collect();
        // The triangles move into one table indexed by primitive id (empty for curves and
        // quadrics), which the scene and the accelerator share; the primitives keep the rest.
        let mut pending = self.primitives;
        let mut meshes: Vec<Mesh> = pending
            .iter_mut()
            .map(|p| match &mut p.shape {
                Shape::Mesh(mesh) => std::mem::take(mesh),
                Shape::Curves(_) | Shape::Quadric(_) => Mesh::default(),
            })
            .collect();
        let mut lights = self.lights;
        let mut light_media: Vec<MediumInterface> =
            self.light_media.iter().map(|&m| MediumInterface { inside: m, outside: m }).collect();
        let mut primitives = Vec::with_capacity(meshes.len());
        for (p, mesh) in pending.into_iter().zip(meshes.iter_mut()) {
            let PendingPrimitive {
                shape,
                material,
                emission,
                alpha,
                medium_interface,
                emission_image,
                emission_per_area,
                ..
            } = p;
            let mut lights_of = LightsOf::Triangles;
            let area_lights = emission.and_then(|em| {
                let first = lights.len() as u32;
                lights_of = match &shape {
                    Shape::Mesh(_) => {
                        push_mesh_lights(mesh, &em, emission_image.as_ref(), emission_per_area, &mut lights)
                    }
                    // A quadric is one light: a sphere light for a full sphere, else sampled by area.
                    Shape::Quadric(q) => {
                        lights.push(quadric_light(q, Arc::new(em.spectrum), em.scale, em.two_sided));
                        LightsOf::Whole
                    }
                    // Curves never emit (`add_curves` gives them no emission).
                    Shape::Curves(_) => return None,
                };
                Some(first)
            });
            // An area light emits into the media on either side of its shape.
            light_media.resize(lights.len(), medium_interface);
            // Faces matter only to the emission above.
            mesh.faces = None;
            // Room for Embree's 16-byte load at the last vertex, so it can read them in place.
            if !mesh.is_empty() {
                mesh.positions.reserve_exact(1);
            }
            let bare_boundary = matches!(self.materials[material as usize], Material::Interface)
                && area_lights.is_none()
                && alpha.is_none();
            primitives.push(Primitive {
                shape,
                material,
                area_lights,
                lights_of,
                medium_interface,
                alpha,
                bare_boundary,
            });
        }
        let meshes: Arc<[Mesh]> = meshes.into();
        let mut curves: Vec<(u32, &Curves)> = Vec::new();
        let mut placed: Vec<(u32, &PlacedQuadric)> = Vec::new();
        for (id, p) in primitives.iter().enumerate() {
            match &p.shape {
                Shape::Mesh(_) => {}
                Shape::Curves(c) => curves.push((id as u32, c)),
                Shape::Quadric(q) => placed.push((id as u32, q)),
            }
        }
        let extra = accel::ExtraShapes { curves: &curves, quadrics: &placed };
        let set = InstanceSet { world_meshes, prototypes: self.prototypes, instances: self.instances };
        let accel = accel::build_scene_shared(accel_kind, &meshes, extra, &set, self.expected_rays)?;
        let quadric_moves = placed.iter().any(|(_, q)| q.moves());
        let has_alpha = primitives.iter().any(|p| p.alpha.is_some());
        let bounds = accel.bounds();
        let radius = if bounds.is_empty() { 1.0 } else { bounds.radius().max(1e-6) };
        let light_sampler = LightSampler::new(self.light_sampler, &lights, radius);
        let emitter_sampler = LightSampler::new(LightSamplerKind::Power, &lights, radius);
        let infinite_lights =
            lights.iter().enumerate().filter(|(_, l)| l.is_infinite()).map(|(i, _)| i as u32).collect();
        let has_interfaces = self.materials.iter().any(Material::may_be_interface);
        let moves = quadric_moves || set.instances.iter().any(|i| i.motion.is_some()) || camera.moves();
        let shutter = moves.then(|| self.shutter.unwrap_or((0.0, 1.0)));
        let object_radii = object_radii(&self.materials, &primitives, &meshes);
        let thin_subsurface = self
            .materials
            .iter()
            .zip(&object_radii)
            .any(|(m, &r)| m.subsurface().is_some_and(|s| s.longest_mean_free_path() > 0.5 * r));
        Ok(Scene {
            has_interfaces,
            has_alpha,
            accel,
            primitives,
            meshes,
            instances: set.instances,
            materials: self.materials,
            lights,
            light_media,
            infinite_lights,
            light_sampler,
            emitter_sampler,
            camera,
            scene_center: if bounds.is_empty() { Vec3::ZERO } else { bounds.center() },
            scene_radius: radius,
            media: self.media,
            camera_medium: self.camera_medium,
            shutter,
            object_radii,
            thin_subsurface,
        })
    }
}

/// Per material, the largest bounding-sphere radius of the primitives made of it; computed for
/// subsurface materials only (whose method choice needs it), 0 for the others.
fn object_radii(materials: &[Material], primitives: &[Primitive], meshes: &[Mesh]) -> Vec<f32> {
    let mut radii = vec![0.0f32; materials.len()];
    if !materials.iter().any(|m| m.subsurface().is_some()) {
        return radii;
    }
    for (p, mesh) in primitives
        .iter()
        .zip(meshes)
        .filter(|(p, _)| materials.get(p.material as usize).is_some_and(|m| m.subsurface().is_some()))
    {
        let b = match &p.shape {
            Shape::Mesh(_) => mesh.bounds(),
            Shape::Quadric(q) => q.bounds(),
            // Curves count for nothing here.
            Shape::Curves(_) => Bounds3::EMPTY,
        };
        if !b.is_empty() {
            let r = &mut radii[p.material as usize];
            *r = r.max(b.radius());
        }
    }
    radii
}

/// The light of radiance `scale · spectrum` on an emissive quadric: a [`SphereLight`] for a
/// full sphere under a similarity (emitting inward when its normal is reversed), a
/// [`QuadricLight`] sampled by area otherwise.
fn quadric_light(q: &PlacedQuadric, spectrum: Arc<Spectrum>, scale: f32, two_sided: bool) -> Light {
    match q.full_sphere() {
        Some((center, radius)) => {
            Light::Sphere(SphereLight { center, radius, spectrum, scale, two_sided, inward: q.flip_normal })
        }
        None => Light::Quadric(Box::new(QuadricLight { shape: q.clone(), area: q.area(), spectrum, scale, two_sided })),
    }
}

/// A scene ready to render: the integrator traces rays through it ([`Scene::intersect`],
/// [`Scene::occluded`]) and asks the returned [`SurfaceInteraction`] for the material and
/// emission at the hit; lights are reached through the light sampler.
pub struct Scene {
    accel: Box<dyn Accel>,
    /// Geometry with its material, emission and media (a hit's `geom_id` indexes this). A
    /// mesh primitive's triangles are in `meshes`; its `Shape::Mesh` is left empty.
    primitives: Vec<Primitive>,
    /// The triangles of each primitive (by `geom_id`; empty for curves and quadrics), shared
    /// with the accelerator, which may trace them in place.
    meshes: Arc<[Mesh]>,
    /// Object instances (`Hit::inst_id` indexes this); their primitives are in object space.
    instances: Vec<Instance>,
    materials: Vec<Material>,
    /// All lights (area lights one per emissive triangle, or one per emissive full sphere).
    lights: Vec<Light>,
    /// Per light, the media on either side of it (the same on both for a light not attached to
    /// geometry).
    light_media: Vec<MediumInterface>,
    /// Lights seen by rays that escape the scene.
    infinite_lights: Vec<u32>,
    /// Light choice for next-event estimation.
    light_sampler: LightSampler,
    /// Light choice for paths that start at the lights: in proportion to power, as pbrt-v4's
    /// bidirectional integrators choose.
    emitter_sampler: LightSampler,
    /// The camera.
    pub camera: CameraDesc,
    /// Centre of the scene bounds.
    pub scene_center: Vec3,
    /// Radius of the scene's bounding sphere.
    pub scene_radius: f32,
    /// Some material is an interface, so shadow rays must look past the surfaces they hit.
    has_interfaces: bool,
    /// Some primitive has an alpha mask, so every hit must be tested against it.
    has_alpha: bool,
    /// Participating media (a [`MediumInterface`] indexes them).
    media: Vec<Medium>,
    /// The medium the camera sits in.
    camera_medium: Option<u32>,
    /// The shutter open and close times when something in the scene or the camera moves
    /// (`None`: every ray
    /// is at time 0 and the camera draws no time sample).
    pub shutter: Option<(f32, f32)>,
    /// Per material, the largest bounding-sphere radius of the primitives made of it, for
    /// subsurface materials (0 for the others) [scene units].
    object_radii: Vec<f32>,
    /// Some subsurface object may be optically thin: its material's longest mean free path
    /// exceeds half its radius.
    thin_subsurface: bool,
}

/// Most interfaces a ray passes through before it is taken as blocked (a guard against
/// degenerate geometry that would trap a ray; real scenes nest a handful).
pub const MAX_INTERFACE_CROSSINGS: u32 = 256;

/// The boundaries between media a path has passed through without scattering, counted
/// against [`MAX_INTERFACE_CROSSINGS`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Crossings(u32);

impl Crossings {
    /// Counts one more crossing; false once there have been more than
    /// [`MAX_INTERFACE_CROSSINGS`], when the path is taken as blocked.
    #[inline]
    pub fn allow_another(&mut self) -> bool {
        self.0 += 1;
        self.0 <= MAX_INTERFACE_CROSSINGS
    }
}

impl Scene {
    /// The closest surface along `ray` (t in (0, ray.t_max]), with its shading geometry,
    /// material and emission.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction<'_>> {
        if self.has_alpha {
            return self.intersect_past_cut_outs(*ray);
        }
        self.accel.intersect(ray).map(|hit| SurfaceInteraction::new(self, ray, &hit))
    }

    /// The closest hit that its primitive's alpha mask keeps. Rejected hits lie at increasing
    /// distances, so continuing the ray past each finds the closest kept one; a ray the masks
    /// keep crossing is taken to escape after [`MAX_INTERFACE_CROSSINGS`] of them.
    #[inline(never)]
    fn intersect_past_cut_outs(&self, mut ray: Ray) -> Option<SurfaceInteraction<'_>> {
        for _ in 0..MAX_INTERFACE_CROSSINGS {
            let hit = self.accel.intersect(&ray)?;
            let si = SurfaceInteraction::new(self, &ray, &hit);
            if !si.is_cut_out(&ray) {
                return Some(si);
            }
            let t_left = ray.t_max - hit.t;
            ray = si.spawn_ray(ray.d);
            ray.t_max = t_left;
        }
        None
    }

    /// The closest hit record along `ray`, for callers that decide from its distance alone
    /// whether they need the interaction ([`Scene::interaction`]).
    #[inline]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        self.accel.intersect(ray)
    }

    /// Every hit along `ray` with t in (0, ray.t_max), in any order (BSSRDF probe rays).
    pub fn all_hits(&self, ray: &Ray, hits: &mut Vec<Hit>) {
        self.accel.intersect_all(ray, hits);
    }

    /// The interaction at `hit`, found along `ray`.
    #[inline]
    pub fn interaction(&self, ray: &Ray, hit: &Hit) -> SurfaceInteraction<'_> {
        SurfaceInteraction::new(self, ray, hit)
    }

    /// True when a surface blocks `ray` with t in (0, ray.t_max) (shadow rays). Interfaces and
    /// cut-outs block nothing: with any in the scene, the ray is traced from surface to surface
    /// past them (pbrt-v4's transmittance rays do the same); without, one occlusion query
    /// answers.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        if !(self.has_interfaces || self.has_alpha) {
            return self.accel.occluded(ray);
        }
        self.occluded_past_interfaces(*ray)
    }

    #[inline(never)]
    fn occluded_past_interfaces(&self, mut ray: Ray) -> bool {
        let end = if ray.t_max.is_finite() { Some(ray.at(ray.t_max)) } else { None };
        for _ in 0..MAX_INTERFACE_CROSSINGS {
            let Some(si) = self.intersect(&ray) else { return false };
            if !si.is_passthrough() {
                return true;
            }
            ray = match end {
                Some(end) => si.spawn_ray_to_point(end),
                None => si.spawn_ray(ray.d),
            };
        }
        true
    }

    /// The accelerator (its name and memory figures).
    pub fn accel(&self) -> &dyn Accel {
        self.accel.as_ref()
    }

    /// The primitives (a hit's `geom_id` indexes them).
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// The object instances (a hit's `inst_id` indexes them).
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// The materials (a primitive's `material` indexes them).
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Every light (area lights one per emissive triangle or full sphere), in the order the light sampler
    /// indexes them.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Number of distinct triangles (instanced ones counted once).
    pub fn triangle_count(&self) -> u64 {
        self.meshes.iter().map(|m| m.len() as u64).sum()
    }

    /// The triangles of primitive `id` (empty for curves and quadrics).
    pub fn mesh(&self, id: u32) -> &Mesh {
        &self.meshes[id as usize]
    }

    /// Bytes of prism's own triangle arrays (positions, indices, normals, texture
    /// coordinates), which Embree may read in place.
    pub fn mesh_bytes(&self) -> usize {
        self.meshes.iter().map(Mesh::bytes).sum()
    }

    /// Chooses a light for next-event estimation at `ctx` with the 2D uniform `u`: the light,
    /// the probability of choosing it, and the 2D uniform for sampling a point on it (`u.x`
    /// remapped within the chosen light's share, `u.y` as it was). One stratified 2D point thus
    /// spreads evenly over an emitter made of many triangles, where an independent choice of
    /// triangle would leave each triangle a random subset of the strata.
    #[inline]
    pub fn sample_light(&self, ctx: &LightSampleContext, u: Vec2) -> Option<(LightId, &Light, f32, Vec2)> {
        self.light_sampler.sample(ctx, u.x).map(|(i, pmf, ux)| (i as LightId, &self.lights[i], pmf, Vec2::new(ux, u.y)))
    }

    /// Probability with which [`Scene::sample_light`] chooses `light` at `ctx`, times the
    /// light's own solid-angle density of sampling `wi` from `ctx.p` (pbrt-v4
    /// `PMF(ctx, light) · PDF_Li(ctx, wi)`).
    #[inline]
    pub fn light_pdf(&self, light: LightId, ctx: &LightSampleContext, wi: Vec3) -> f32 {
        let pmf = self.light_sampler.pmf(ctx, light as usize);
        if pmf == 0.0 {
            return 0.0;
        }
        pmf * self.lights[light as usize].pdf_li(ctx, wi)
    }

    /// Chooses a light to start a path from, in proportion to its power, with `u` in [0, 1):
    /// the light, the probability of choosing it, and `u` rescaled to a fresh uniform.
    #[inline]
    pub fn sample_emitter(&self, u: f32) -> Option<(LightId, &Light, f32, f32)> {
        let anywhere = LightSampleContext::medium(Vec3::ZERO);
        self.emitter_sampler.sample(&anywhere, u).map(|(i, pmf, u)| (i as LightId, &self.lights[i], pmf, u))
    }

    /// Probability with which [`Scene::sample_emitter`] chooses `light`.
    #[inline]
    pub fn emitter_pmf(&self, light: LightId) -> f32 {
        self.emitter_sampler.pmf(&LightSampleContext::medium(Vec3::ZERO), light as usize)
    }

    /// The scene's bounding sphere, across which lights at infinity send the paths they start.
    pub fn sphere(&self) -> crate::light::SceneSphere {
        crate::light::SceneSphere { center: self.scene_center, radius: self.scene_radius }
    }

    /// The lights that rays escaping the scene see.
    pub fn infinite_lights(&self) -> impl Iterator<Item = (LightId, &Light)> + '_ {
        self.infinite_lights.iter().map(|&i| (i, &self.lights[i as usize]))
    }

    /// The largest bounding-sphere radius of the primitives made of subsurface material
    /// `material` [scene units], computed when the scene was built (0 for other materials).
    pub fn material_radius(&self, material: u32) -> f32 {
        self.object_radii.get(material as usize).copied().unwrap_or(0.0)
    }

    /// True when some material scatters below its surface.
    pub fn has_subsurface(&self) -> bool {
        self.materials.iter().any(|m| m.subsurface().is_some())
    }

    /// True when some subsurface object may be optically thin (its material's longest mean free
    /// path exceeds half its bounding radius), so that even the diffusion method may walk it.
    pub fn may_have_thin_subsurface(&self) -> bool {
        self.thin_subsurface
    }

    /// The participating media (a [`MediumInterface`] indexes them).
    pub fn media(&self) -> &[Medium] {
        &self.media
    }

    /// True when some material is an interface or some primitive has an alpha mask: a ray may
    /// then pass the first surface it hits.
    pub fn has_interfaces_or_cut_outs(&self) -> bool {
        self.has_interfaces || self.has_alpha
    }

    /// True when the scene has participating media (and needs the volumetric path tracer).
    pub fn has_media(&self) -> bool {
        !self.media.is_empty()
    }

    /// The medium the camera sits in (`None`: vacuum).
    pub fn camera_medium(&self) -> Option<u32> {
        self.camera_medium
    }

    /// The medium a ray leaving light `id` from a point with normal `n` (zero for a light at a
    /// point) along `d` starts in (pbrt-v4: the light's medium interface, its side chosen by
    /// the direction).
    pub fn light_medium(&self, id: LightId, n: Vec3, d: Vec3) -> Option<u32> {
        let mi = self.light_media.get(id as usize).copied().unwrap_or_default();
        mi.medium_toward(d, n, mi.outside)
    }

    /// True when some material disperses light (model only what the scene needs).
    pub fn has_dispersion(&self) -> bool {
        self.materials.iter().any(Material::is_dispersive)
    }
}

/// A light's index in the scene's light list: the handle the light sampler's pmf is keyed by.
pub type LightId = u32;
