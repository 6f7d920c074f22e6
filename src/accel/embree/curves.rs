//! Curves as Embree's own curve geometry: cubic Bézier segments with a radius per control point
//! (x, y, z, r as float4), one index per segment (its first control point). Flat curves become
//! `FLAT_BEZIER_CURVE` (ribbons facing the ray, as pbrt-v4's) and pbrt-v4's "cylinder" curves
//! ray-facing flat curves too
//! ([`CYLINDER_AS_ROUND`] switches them to Embree's round tubes). Ribbons would become
//! `NORMAL_ORIENTED_BEZIER_CURVE` with a normal per control point, which is not pbrt-v4's ribbon:
//! scenes attach them as user geometry instead (`ribbons.rs`), and only the test measuring the
//! difference attaches them here. A hit's u is the segment's curve parameter; the surface is
//! recomputed from it (`geometry::curve_hit::curve_surface`).

use super::device::{Device, EmbreeError};
use super::ffi;
use crate::geometry::{CurveKind, Curves};

/// Whether pbrt-v4's "cylinder" curves are traced as Embree's round curves (true tubes) rather
/// than as ray-facing flat curves. pbrt-v4 intersects a flat ribbon facing the ray and only
/// turns the shading normal; the flat curve matches its silhouettes and self-shadowing.
pub const CYLINDER_AS_ROUND: bool = false;

/// The Embree geometry type for curves of `kind`.
fn geometry_type(kind: CurveKind) -> ffi::RTCGeometryType {
    match kind {
        CurveKind::Flat => ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE,
        CurveKind::Cylinder if CYLINDER_AS_ROUND => ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE,
        CurveKind::Cylinder => ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE,
        CurveKind::Ribbon => ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE,
    }
}

/// Attaches `curves` to `scene` as one committed curve geometry with id `id`.
pub(super) fn attach(scene: ffi::RTCScene, device: &Device, curves: &Curves, id: u32) -> Result<(), EmbreeError> {
    let Some(first) = curves.segments.first() else { return Ok(()) };
    let kind = first.kind;
    let n = curves.segments.len();
    // Control point k of a segment sits at u = k/3; a width linear in u is reproduced exactly by
    // Bézier radii at the thirds.
    let vertices: Vec<[f32; 4]> = curves
        .segments
        .iter()
        .flat_map(|s| {
            (0..4).map(move |k| {
                let p = s.cp[k];
                [p.x, p.y, p.z, 0.5 * s.width_at(k as f32 / 3.0)]
            })
        })
        .collect();
    let normals: Vec<[f32; 3]> =
        curves.segments.iter().flat_map(|s| (0..4).map(move |k| s.ribbon_normal(k as f32 / 3.0).to_array())).collect();
    // SAFETY: valid device; the buffers Embree allocates are filled within their sizes, and the
    // geometry is released after attaching (the scene keeps its own reference).
    unsafe {
        let geom = ffi::rtcNewGeometry(device.raw(), geometry_type(kind));
        if geom.is_null() {
            return Err(EmbreeError::Call(device.take_error().unwrap_or_default()));
        }
        let vb = ffi::rtcSetNewGeometryBuffer(
            geom,
            ffi::RTCBufferType_RTC_BUFFER_TYPE_VERTEX,
            0,
            ffi::RTCFormat_RTC_FORMAT_FLOAT4,
            16,
            vertices.len(),
        ) as *mut [f32; 4];
        let ib = ffi::rtcSetNewGeometryBuffer(
            geom,
            ffi::RTCBufferType_RTC_BUFFER_TYPE_INDEX,
            0,
            ffi::RTCFormat_RTC_FORMAT_UINT,
            4,
            n,
        ) as *mut u32;
        let nb = if kind == CurveKind::Ribbon {
            ffi::rtcSetNewGeometryBuffer(
                geom,
                ffi::RTCBufferType_RTC_BUFFER_TYPE_NORMAL,
                0,
                ffi::RTCFormat_RTC_FORMAT_FLOAT3,
                12,
                normals.len(),
            ) as *mut [f32; 3]
        } else {
            std::ptr::NonNull::dangling().as_ptr()
        };
        if vb.is_null() || ib.is_null() || nb.is_null() {
            ffi::rtcReleaseGeometry(geom);
            return Err(EmbreeError::Call(
                device.take_error().unwrap_or_else(|| "out of memory for curve buffers".into()),
            ));
        }
        std::slice::from_raw_parts_mut(vb, vertices.len()).copy_from_slice(&vertices);
        for (i, dst) in std::slice::from_raw_parts_mut(ib, n).iter_mut().enumerate() {
            *dst = 4 * i as u32;
        }
        if kind == CurveKind::Ribbon {
            std::slice::from_raw_parts_mut(nb, normals.len()).copy_from_slice(&normals);
        }
        ffi::rtcCommitGeometry(geom);
        ffi::rtcAttachGeometryByID(scene, geom, id);
        ffi::rtcReleaseGeometry(geom);
    }
    device.take_error().map_or(Ok(()), |e| Err(EmbreeError::Call(e)))
}
