//! How Embree builds the BVH of a scene of triangle meshes: its build quality and its leaf
//! layout, chosen by the scene's triangle count ([`BuildChoice::for_triangles`]) or set by
//! [`BUILD_ENV`] for measurements.
//!
//! The choices, as Embree 3.13 makes them (`verbose=2` names the builder and the leaves):
//! - medium quality: the SAH builder over the whole scene (`BVH8<triangle4v>`: the three
//!   vertices of four triangles copied into each leaf, ~46 bytes per triangle);
//! - low quality: a two-level BVH whose meshes are built by the Morton-code builder (one sort of
//!   the triangles' centroid codes, no SAH sweeps): a faster build, a slower traversal;
//! - compact (`RTC_SCENE_FLAG_COMPACT`): `BVH4<triangle4i>`, leaves holding vertex indices that
//!   traversal follows into the vertex buffer (~21 bytes per triangle instead of ~46).
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

/// Build quality and leaf layout of one Embree scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildChoice {
    /// Embree's build quality (of the scene and of each triangle geometry).
    pub quality: BuildQuality,
    /// `RTC_SCENE_FLAG_COMPACT`: index leaves instead of vertex copies.
    pub compact: bool,
}

impl BuildChoice {
    /// Embree's default: the SAH builder with vertex leaves.
    pub const MEDIUM: Self = Self { quality: BuildQuality::Medium, compact: false };

    /// The rule for a scene of `triangles`: Embree's default below [`BIG_SCENE_TRIANGLES`], from
    /// there the same SAH build with compact leaves. On a 20 M-triangle mesh whose arrays
    /// Embree reads in place, compact leaves take the peak memory of the start-up from 118 to 53
    /// bytes per triangle and Embree's build to 0.76× its CPU time, for 1.1–1.26× the render
    /// time; the Morton builder (`low`) would halve the build's CPU time again but trace ~1.5×
    /// slower than compact SAH leaves and hold 76 bytes per triangle (docs/benchmarks.md,
    /// "One big mesh").
    pub fn for_triangles(triangles: usize) -> Self {
        Self { quality: BuildQuality::Medium, compact: triangles >= BIG_SCENE_TRIANGLES }
    }

    /// [`BuildChoice::for_triangles`], unless [`BUILD_ENV`] sets the choice.
    pub fn for_scene(triangles: usize) -> Result<Self, EmbreeError> {
        match std::env::var(BUILD_ENV) {
            Ok(s) if !s.trim().is_empty() => Self::parse(&s),
            _ => Ok(Self::for_triangles(triangles)),
        }
    }

    /// Reads `low|medium|high[,compact]`.
    pub fn parse(s: &str) -> Result<Self, EmbreeError> {
        let bad =
            || EmbreeError::Call(format!("{BUILD_ENV}={s:?}: expected low, medium or high, then optionally ,compact"));
        let mut parts = s.split(',').map(str::trim);
        let quality = match parts.next() {
            Some("low") => BuildQuality::Low,
            Some("medium") => BuildQuality::Medium,
            Some("high") => BuildQuality::High,
            _ => return Err(bad()),
        };
        let compact = match parts.next() {
            None => false,
            Some("compact") => true,
            Some(_) => return Err(bad()),
        };
        if parts.next().is_some() {
            return Err(bad());
        }
        Ok(Self { quality, compact })
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
            BuildChoice { quality: BuildQuality::Low, compact: true }
        );
        for bad in ["", "fast", "low,compact,x", "medium,tight"] {
            assert!(BuildChoice::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn rule_switches_at_the_threshold() {
        assert_eq!(BuildChoice::for_triangles(BIG_SCENE_TRIANGLES - 1), BuildChoice::MEDIUM);
        let big = BuildChoice::for_triangles(BIG_SCENE_TRIANGLES);
        assert!(big.compact && big.quality == BuildQuality::Medium);
    }
}
