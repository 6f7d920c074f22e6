//! The parameters of pbrt-v4's `curve` shape, with pbrt-v4's defaults and checks: "type" flat
//! (default), ribbon or cylinder; "basis" bezier (default) or bspline; "degree" 3 (default) or
//! 2; "P"; "width" (1) or "width0"/"width1" at the two ends, linear along the whole curve; "N",
//! one normal per segment end, for ribbons; "splitdepth" (3).

use super::params::ParamSet;
use crate::geometry::curve::{bezier_segments, CurveBasis, CurveError};
use crate::geometry::{CurveKind, CurveSegment, Curves};

/// Why a curve's parameters make no curve.
#[derive(Debug, thiserror::Error)]
pub enum CurveParamError {
    /// A width at either end that is negative or not finite.
    #[error("curve widths must be finite and non-negative, got {w0} and {w1}")]
    Widths { w0: f32, w1: f32 },
    /// A basis other than "bezier" and "bspline".
    #[error("basis \"{0}\": only \"bezier\" and \"bspline\" are supported")]
    Basis(String),
    /// No "P".
    #[error("curve needs a \"point3 P\" parameter")]
    NoPoints,
    /// A negative degree.
    #[error("degree {0}: only 2 and 3 are supported")]
    Degree(i32),
    /// Control points that make no curve of the degree and basis.
    #[error(transparent)]
    Points(#[from] CurveError),
    /// A ribbon without one normal per segment end.
    #[error(
        "a ribbon curve of {segments} segment(s) needs {} normals \"N\" (one per segment end), got {normals}",
        .segments + 1
    )]
    RibbonNormals { segments: usize, normals: usize },
}

/// Reads a curve shape from `ps` (object space), marking its parameters used; an invalid curve
/// is an error, a parameter pbrt-v4 ignores a note in `notes`.
pub fn load(ps: &ParamSet, notes: &mut Vec<String>) -> Result<Curves, CurveParamError> {
    let width = ps.float_or("width", 1.0);
    let (w0, w1) = (ps.float_or("width0", width), ps.float_or("width1", width));
    if !(w0 >= 0.0 && w1 >= 0.0 && w0.is_finite() && w1.is_finite()) {
        return Err(CurveParamError::Widths { w0, w1 });
    }
    let degree = ps.int_or("degree", 3);
    let basis = match ps.string("basis").unwrap_or("bezier") {
        "bezier" => CurveBasis::Bezier,
        "bspline" => CurveBasis::BSpline,
        other => return Err(CurveParamError::Basis(other.to_string())),
    };
    let kind = match ps.string("type").unwrap_or("flat") {
        "flat" => CurveKind::Flat,
        "ribbon" => CurveKind::Ribbon,
        "cylinder" => CurveKind::Cylinder,
        other => {
            notes.push(format!("unknown curve type \"{other}\"; using \"cylinder\" as pbrt-v4 does"));
            CurveKind::Cylinder
        }
    };
    let Some(p) = ps.point3s("P") else { return Err(CurveParamError::NoPoints) };
    let degree = usize::try_from(degree).map_err(|_| CurveParamError::Degree(degree))?;
    let cps = bezier_segments(p, basis, degree)?;
    let n = ps.normals("N").unwrap_or(&[]);
    let normals = match kind {
        CurveKind::Ribbon if n.len() != cps.len() + 1 => {
            return Err(CurveParamError::RibbonNormals { segments: cps.len(), normals: n.len() })
        }
        CurveKind::Ribbon => n,
        _ => {
            if !n.is_empty() {
                notes.push("curve normals \"N\" are only used by \"ribbon\" curves; ignored".into());
            }
            &[]
        }
    };
    let split_depth = ps.int_or("splitdepth", 3).clamp(0, 10) as u32;
    let count = cps.len() as f32;
    let lerp = |t: f32| (1.0 - t) * w0 + t * w1;
    let segments = cps
        .into_iter()
        .enumerate()
        .map(|(s, cp)| {
            let width = [lerp(s as f32 / count), lerp((s + 1) as f32 / count)];
            let ends = if normals.is_empty() { [glam::Vec3::ZERO; 2] } else { [normals[s], normals[s + 1]] };
            CurveSegment::new(cp, width, kind, ends)
        })
        .collect();
    Ok(Curves { segments, split_depth, flip_normal: false })
}
