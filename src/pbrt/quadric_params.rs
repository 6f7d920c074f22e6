//! The parameters of pbrt-v4's `sphere`, `disk` and `cylinder` shapes, with pbrt-v4's defaults
//! and range rules (z limits ordered and, for the sphere, clamped to ±radius; φmax in degrees).

use super::params::ParamSet;
use crate::geometry::Quadric;

/// The pbrt-v4 shape names that are quadrics.
pub const KINDS: &[&str] = &["sphere", "disk", "cylinder"];

/// Why a quadric's parameters make no shape.
#[derive(Debug, thiserror::Error)]
pub enum QuadricParamError {
    /// A radius that is not positive and finite.
    #[error("{kind} radius must be positive, got {radius}")]
    Radius { kind: String, radius: f32 },
    /// A φmax outside (0, 360] degrees.
    #[error("{kind} phimax must be in (0, 360] degrees, got {phi_max}")]
    PhiMax { kind: String, phi_max: f32 },
    /// z limits, as given, that bound nothing.
    #[error("{kind} zmin ({z_min}) and zmax ({z_max}) leave an empty range")]
    EmptyZRange { kind: String, z_min: f32, z_max: f32 },
    /// Sphere z limits that bound nothing once clamped to ±radius.
    #[error("sphere zmin ({z_min}) must be below zmax ({z_max}) within ±radius")]
    SphereZRange { z_min: f32, z_max: f32 },
    /// A disk inner radius outside [0, radius), or a non-finite height.
    #[error("disk innerradius must be in [0, radius = {radius}), got {inner_radius}")]
    InnerRadius { radius: f32, inner_radius: f32 },
    /// A shape name that is no quadric.
    #[error("\"{0}\" is not a quadric")]
    NotQuadric(String),
}

/// Reads the quadric `kind` ("sphere", "disk" or "cylinder") from `ps`, marking its parameters
/// used; an empty or non-finite shape is an error.
pub fn load(kind: &str, ps: &ParamSet) -> Result<Quadric, QuadricParamError> {
    let radius = ps.float_or("radius", 1.0);
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(QuadricParamError::Radius { kind: kind.to_string(), radius });
    }
    let phi_max = ps.float_or("phimax", 360.0);
    if !(phi_max > 0.0 && phi_max <= 360.0) {
        return Err(QuadricParamError::PhiMax { kind: kind.to_string(), phi_max });
    }
    let z_range = |lo: f32, hi: f32| {
        let (a, b) = (ps.float_or("zmin", lo), ps.float_or("zmax", hi));
        let (z_min, z_max) = (a.min(b), a.max(b));
        if !(z_min < z_max && z_min.is_finite() && z_max.is_finite()) {
            return Err(QuadricParamError::EmptyZRange { kind: kind.to_string(), z_min: a, z_max: b });
        }
        Ok((z_min, z_max))
    };
    match kind {
        "sphere" => {
            let (z_min, z_max) = z_range(-radius, radius)?;
            let (z_min, z_max) = (z_min.clamp(-radius, radius), z_max.clamp(-radius, radius));
            if z_min >= z_max {
                return Err(QuadricParamError::SphereZRange { z_min, z_max });
            }
            Ok(Quadric::Sphere { radius, z_min, z_max, phi_max })
        }
        "cylinder" => {
            let (z_min, z_max) = z_range(-1.0, 1.0)?;
            Ok(Quadric::Cylinder { radius, z_min, z_max, phi_max })
        }
        "disk" => {
            let height = ps.float_or("height", 0.0);
            let inner_radius = ps.float_or("innerradius", 0.0);
            if !(0.0..radius).contains(&inner_radius) || !height.is_finite() {
                return Err(QuadricParamError::InnerRadius { radius, inner_radius });
            }
            Ok(Quadric::Disk { height, radius, inner_radius, phi_max })
        }
        _ => Err(QuadricParamError::NotQuadric(kind.to_string())),
    }
}
