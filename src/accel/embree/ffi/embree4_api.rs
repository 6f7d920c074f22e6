//! The part of the Embree 4.4 C API that prism uses, declared by hand from Embree 4.4.0's public
//! headers (include/embree4/rtcore_{common,device,buffer,geometry,scene,ray}.h), with the names
//! bindgen would give them (`Enum_CONSTANT`), so that the backend reads the same under both
//! versions.
//!
//! Layouts are those of a library configured with `RTC_MAX_INSTANCE_LEVEL_COUNT = 1` and
//! `RTC_GEOMETRY_INSTANCE_ARRAY` (Embree's defaults since 4.3, and the release build in the
//! `embreex4` wheel): `RTCHit` ends with `instID[1]` and `instPrimID[1]` (48 bytes with its
//! 16-byte alignment), `RTCRayQueryContext` holds those two stacks (8 bytes). The device checks
//! the library's version and the words it writes into a hit at start-up
//! (`super::super::library_check`) and refuses a library that differs.
#![allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `RTC_MAX_INSTANCE_LEVEL_COUNT` of the library (rtcore_config.h).
pub const RTC_MAX_INSTANCE_LEVEL_COUNT: c_uint = 1;

// --- Opaque handles (rtcore_device.h, rtcore_geometry.h) ---

#[repr(C)]
pub struct RTCDeviceTy {
    _private: [u8; 0],
}
pub type RTCDevice = *mut RTCDeviceTy;
#[repr(C)]
pub struct RTCSceneTy {
    _private: [u8; 0],
}
pub type RTCScene = *mut RTCSceneTy;
#[repr(C)]
pub struct RTCGeometryTy {
    _private: [u8; 0],
}
pub type RTCGeometry = *mut RTCGeometryTy;

// --- Enumerations (C enums: `unsigned int` values) ---

pub type RTCDeviceProperty = c_uint;
pub const RTCDeviceProperty_RTC_DEVICE_PROPERTY_VERSION: RTCDeviceProperty = 0;
pub const RTCDeviceProperty_RTC_DEVICE_PROPERTY_VERSION_MAJOR: RTCDeviceProperty = 1;

pub type RTCError = c_uint;

pub type RTCBuildQuality = c_uint;
pub const RTCBuildQuality_RTC_BUILD_QUALITY_LOW: RTCBuildQuality = 0;
pub const RTCBuildQuality_RTC_BUILD_QUALITY_MEDIUM: RTCBuildQuality = 1;
pub const RTCBuildQuality_RTC_BUILD_QUALITY_HIGH: RTCBuildQuality = 2;

pub type RTCSceneFlags = c_uint;
pub const RTCSceneFlags_RTC_SCENE_FLAG_COMPACT: RTCSceneFlags = 1 << 1;
pub const RTCSceneFlags_RTC_SCENE_FLAG_ROBUST: RTCSceneFlags = 1 << 2;

pub type RTCGeometryType = c_uint;
pub const RTCGeometryType_RTC_GEOMETRY_TYPE_TRIANGLE: RTCGeometryType = 0;
pub const RTCGeometryType_RTC_GEOMETRY_TYPE_QUAD: RTCGeometryType = 1;
pub const RTCGeometryType_RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE: RTCGeometryType = 24;
pub const RTCGeometryType_RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE: RTCGeometryType = 25;
pub const RTCGeometryType_RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE: RTCGeometryType = 26;
pub const RTCGeometryType_RTC_GEOMETRY_TYPE_USER: RTCGeometryType = 120;
pub const RTCGeometryType_RTC_GEOMETRY_TYPE_INSTANCE: RTCGeometryType = 121;

pub type RTCBufferType = c_uint;
pub const RTCBufferType_RTC_BUFFER_TYPE_INDEX: RTCBufferType = 0;
pub const RTCBufferType_RTC_BUFFER_TYPE_VERTEX: RTCBufferType = 1;
pub const RTCBufferType_RTC_BUFFER_TYPE_NORMAL: RTCBufferType = 3;

pub type RTCFormat = c_uint;
pub const RTCFormat_RTC_FORMAT_UINT: RTCFormat = 0x5001;
pub const RTCFormat_RTC_FORMAT_UINT3: RTCFormat = 0x5003;
pub const RTCFormat_RTC_FORMAT_UINT4: RTCFormat = 0x5004;
pub const RTCFormat_RTC_FORMAT_FLOAT3: RTCFormat = 0x9003;
pub const RTCFormat_RTC_FORMAT_FLOAT4: RTCFormat = 0x9004;
pub const RTCFormat_RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR: RTCFormat = 0x9234;

/// `RTCRayQueryFlags` (rtcore_common.h).
pub type RTCRayQueryFlags = c_uint;
pub const RTCRayQueryFlags_RTC_RAY_QUERY_FLAG_INCOHERENT: RTCRayQueryFlags = 0;

/// `RTCFeatureFlags` (rtcore_common.h): the features traversal may meet (used by SYCL builds).
pub type RTCFeatureFlags = c_uint;
pub const RTCFeatureFlags_RTC_FEATURE_FLAG_ALL: RTCFeatureFlags = 0xffff_ffff;

// --- Structures ---

/// An affine transform as T · R · U: translation, a rotation quaternion (r + i·x + j·y + k·z)
/// and an upper-triangular scale/skew/shift matrix (rtcore_quaternion.h; the same in Embree 3).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCQuaternionDecomposition {
    pub scale_x: f32,
    pub scale_y: f32,
    pub scale_z: f32,
    pub skew_xy: f32,
    pub skew_xz: f32,
    pub skew_yz: f32,
    pub shift_x: f32,
    pub shift_y: f32,
    pub shift_z: f32,
    pub quaternion_r: f32,
    pub quaternion_i: f32,
    pub quaternion_j: f32,
    pub quaternion_k: f32,
    pub translation_x: f32,
    pub translation_y: f32,
    pub translation_z: f32,
}

/// One ray (rtcore_ray.h).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRay {
    pub org_x: f32,
    pub org_y: f32,
    pub org_z: f32,
    pub tnear: f32,
    pub dir_x: f32,
    pub dir_y: f32,
    pub dir_z: f32,
    pub time: f32,
    pub tfar: f32,
    pub mask: c_uint,
    pub id: c_uint,
    pub flags: c_uint,
}

/// One hit (rtcore_ray.h), with the instance-array stack `instPrimID` of Embree ≥ 4.3.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCHit {
    pub Ng_x: f32,
    pub Ng_y: f32,
    pub Ng_z: f32,
    pub u: f32,
    pub v: f32,
    pub primID: c_uint,
    pub geomID: c_uint,
    pub instID: [c_uint; RTC_MAX_INSTANCE_LEVEL_COUNT as usize],
    pub instPrimID: [c_uint; RTC_MAX_INSTANCE_LEVEL_COUNT as usize],
}

/// A ray and its hit, as `rtcIntersect1` reads and writes them.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRayHit {
    pub ray: RTCRay,
    pub hit: RTCHit,
}

/// Ray and hit packets of run-time width N, seen by callbacks (layout in rtcore_ray.h).
#[repr(C)]
pub struct RTCRayN {
    _private: [u8; 0],
}
#[repr(C)]
pub struct RTCRayHitN {
    _private: [u8; 0],
}

/// The per-query context (rtcore_common.h): the instance stacks Embree maintains while it
/// traverses instances. With one instance level there is no `instStackSize` field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRayQueryContext {
    pub instID: [c_uint; RTC_MAX_INSTANCE_LEVEL_COUNT as usize],
    pub instPrimID: [c_uint; RTC_MAX_INSTANCE_LEVEL_COUNT as usize],
}

/// Arguments of a filter callback; prism sets none, so the fields stay opaque.
#[repr(C)]
pub struct RTCFilterFunctionNArguments {
    _private: [u8; 0],
}
pub type RTCFilterFunctionN = Option<unsafe extern "C" fn(args: *const RTCFilterFunctionNArguments)>;

/// Optional arguments of `rtcIntersect1` (rtcore_scene.h).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RTCIntersectArguments {
    pub flags: RTCRayQueryFlags,
    pub feature_mask: RTCFeatureFlags,
    pub context: *mut RTCRayQueryContext,
    pub filter: RTCFilterFunctionN,
    pub intersect: RTCIntersectFunctionN,
    /// Present only in libraries built with `EMBREE_MIN_WIDTH`; always declared (as 0, the value
    /// `rtcInitIntersectArguments` gives it), so that such a library never reads past the struct.
    pub minWidthDistanceFactor: f32,
}

/// Optional arguments of `rtcOccluded1` (rtcore_scene.h).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RTCOccludedArguments {
    pub flags: RTCRayQueryFlags,
    pub feature_mask: RTCFeatureFlags,
    pub context: *mut RTCRayQueryContext,
    pub filter: RTCFilterFunctionN,
    pub occluded: RTCOccludedFunctionN,
    /// As in [`RTCIntersectArguments`].
    pub minWidthDistanceFactor: f32,
}

/// An axis-aligned box (rtcore_common.h).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCBounds {
    pub lower_x: f32,
    pub lower_y: f32,
    pub lower_z: f32,
    pub align0: f32,
    pub upper_x: f32,
    pub upper_y: f32,
    pub upper_z: f32,
    pub align1: f32,
}

/// Arguments of a user geometry's bounds callback (rtcore_geometry.h).
#[repr(C)]
#[derive(Debug)]
pub struct RTCBoundsFunctionArguments {
    pub geometryUserPtr: *mut c_void,
    pub primID: c_uint,
    pub timeStep: c_uint,
    pub bounds_o: *mut RTCBounds,
}
pub type RTCBoundsFunction = Option<unsafe extern "C" fn(args: *const RTCBoundsFunctionArguments)>;

/// Arguments of a user geometry's intersect callback (rtcore_geometry.h).
#[repr(C)]
#[derive(Debug)]
pub struct RTCIntersectFunctionNArguments {
    pub valid: *mut c_int,
    pub geometryUserPtr: *mut c_void,
    pub primID: c_uint,
    pub context: *mut RTCRayQueryContext,
    pub rayhit: *mut RTCRayHitN,
    pub N: c_uint,
    pub geomID: c_uint,
}
pub type RTCIntersectFunctionN = Option<unsafe extern "C" fn(args: *const RTCIntersectFunctionNArguments)>;

/// Arguments of a user geometry's occluded callback (rtcore_geometry.h).
#[repr(C)]
#[derive(Debug)]
pub struct RTCOccludedFunctionNArguments {
    pub valid: *mut c_int,
    pub geometryUserPtr: *mut c_void,
    pub primID: c_uint,
    pub context: *mut RTCRayQueryContext,
    pub ray: *mut RTCRayN,
    pub N: c_uint,
    pub geomID: c_uint,
}
pub type RTCOccludedFunctionN = Option<unsafe extern "C" fn(args: *const RTCOccludedFunctionNArguments)>;

/// Error callback (rtcore_device.h).
pub type RTCErrorFunction = Option<unsafe extern "C" fn(userPtr: *mut c_void, code: RTCError, str_: *const c_char)>;
/// Memory monitor callback (rtcore_device.h): `bytes` allocated (> 0) or freed (< 0).
pub type RTCMemoryMonitorFunction = Option<unsafe extern "C" fn(ptr: *mut c_void, bytes: isize, post: bool) -> bool>;

extern "C" {
    // rtcore_device.h
    pub fn rtcNewDevice(config: *const c_char) -> RTCDevice;
    pub fn rtcReleaseDevice(device: RTCDevice);
    pub fn rtcGetDeviceProperty(device: RTCDevice, prop: RTCDeviceProperty) -> isize;
    pub fn rtcGetDeviceError(device: RTCDevice) -> RTCError;
    pub fn rtcSetDeviceErrorFunction(device: RTCDevice, error: RTCErrorFunction, userPtr: *mut c_void);
    pub fn rtcSetDeviceMemoryMonitorFunction(
        device: RTCDevice,
        memoryMonitor: RTCMemoryMonitorFunction,
        userPtr: *mut c_void,
    );

    // rtcore_scene.h
    pub fn rtcNewScene(device: RTCDevice) -> RTCScene;
    pub fn rtcReleaseScene(scene: RTCScene);
    pub fn rtcAttachGeometryByID(scene: RTCScene, geometry: RTCGeometry, geomID: c_uint);
    pub fn rtcCommitScene(scene: RTCScene);
    pub fn rtcSetSceneBuildQuality(scene: RTCScene, quality: RTCBuildQuality);
    pub fn rtcSetSceneFlags(scene: RTCScene, flags: RTCSceneFlags);
    pub fn rtcIntersect1(scene: RTCScene, rayhit: *mut RTCRayHit, args: *mut RTCIntersectArguments);
    pub fn rtcOccluded1(scene: RTCScene, ray: *mut RTCRay, args: *mut RTCOccludedArguments);

    // rtcore_geometry.h
    pub fn rtcNewGeometry(device: RTCDevice, type_: RTCGeometryType) -> RTCGeometry;
    pub fn rtcReleaseGeometry(geometry: RTCGeometry);
    pub fn rtcCommitGeometry(geometry: RTCGeometry);
    pub fn rtcSetNewGeometryBuffer(
        geometry: RTCGeometry,
        type_: RTCBufferType,
        slot: c_uint,
        format: RTCFormat,
        byteStride: usize,
        itemCount: usize,
    ) -> *mut c_void;
    pub fn rtcSetSharedGeometryBuffer(
        geometry: RTCGeometry,
        type_: RTCBufferType,
        slot: c_uint,
        format: RTCFormat,
        ptr: *const c_void,
        byteOffset: usize,
        byteStride: usize,
        itemCount: usize,
    );
    pub fn rtcSetGeometryBuildQuality(geometry: RTCGeometry, quality: RTCBuildQuality);
    pub fn rtcSetGeometryUserPrimitiveCount(geometry: RTCGeometry, userPrimitiveCount: c_uint);
    pub fn rtcSetGeometryUserData(geometry: RTCGeometry, ptr: *mut c_void);
    pub fn rtcSetGeometryBoundsFunction(geometry: RTCGeometry, bounds: RTCBoundsFunction, userPtr: *mut c_void);
    pub fn rtcSetGeometryIntersectFunction(geometry: RTCGeometry, intersect: RTCIntersectFunctionN);
    pub fn rtcSetGeometryOccludedFunction(geometry: RTCGeometry, occluded: RTCOccludedFunctionN);
    pub fn rtcSetGeometryInstancedScene(geometry: RTCGeometry, scene: RTCScene);
    pub fn rtcSetGeometryTransform(geometry: RTCGeometry, timeStep: c_uint, format: RTCFormat, xfm: *const c_void);
    pub fn rtcSetGeometryTimeStepCount(geometry: RTCGeometry, timeStepCount: c_uint);
    pub fn rtcSetGeometryTimeRange(geometry: RTCGeometry, startTime: f32, endTime: f32);
    pub fn rtcSetGeometryTransformQuaternion(
        geometry: RTCGeometry,
        timeStep: c_uint,
        qd: *const RTCQuaternionDecomposition,
    );
}
