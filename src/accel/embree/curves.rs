//! Curves as Embree's own curve geometry, kept to measure them against pbrt-v4's (scenes attach
//! every curve as user geometry running pbrt-v4's test: `user_curves.rs`): cubic Bézier segments
//! with a radius per control point (x, y, z, r as float4), one index per segment (its first
//! control point). Flat and "cylinder" curves become `FLAT_BEZIER_CURVE` (ray-facing quads),
//! ribbons `NORMAL_ORIENTED_BEZIER_CURVE` with a normal per control point.

use super::device::{Device, EmbreeError};
use super::ffi;
use crate::geometry::{CurveKind, Curves};

/// The Embree geometry type for curves of `kind`.
fn geometry_type(kind: CurveKind) -> ffi::RTCGeometryType {
    match kind {
        CurveKind::Flat | CurveKind::Cylinder => ffi::RTCGeometryType_RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE,
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
