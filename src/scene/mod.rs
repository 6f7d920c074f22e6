//! Scenes: a builder that collects meshes, materials and lights (from the built-in Cornell box or
//! a pbrt-v4 file), and the render-ready [`Scene`] with its accelerator.

mod cornell;
pub mod desc;
pub mod error;
pub mod instances;
mod interaction;
pub mod mesh_io;
pub mod names;
pub mod params;
pub mod parser;
pub mod pbrt;
pub mod shapes;
mod source;
pub mod tokenizer;

pub use cornell::add_cornell_box;
pub use desc::{
    AreaLightDesc, Directive, InstanceDesc, LightDesc, MaterialDesc, MaterialRef, NamedMaterial, ObjectDesc, SceneDesc,
    ShapeDesc, ShapeGeometry, TextureClass, TextureDesc,
};
pub use error::{Location, SceneError, Warning};
pub use instances::{Instance, InstanceSet, Prototype};
pub use interaction::SurfaceInteraction;
pub use params::{FloatOrTexture, ParamSet, ParamValue, SpectrumOrTexture, SpectrumParam};
pub use parser::{look_at, parse_file, parse_str, ParseOptions};

use crate::accel::{self, Accel, AccelKind};
use crate::camera::Camera;
use crate::geometry::Mesh;
use crate::light::{AreaLight, Light, LightSampler};
use crate::material::Material;
use crate::spectrum::Spectrum;
use glam::{Mat4, Vec3};
use std::sync::Arc;

/// Emission of an area light attached to a mesh: radiance `scale · spectrum(λ)`.
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
    /// Camera space → world space.
    pub camera_to_world: Mat4,
    /// Field of view along the shorter image axis [degrees].
    pub fov_deg: f32,
    /// Thin-lens radius (0: pinhole).
    pub lens_radius: f32,
    /// Focal distance.
    pub focal_distance: f32,
    /// Optional screen window.
    pub screen_window: Option<[f32; 4]>,
}

impl CameraDesc {
    /// The camera for an image of `resolution`.
    pub fn camera(&self, resolution: (u32, u32)) -> Camera {
        Camera::perspective(
            self.camera_to_world,
            resolution,
            self.fov_deg,
            self.lens_radius,
            self.focal_distance,
            self.screen_window,
        )
    }
}

/// Why a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The accelerator failed (e.g. Embree device creation).
    #[error("{0}")]
    Accel(String),
    /// No camera was given.
    #[error("the scene has no camera")]
    NoCamera,
}

/// Collects a scene's parts before the accelerator is built.
#[derive(Default)]
pub struct SceneBuilder {
    meshes: Vec<Mesh>,
    mesh_material: Vec<u32>,
    mesh_emission: Vec<Option<Emission>>,
    /// Prototype each mesh belongs to (`u32::MAX`: a world mesh).
    mesh_prototype: Vec<u32>,
    prototypes: Vec<Prototype>,
    instances: Vec<Instance>,
    materials: Vec<Material>,
    lights: Vec<Light>,
    camera: Option<CameraDesc>,
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

    /// Adds a material, returning its id.
    pub fn add_material(&mut self, m: Material) -> u32 {
        self.materials.push(m);
        self.materials.len() as u32 - 1
    }

    /// Adds a mesh with a material and optional area emission, returning its id. Triangles with
    /// non-finite vertices or zero area are dropped with one warning naming the mesh.
    pub fn add_mesh(&mut self, mut mesh: Mesh, material: u32, emission: Option<Emission>) -> u32 {
        let id = self.meshes.len() as u32;
        let dropped = mesh.remove_degenerate();
        if dropped > 0 {
            self.warnings
                .push(format!("mesh {id}: skipped {dropped} degenerate triangle(s) (zero area or NaN/Inf vertices)"));
        }
        self.meshes.push(mesh);
        self.mesh_material.push(material);
        self.mesh_emission.push(emission);
        self.mesh_prototype.push(u32::MAX);
        id
    }

    /// Adds a prototype: meshes in object space, each with its material (no emission: pbrt-v4
    /// does not instance area lights). Returns its id for [`SceneBuilder::add_instance`].
    pub fn add_prototype(&mut self, meshes: Vec<(Mesh, u32)>) -> u32 {
        let proto = self.prototypes.len() as u32;
        let mut ids = Vec::with_capacity(meshes.len());
        for (mesh, material) in meshes {
            let id = self.add_mesh(mesh, material, None);
            self.mesh_prototype[id as usize] = proto;
            ids.push(id);
        }
        self.prototypes.push(Prototype { meshes: ids });
        proto
    }

    /// Places prototype `prototype` at `world_from_object`. A singular or non-finite transform
    /// (or an unknown prototype) places nothing and returns false with a warning.
    pub fn add_instance(&mut self, prototype: u32, world_from_object: Mat4) -> bool {
        if prototype as usize >= self.prototypes.len() {
            self.warnings.push(format!("instance of unknown prototype {prototype} skipped"));
            return false;
        }
        match Instance::new(prototype, world_from_object) {
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

    /// Moves every non-emissive world mesh into one new prototype placed once at the identity
    /// (so that `transform` then moves it as an instance); returns the prototype, or `None` when
    /// there was nothing to move. Lets tests trace any scene through the instancing paths.
    pub fn instance_world_geometry(&mut self) -> Option<u32> {
        let proto = self.prototypes.len() as u32;
        let ids: Vec<u32> = (0..self.meshes.len() as u32)
            .filter(|&m| self.mesh_prototype[m as usize] == u32::MAX && self.mesh_emission[m as usize].is_none())
            .collect();
        if ids.is_empty() {
            return None;
        }
        for &m in &ids {
            self.mesh_prototype[m as usize] = proto;
        }
        self.prototypes.push(Prototype { meshes: ids });
        self.add_instance(proto, Mat4::IDENTITY).then_some(proto)
    }

    /// Number of instances placed so far.
    pub fn instance_count(&self) -> usize {
        self.instances.len()
    }

    /// Replaces every instance by world-space copies of its prototype's meshes (the reference
    /// that instancing must reproduce); the prototypes' own meshes become empty.
    pub fn flatten_instances(&mut self) {
        for inst in std::mem::take(&mut self.instances) {
            for &m in &self.prototypes[inst.prototype as usize].meshes.clone() {
                let copy = self.meshes[m as usize].transformed(&inst.world_from_object);
                self.add_mesh(copy, self.mesh_material[m as usize], None);
            }
        }
        for p in std::mem::take(&mut self.prototypes) {
            for m in p.meshes {
                self.meshes[m as usize] = Mesh::default();
                self.mesh_prototype[m as usize] = u32::MAX;
            }
        }
    }

    /// Adds a light that is not attached to geometry.
    pub fn add_light(&mut self, l: Light) {
        self.lights.push(l);
    }

    /// Sets a pinhole camera.
    pub fn set_camera(&mut self, camera_to_world: Mat4, fov_deg: f32) {
        self.camera =
            Some(CameraDesc { camera_to_world, fov_deg, lens_radius: 0.0, focal_distance: 1e6, screen_window: None });
    }

    /// Sets a full camera description.
    pub fn set_camera_desc(&mut self, c: CameraDesc) {
        self.camera = Some(c);
    }

    /// Applies `m` (a similarity: rotation, uniform scale, translation) to all geometry, lights
    /// and the camera. Used to test that nothing depends on the scene's scale or position.
    pub fn transform(&mut self, m: Mat4) {
        for (mesh, &proto) in self.meshes.iter_mut().zip(&self.mesh_prototype) {
            if proto == u32::MAX {
                *mesh = mesh.transformed(&m);
            }
        }
        for inst in self.instances.iter_mut() {
            *inst =
                Instance::new(inst.prototype, m * inst.world_from_object).expect("a similarity keeps it invertible");
        }
        if let Some(c) = self.camera.as_mut() {
            // Keep the camera frame orthonormal: move the origin, rotate the axes, do not scale.
            let scale = m.transform_vector3(Vec3::X).length();
            c.camera_to_world = m * c.camera_to_world * Mat4::from_scale(Vec3::splat(1.0 / scale));
            c.focal_distance *= scale;
            c.lens_radius *= scale;
        }
        assert!(self.lights.is_empty(), "SceneBuilder::transform: transform lights before adding them");
    }

    /// Builds the accelerator and the lights.
    pub fn build(self, accel_kind: AccelKind) -> Result<Scene, BuildError> {
        let camera = self.camera.ok_or(BuildError::NoCamera)?;
        let accel = if self.prototypes.is_empty() {
            accel::build(accel_kind, &self.meshes)
        } else {
            let set = InstanceSet {
                world_meshes: (0..self.meshes.len() as u32)
                    .filter(|&m| self.mesh_prototype[m as usize] == u32::MAX)
                    .collect(),
                prototypes: self.prototypes,
                instances: self.instances.clone(),
            };
            accel::build_instanced(accel_kind, &self.meshes, &set)
        }
        .map_err(BuildError::Accel)?;
        let mut lights = self.lights;
        let mut mesh_light_offset = vec![u32::MAX; self.meshes.len()];
        for (mi, (mesh, em)) in self.meshes.iter().zip(&self.mesh_emission).enumerate() {
            let Some(em) = em else { continue };
            mesh_light_offset[mi] = lights.len() as u32;
            let spectrum = Arc::new(em.spectrum.clone());
            for prim in 0..mesh.len() {
                let p = mesh.triangle(prim);
                let n = (p[1] - p[0]).cross(p[2] - p[0]);
                lights.push(Light::Area(AreaLight {
                    p,
                    n: n.normalize_or_zero(),
                    area: 0.5 * n.length(),
                    spectrum: spectrum.clone(),
                    scale: em.scale,
                    two_sided: em.two_sided,
                    mesh: mi as u32,
                    prim: prim as u32,
                }));
            }
        }
        let bounds = accel.bounds();
        let radius = if bounds.is_empty() { 1.0 } else { bounds.radius().max(1e-6) };
        let light_sampler = LightSampler::new(&lights, radius);
        let infinite_lights = lights.iter().enumerate().filter(|(_, l)| l.is_infinite()).map(|(i, _)| i).collect();
        Ok(Scene {
            accel,
            meshes: self.meshes,
            mesh_material: self.mesh_material,
            mesh_light_offset,
            instances: self.instances,
            materials: self.materials,
            lights,
            infinite_lights,
            light_sampler,
            camera,
            scene_center: if bounds.is_empty() { Vec3::ZERO } else { bounds.center() },
            scene_radius: radius,
        })
    }
}

/// A scene ready to render.
pub struct Scene {
    /// Ray intersection.
    pub accel: Box<dyn Accel>,
    /// Geometry (geometry id = index).
    pub meshes: Vec<Mesh>,
    /// Material id of each mesh.
    pub mesh_material: Vec<u32>,
    /// Index of the first area light of each emissive mesh (light of triangle i = offset + i),
    /// `u32::MAX` for meshes that do not emit.
    pub mesh_light_offset: Vec<u32>,
    /// Object instances (`Hit::inst_id` indexes this); their meshes are in object space.
    pub instances: Vec<Instance>,
    /// Materials.
    pub materials: Vec<Material>,
    /// All lights (area lights one per emissive triangle).
    pub lights: Vec<Light>,
    /// Indices of lights seen by rays that escape the scene.
    pub infinite_lights: Vec<usize>,
    /// Power-proportional light choice.
    pub light_sampler: LightSampler,
    /// The camera.
    pub camera: CameraDesc,
    /// Centre of the scene bounds.
    pub scene_center: Vec3,
    /// Radius of the scene's bounding sphere.
    pub scene_radius: f32,
}

impl Scene {
    /// The area light for triangle `prim` of mesh `mesh`, if it emits.
    #[inline]
    pub fn area_light_index(&self, mesh: u32, prim: u32) -> Option<usize> {
        let off = self.mesh_light_offset[mesh as usize];
        (off != u32::MAX).then(|| (off + prim) as usize)
    }

    /// True when some material disperses light (model only what the scene needs).
    pub fn has_dispersion(&self) -> bool {
        self.materials.iter().any(Material::is_dispersive)
    }
}
