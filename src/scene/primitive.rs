//! Primitives: a shape's geometry bound to what a ray hit on it needs — its material, its area
//! light, the media on either side and its alpha mask — as pbrt-v4's `GeometricPrimitive` (Pharr, Jakob &
//! Humphreys, *Physically Based Rendering*, 4th ed., §7.1.1) and Mitsuba 3's `Shape` do. The
//! integrator asks the hit ([`super::SurfaceInteraction`]) for these, never the scene's lists.

use super::mesh_lights::LightsOf;
use crate::geometry::Shape;
use crate::material::FloatTexture;

/// The participating media on the two sides of a surface (pbrt-v4 `MediumInterface`): indices
/// into the scene's media, `None` for vacuum. `inside` is the side the geometric normal points
/// away from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumInterface {
    /// Medium behind the surface (opposite its geometric normal).
    pub inside: Option<u32>,
    /// Medium in front of the surface.
    pub outside: Option<u32>,
}

impl MediumInterface {
    /// True when the media on the two sides differ, so a ray crossing the surface changes
    /// medium; a surface that is no transition leaves a ray in the medium it was in (pbrt-v4
    /// `MediumInterface::IsMediumTransition`).
    #[inline]
    pub fn is_transition(&self) -> bool {
        self.inside != self.outside
    }

    /// The medium a ray leaving along `d` enters, for a surface with (oriented) geometric
    /// normal `ng`, coming from `current`.
    #[inline]
    pub fn medium_toward(&self, d: glam::Vec3, ng: glam::Vec3, current: Option<u32>) -> Option<u32> {
        if !self.is_transition() {
            current
        } else if d.dot(ng) > 0.0 {
            self.outside
        } else {
            self.inside
        }
    }
}

/// A shape — triangles, curves or a quadric — with its material, area emission, medium
/// interface and alpha. A hit's `geom_id` names its primitive; primitives of object instances
/// are in object space.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    /// The geometry.
    pub shape: Shape,
    /// Index of its material in the scene's materials.
    pub material: u32,
    /// Index in the scene's lights of the primitive's first light, when it emits.
    pub area_lights: Option<u32>,
    /// Which light each triangle is, from `area_lights`: one per triangle (so the light sampler
    /// can pick triangles in proportion to their power) or per rectangular face, or the whole
    /// primitive one light (a quadric: a sphere sampled by solid angle, or another quadric
    /// sampled by area).
    pub lights_of: LightsOf,
    /// The media inside and outside the surface.
    pub medium_interface: MediumInterface,
    /// Cut-out mask (pbrt-v4's `alpha`): where it is 0 a ray passes through the surface. `None`
    /// is opaque; the accelerator's any-hit test is where a mask takes effect.
    pub alpha: Option<FloatTexture>,
    /// The surface is only a boundary between media (`Material::Interface`) that neither
    /// emits nor cuts out: nothing shades or textures a hit on it, so its interaction needs no
    /// (u, v), derivatives or shading normal.
    pub bare_boundary: bool,
}

impl Primitive {
    /// The light index of triangle `prim`'s area light, if the primitive emits.
    #[inline]
    pub fn area_light(&self, prim: u32) -> Option<u32> {
        self.area_lights.map(|first| self.lights_of.of(first, prim))
    }
}
