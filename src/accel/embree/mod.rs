//! Intel Embree backend: Embree 3 (feature `embree`, Debian's libembree-dev) or Embree 4
//! (feature `embree4`). Embree types never leave this module; everything that differs between
//! the two versions is in `ffi/` (the declarations and a few shims), and the device checks at
//! start-up that the library matches them (`library_check`).
//!
//! Two triangle tests ([`TriangleTest`]): Embree's own kernel (fast; lets about 1 in 4000 rays
//! aimed exactly at a vertex through a closed mesh), or prism's watertight test run from Embree
//! user-geometry callbacks (no leaks; slower), selected on the command line as `embree` and
//! `embree-watertight`.

mod build_choice;
#[cfg(test)]
mod curves;
mod device;
mod error;
mod ffi;
#[cfg(test)]
mod hit_record_tests;
mod instanced;
mod library_check;
mod motion;
mod quadrics;
mod quads;
mod ray_context;
mod scene;
#[cfg(test)]
mod shared_tests;
mod user_curves;
mod user_triangles;

pub use build_choice::{
    BuildChoice, BIG_SCENE_TRIANGLES, BUILD_ENV, MORTON_MIN_TRIANGLES, MORTON_RAYS_PER_TRIANGLE,
    QUADS_RAYS_PER_TRIANGLE,
};
pub use device::{error_name, Device, EmbreeError, CONFIG_ENV};
pub use error::{EmbreeVersion, LibraryMismatch};

use super::Accel;
use crate::geometry::InstanceSet;
use crate::geometry::{Bounds3, Curves, Hit, Mesh, PlacedQuadric, Ray};
use std::sync::Arc;

/// BVH build quality, as Embree names it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    /// Fast build, slower traversal.
    Low,
    /// Embree's default.
    #[default]
    Medium,
    /// Slower build (spatial splits), fastest traversal.
    High,
}

/// Which ray–triangle test Embree runs at the BVH's leaves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleTest {
    /// Embree's triangle geometry and its robust kernel (Plücker edge tests): the fastest, but
    /// not watertight at vertices (docs/benchmarks.md, "Why Embree leaks at vertices").
    #[default]
    Embree,
    /// User geometry whose callbacks run [`crate::accel::watertight`] (Woop et al. 2013): no ray
    /// passes between triangles sharing an edge or a vertex.
    Watertight,
}

/// Ray intersection through Embree.
pub struct EmbreeAccel {
    scene: Levels,
    test: TriangleTest,
    /// Batches are traced as 16-ray packets (with Embree 3; the Embree 4 build traces them one
    /// ray at a time): one level, Embree's own triangle kernel and no user geometry (whose
    /// callbacks take one ray at a time).
    #[cfg_attr(not(feature = "embree"), allow(dead_code))]
    packets: bool,
}

/// One scene of meshes, or prototypes instanced into a top-level scene.
enum Levels {
    Flat(scene::Scene),
    Instanced(instanced::InstancedScene),
}

/// Triangles in `meshes`.
fn triangle_count(meshes: &[Mesh]) -> usize {
    meshes.iter().map(Mesh::len).sum()
}

impl BuildQuality {
    fn rtc(self) -> ffi::RTCBuildQuality {
        match self {
            BuildQuality::Low => ffi::RTCBuildQuality_RTC_BUILD_QUALITY_LOW,
            BuildQuality::Medium => ffi::RTCBuildQuality_RTC_BUILD_QUALITY_MEDIUM,
            BuildQuality::High => ffi::RTCBuildQuality_RTC_BUILD_QUALITY_HIGH,
        }
    }
}

impl EmbreeAccel {
    /// Builds an Embree scene over `meshes` (geometry id = mesh index), as
    /// [`BuildChoice::for_scene`] chooses for their triangle count and no known ray count.
    pub fn new(meshes: &[Mesh]) -> Result<Self, EmbreeError> {
        Self::with_test(meshes, BuildChoice::for_scene(triangle_count(meshes), None)?, TriangleTest::Embree)
    }

    /// Builds with the given quality.
    pub fn with_quality(meshes: &[Mesh], quality: BuildQuality) -> Result<Self, EmbreeError> {
        Self::with_test(meshes, BuildChoice { quality, compact: false, quads: false }, TriangleTest::Embree)
    }

    /// Builds over `meshes` with the watertight triangle test ([`TriangleTest::Watertight`]).
    pub fn watertight(meshes: &[Mesh]) -> Result<Self, EmbreeError> {
        Self::with_test(meshes, BuildChoice::MEDIUM, TriangleTest::Watertight)
    }

    /// Builds with the given build choice and triangle test.
    pub fn with_test(meshes: &[Mesh], choice: BuildChoice, test: TriangleTest) -> Result<Self, EmbreeError> {
        let device = device::Device::new()?;
        let packets = test == TriangleTest::Embree;
        Ok(Self { scene: Levels::Flat(scene::Scene::build(device, meshes, choice, test)?), test, packets })
    }

    /// Builds one scene over `meshes`, `curves` ((geometry id, its curves), as user
    /// geometry running pbrt-v4's curve test: `user_curves.rs`) and static `quadrics` ((geometry id, its quadric), as user
    /// geometry: `quadrics.rs`) with the given triangle test; Embree's triangles are built as
    /// [`BuildChoice::for_scene`] chooses for their count and the `rays` the render expects to
    /// trace (if known), and read in place when `shared` holds `meshes`.
    pub fn with_extra(
        meshes: &[Mesh],
        curves: &[(u32, &Curves)],
        quadrics: &[(u32, &PlacedQuadric)],
        test: TriangleTest,
        shared: Option<Arc<[Mesh]>>,
        rays: Option<u64>,
    ) -> Result<Self, EmbreeError> {
        let device = device::Device::new()?;
        let choice = match test {
            TriangleTest::Embree => BuildChoice::for_scene(triangle_count(meshes), rays)?,
            TriangleTest::Watertight => BuildChoice::MEDIUM,
        };
        let extra = super::ExtraShapes { curves, quadrics };
        let scene = scene::Scene::build_with_extra(device, meshes, extra, choice, test, shared)?;
        let packets = test == TriangleTest::Embree && quadrics.is_empty();
        Ok(Self { scene: Levels::Flat(scene), test, packets })
    }

    /// Builds a two-level scene: one Embree scene per prototype, instanced into a top scene
    /// that also holds `set.world_meshes`. Hits report scene mesh ids and the instance index.
    pub fn instanced(meshes: &[Mesh], set: &InstanceSet) -> Result<Self, EmbreeError> {
        Self::instanced_with_test(meshes, set, TriangleTest::Embree)
    }

    /// [`EmbreeAccel::instanced`] with the given triangle test (in prototypes and world meshes).
    pub fn instanced_with_test(meshes: &[Mesh], set: &InstanceSet, test: TriangleTest) -> Result<Self, EmbreeError> {
        let shapes = super::ShapeTable::new(super::ExtraShapes::default());
        Self::instanced_with_shapes(meshes, &shapes, set, test, None)
    }

    /// [`EmbreeAccel::instanced_with_test`] with the curves and static quadrics of `shapes`
    /// (by primitive id, in the world or in prototypes) in the scenes too; the triangles are read
    /// in place when `shared` holds `meshes`.
    pub(crate) fn instanced_with_shapes(
        meshes: &[Mesh],
        shapes: &super::ShapeTable,
        set: &InstanceSet,
        test: TriangleTest,
        shared: Option<Arc<[Mesh]>>,
    ) -> Result<Self, EmbreeError> {
        let device = device::Device::new()?;
        let q = BuildQuality::Medium.rtc();
        // Vertex leaves throughout: quads, as for a flat scene of as many stored triangles.
        let quads = test == TriangleTest::Embree && triangle_count(meshes) >= MORTON_MIN_TRIANGLES;
        let scene = instanced::InstancedScene::build(device, meshes, shapes, set, q, test, shared, quads)?;
        Ok(Self { scene: Levels::Instanced(scene), test, packets: false })
    }

    /// The triangle test this accelerator runs.
    pub fn triangle_test(&self) -> TriangleTest {
        self.test
    }

    /// Traces `rays` through raw `rtcIntersect1` with no conversion to prism's types, returning
    /// the number of hits: the baseline for measuring the wrapper's overhead (benches/accel.rs).
    #[doc(hidden)]
    pub fn raw_trace_count(&self, rays: &[Ray]) -> usize {
        let Levels::Flat(scene) = &self.scene else {
            return rays.iter().filter(|r| self.intersect(r).is_some()).count();
        };
        let mut hits = 0;
        for r in rays {
            let mut rh = ffi::RTCRayHit {
                ray: scene::Scene::rtc_ray(r),
                hit: ffi::RTCHit { geomID: ffi::RTC_INVALID_GEOMETRY_ID, ..Default::default() },
            };
            scene.raw_intersect(&mut rh);
            hits += (rh.hit.geomID != ffi::RTC_INVALID_GEOMETRY_ID) as usize;
        }
        hits
    }
}

impl Accel for EmbreeAccel {
    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        match &self.scene {
            Levels::Flat(s) => s.intersect(ray),
            Levels::Instanced(s) => s.intersect(ray),
        }
    }
    #[inline]
    fn occluded(&self, ray: &Ray) -> bool {
        match &self.scene {
            Levels::Flat(s) => s.occluded(ray),
            Levels::Instanced(s) => s.occluded(ray),
        }
    }
    #[cfg(feature = "embree")]
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        match &self.scene {
            Levels::Flat(s) if self.packets => {
                for (r, h) in rays.chunks(16).zip(hits.chunks_mut(16)) {
                    s.intersect16(r, h);
                }
            }
            _ => rays.iter().zip(hits).for_each(|(r, h)| *h = self.intersect(r)),
        }
    }
    #[cfg(feature = "embree")]
    fn occluded_batch(&self, rays: &[Ray], blocked: &mut [bool]) {
        match &self.scene {
            Levels::Flat(s) if self.packets => {
                for (r, b) in rays.chunks(16).zip(blocked.chunks_mut(16)) {
                    s.occluded16(r, b);
                }
            }
            _ => rays.iter().zip(blocked).for_each(|(r, b)| *b = self.occluded(r)),
        }
    }
    fn bounds(&self) -> Bounds3 {
        match &self.scene {
            Levels::Flat(s) => s.bounds(),
            Levels::Instanced(s) => s.bounds(),
        }
    }
    fn memory_bytes(&self) -> usize {
        match &self.scene {
            Levels::Flat(s) => s.memory_bytes(),
            Levels::Instanced(s) => s.memory_bytes(),
        }
    }
    fn name(&self) -> &'static str {
        match self.test {
            TriangleTest::Embree => "embree",
            TriangleTest::Watertight => "embree-watertight",
        }
    }
}

/// Sets flush-to-zero and denormals-are-zero in this thread's MXCSR, as Embree's documentation
/// asks of every thread that traces rays (denormal arithmetic is slow in its kernels).
pub fn set_flush_denormals() {
    #[cfg(target_arch = "x86_64")]
    {
        let mut csr: u32 = 0;
        // SAFETY: stmxcsr/ldmxcsr read and write this thread's SSE control register; setting the
        // FTZ (bit 15) and DAZ (bit 6) bits only changes denormal handling.
        unsafe {
            std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack));
            csr |= (1 << 15) | (1 << 6);
            std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack));
        }
    }
}
