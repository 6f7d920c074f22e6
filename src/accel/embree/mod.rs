//! Intel Embree 3 backend (feature `embree`). Embree types never leave this module; everything
//! specific to Embree 3 (vs 4) is in ffi.rs, device.rs and scene.rs.

mod device;
mod ffi;
mod instanced;
mod scene;

pub use device::{error_name, Device, EmbreeError, CONFIG_ENV};

use super::Accel;
use crate::geometry::{Bounds3, Hit, Mesh, Ray};
use crate::scene::instances::InstanceSet;

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

/// Ray intersection through Embree.
pub struct EmbreeAccel {
    scene: Levels,
}

/// One scene of meshes, or prototypes instanced into a top-level scene.
enum Levels {
    Flat(scene::Scene),
    Instanced(instanced::InstancedScene),
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
    /// Builds an Embree scene over `meshes` (geometry id = mesh index).
    pub fn new(meshes: &[Mesh]) -> Result<Self, EmbreeError> {
        Self::with_quality(meshes, BuildQuality::Medium)
    }

    /// Builds with the given quality.
    pub fn with_quality(meshes: &[Mesh], quality: BuildQuality) -> Result<Self, EmbreeError> {
        let device = device::Device::new()?;
        Ok(Self { scene: Levels::Flat(scene::Scene::build(device, meshes, quality.rtc())?) })
    }

    /// Builds a two-level scene: one Embree scene per prototype, instanced into a top scene
    /// that also holds `set.world_meshes`. Hits report scene mesh ids and the instance index.
    pub fn instanced(meshes: &[Mesh], set: &InstanceSet) -> Result<Self, EmbreeError> {
        let device = device::Device::new()?;
        let q = BuildQuality::Medium.rtc();
        Ok(Self { scene: Levels::Instanced(instanced::InstancedScene::build(device, meshes, set, q)?) })
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
        "embree"
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
