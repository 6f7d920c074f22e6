//! How Embree builds the BVH of a scene of triangle meshes: its build quality and its leaf
//! layout, chosen by the scene's triangle count and the rays the render will trace
//! ([`BuildChoice::for_triangles`]) or set by [`BUILD_ENV`] for measurements.
//!
//! The choices, as Embree 3.13 makes them (`verbose=2` names the builder and the leaves):
//! - medium quality: the SAH builder over the whole scene (`BVH8<triangle4v>`: the three
//!   vertices of four triangles copied into each leaf, ~46 bytes per triangle);
//! - low quality: a two-level BVH whose meshes are built by the Morton-code builder (one sort of
//!   the triangles' centroid codes, no SAH sweeps): a faster build, a slower traversal;
//! - compact (`RTC_SCENE_FLAG_COMPACT`): `BVH4<triangle4i>`, leaves holding vertex indices that
//!   traversal follows into the vertex buffer (~21 bytes per triangle instead of ~46);
//! - quads: a mesh's triangles paired into Embree quads where it lists the two halves of a
//!   quad in a row (`quads.rs`), half as many primitives to build over.
//!
//! A different BVH may report the other of two triangles hit at exactly the same distance;
//! nothing else about a hit changes.

use super::device::EmbreeError;
use super::{ffi, BuildQuality};

/// Environment variable overriding the rule: a build quality `low`, `medium` or `high`, then
/// optionally `,compact` (e.g. `low,compact`); empty or unset means the rule.
pub const BUILD_ENV: &str = "PRISM_EMBREE_BUILD";

/// Scenes of at least this many triangles get compact leaves ([`BuildChoice::for_triangles`]):
/// 2²³, about 1 GB at Embree's default layout.
pub const BIG_SCENE_TRIANGLES: usize = 8 << 20;

/// Scenes of fewer triangles keep the SAH build whatever the number of rays: 2²⁰, whose SAH
/// build takes well under a CPU-second, too little for a faster build to matter.
pub const MORTON_MIN_TRIANGLES: usize = 1 << 20;

/// Rays per triangle below which the Morton build takes less time in all than the SAH build
/// ([`BuildChoice::for_triangles`]).
pub const MORTON_RAYS_PER_TRIANGLE: f64 = 0.4;

/// Rays per triangle below which a scene with compact leaves is built over quads
/// ([`BuildChoice::for_triangles`]).
pub const QUADS_RAYS_PER_TRIANGLE: f64 = 4.0;

/// Build quality and leaf layout of one Embree scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildChoice {
    /// Embree's build quality (of the scene and of each triangle geometry).
    pub quality: BuildQuality,
    /// `RTC_SCENE_FLAG_COMPACT`: index leaves instead of vertex copies.
    pub compact: bool,
    /// Triangles paired into Embree quads where a mesh lists two halves of a quad in a row
    /// (`quads.rs`).
    pub quads: bool,
}

impl BuildChoice {
    /// Embree's default: the SAH builder with vertex leaves.
    pub const MEDIUM: Self = Self { quality: BuildQuality::Medium, compact: false, quads: false };

    /// The rule for a scene of `triangles` through which a render will trace about `rays`
    /// (`None`: unknown, taken as many).
    ///
    /// Leaves: Embree's default below [`BIG_SCENE_TRIANGLES`], compact from there. On a
    /// 20 M-triangle mesh whose arrays Embree reads in place, compact leaves take the peak
    /// memory of the start-up from 118 to 53 bytes per triangle and Embree's build to 0.76× its
    /// CPU time, for 1.1–1.26× the render time.
    ///
    /// Quality: SAH, except for scenes of [`MORTON_MIN_TRIANGLES`] up to
    /// [`BIG_SCENE_TRIANGLES`] through which fewer than [`MORTON_RAYS_PER_TRIANGLE`] rays per
    /// triangle will be traced: those get the Morton builder (`low`). Measured on a
    /// 20 M-triangle mesh (docs/benchmarks.md, "One big mesh"), the Morton build saves
    /// B ≈ 0.18 CPU-µs per triangle and its BVH costs d ≈ 0.44 CPU-µs more per ray (path
    /// tracing, shading included: 2.07 against 1.63), so it pays below B/d ≈ 0.4 rays per
    /// triangle. Compact scenes keep SAH all the same: there the Morton build's temporaries
    /// raise the peak memory from 53 to 76 bytes per triangle.
    ///
    /// Quads: from [`MORTON_MIN_TRIANGLES`] (below, the build takes too little time to matter
    /// and images stay as they were). With vertex leaves a quad BVH is both faster to build and
    /// to trace (4 M-triangle heightfield: Embree's build 0.49× the CPU time, render 0.98×,
    /// 0.70× the bytes); with compact leaves it builds in 0.57× the time but traces ~3% slower
    /// (20 M triangles: B ≈ 0.155 CPU-µs saved per triangle, d ≈ 0.04 CPU-µs more per ray),
    /// so compact scenes get quads below [`QUADS_RAYS_PER_TRIANGLE`] ≈ B/d rays per triangle.
    pub fn for_triangles(triangles: usize, rays: Option<u64>) -> Self {
        let compact = triangles >= BIG_SCENE_TRIANGLES;
        let fewer = |per_triangle: f64| rays.is_some_and(|r| (r as f64) < per_triangle * triangles as f64);
        let few_rays =
            (MORTON_MIN_TRIANGLES..BIG_SCENE_TRIANGLES).contains(&triangles) && fewer(MORTON_RAYS_PER_TRIANGLE);
        let quality = if few_rays { BuildQuality::Low } else { BuildQuality::Medium };
        let quads = triangles >= MORTON_MIN_TRIANGLES && (!compact || fewer(QUADS_RAYS_PER_TRIANGLE));
        Self { quality, compact, quads }
    }

    /// [`BuildChoice::for_triangles`], unless [`BUILD_ENV`] sets the choice.
    pub fn for_scene(triangles: usize, rays: Option<u64>) -> Result<Self, EmbreeError> {
        match std::env::var(BUILD_ENV) {
            Ok(s) if !s.trim().is_empty() => Self::parse(&s),
            _ => Ok(Self::for_triangles(triangles, rays)),
        }
    }

    /// Reads `low|medium|high[,compact][,quads]`.
    pub fn parse(s: &str) -> Result<Self, EmbreeError> {
        let bad = || {
            EmbreeError::Call(format!(
                "{BUILD_ENV}={s:?}: expected low, medium or high, then optionally ,compact and ,quads"
            ))
        };
        let mut parts = s.split(',').map(str::trim);
        let quality = match parts.next() {
            Some("low") => BuildQuality::Low,
            Some("medium") => BuildQuality::Medium,
            Some("high") => BuildQuality::High,
            _ => return Err(bad()),
        };
        let mut choice = Self { quality, compact: false, quads: false };
        for part in parts {
            let flag = match part {
                "compact" => &mut choice.compact,
                "quads" => &mut choice.quads,
                _ => return Err(bad()),
            };
            if std::mem::replace(flag, true) {
                return Err(bad());
            }
        }
        Ok(choice)
    }

    /// The scene flags: always robust (no leaks through shared edges), compact if chosen.
    pub(super) fn scene_flags(self) -> ffi::RTCSceneFlags {
        let compact = if self.compact { ffi::RTCSceneFlags_RTC_SCENE_FLAG_COMPACT } else { 0 };
        ffi::RTCSceneFlags_RTC_SCENE_FLAG_ROBUST | compact
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_quality_and_compact() {
        assert_eq!(BuildChoice::parse("medium").unwrap(), BuildChoice::MEDIUM);
        assert_eq!(
            BuildChoice::parse("low, compact").unwrap(),
            BuildChoice { quality: BuildQuality::Low, compact: true, quads: false }
        );
        for bad in ["", "fast", "low,compact,x", "medium,tight"] {
            assert!(BuildChoice::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn rule_switches_at_the_threshold() {
        assert!(!BuildChoice::for_triangles(BIG_SCENE_TRIANGLES - 1, None).compact);
        let big = BuildChoice::for_triangles(BIG_SCENE_TRIANGLES, None);
        assert!(big.compact && big.quality == BuildQuality::Medium);
    }

    #[test]
    fn few_rays_over_many_triangles_take_the_morton_build() {
        let n = 4_000_000;
        let medium = BuildChoice { quality: BuildQuality::Medium, compact: false, quads: true };
        let low = BuildChoice { quality: BuildQuality::Low, ..medium };
        // 128 × 128 pixels, 4 samples of up to 11 rays: 0.18 rays per triangle.
        assert_eq!(BuildChoice::for_triangles(n, Some(128 * 128 * 4 * 11)), low);
        // 1920 × 1080 pixels, 64 samples: far more rays than triangles.
        assert_eq!(BuildChoice::for_triangles(n, Some(1920 * 1080 * 64 * 11)), medium);
        assert_eq!(BuildChoice::for_triangles(n, None), medium);
        // Just below and at the crossover.
        let at = (MORTON_RAYS_PER_TRIANGLE * n as f64) as u64;
        assert_eq!(BuildChoice::for_triangles(n, Some(at - 1)), low);
        assert_eq!(BuildChoice::for_triangles(n, Some(at)), medium);
        // Small scenes, and big ones (compact leaves), keep SAH however few the rays.
        assert_eq!(BuildChoice::for_triangles(MORTON_MIN_TRIANGLES - 1, Some(1)), BuildChoice::MEDIUM);
        assert_eq!(BuildChoice::for_triangles(MORTON_MIN_TRIANGLES, Some(1)), low);
        let big = BuildChoice::for_triangles(BIG_SCENE_TRIANGLES, Some(1));
        assert_eq!(big, BuildChoice { quality: BuildQuality::Medium, compact: true, quads: true });
    }

    #[test]
    fn quads_from_a_million_triangles_and_with_compact_leaves_only_for_few_rays() {
        // Small scenes keep triangles whatever the rays; mid-sized ones take quads whatever the rays.
        for rays in [None, Some(1), Some(u64::MAX)] {
            assert!(!BuildChoice::for_triangles(MORTON_MIN_TRIANGLES - 1, rays).quads);
            assert!(BuildChoice::for_triangles(MORTON_MIN_TRIANGLES, rays).quads);
            assert!(BuildChoice::for_triangles(BIG_SCENE_TRIANGLES - 1, rays).quads);
        }
        // Compact scenes: quads below the crossover, triangles at it and for unknown rays.
        let n = 20_000_000;
        let at = (QUADS_RAYS_PER_TRIANGLE * n as f64) as u64;
        assert!(BuildChoice::for_triangles(n, Some(at - 1)).quads);
        assert!(!BuildChoice::for_triangles(n, Some(at)).quads);
        assert!(!BuildChoice::for_triangles(n, None).quads);
    }

    #[test]
    fn parses_every_flag_once_in_any_order() {
        let all = BuildChoice { quality: BuildQuality::High, compact: true, quads: true };
        assert_eq!(BuildChoice::parse("high,quads,compact").unwrap(), all);
        assert_eq!(BuildChoice::parse("high, compact, quads").unwrap(), all);
        for bad in ["medium,quads,quads", "quads", "medium,,quads"] {
            assert!(BuildChoice::parse(bad).is_err(), "{bad}");
        }
    }
}
