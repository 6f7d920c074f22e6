//! The parameters of pbrt-v4's `curve` shape, with pbrt-v4's defaults and checks: "type" flat
//! (default), ribbon or cylinder; "basis" bezier (default) or bspline; "degree" 3 (default) or
//! 2; "P"; "width" (1) or "width0"/"width1" at the two ends, linear along the whole curve; "N",
//! one normal per segment end, for ribbons; "splitdepth" (3).

use super::params::ParamSet;
use crate::geometry::curve::{bezier_segments, CurveBasis};
use crate::geometry::{CurveKind, CurveSegment, Curves};

/// Reads a curve shape from `ps` (object space), marking its parameters used; an invalid curve
/// is an error message, a parameter pbrt-v4 ignores a note in `notes`.
pub fn load(ps: &ParamSet, notes: &mut Vec<String>) -> Result<Curves, String> {
    let width = ps.float_or("width", 1.0);
    let (w0, w1) = (ps.float_or("width0", width), ps.float_or("width1", width));
    if !(w0 >= 0.0 && w1 >= 0.0 && w0.is_finite() && w1.is_finite()) {
        return Err(format!("curve widths must be finite and non-negative, got {w0} and {w1}"));
    }
    let degree = ps.int_or("degree", 3);
    let basis = match ps.string("basis").unwrap_or("bezier") {
        "bezier" => CurveBasis::Bezier,
        "bspline" => CurveBasis::BSpline,
        other => return Err(format!("basis \"{other}\": only \"bezier\" and \"bspline\" are supported")),
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
    let Some(p) = ps.point3s("P") else { return Err("curve needs a \"point3 P\" parameter".into()) };
    let degree = usize::try_from(degree).map_err(|_| format!("degree {degree}: only 2 and 3 are supported"))?;
    let cps = bezier_segments(p, basis, degree).map_err(|e| e.to_string())?;
    let n = ps.normals("N").unwrap_or(&[]);
    let normals = match kind {
        CurveKind::Ribbon if n.len() != cps.len() + 1 => {
            return Err(format!(
                "a ribbon curve of {} segment(s) needs {} normals \"N\" (one per segment end), got {}",
                cps.len(),
                cps.len() + 1,
                n.len()
            ))
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
