//! The handful of Intel Open Image Denoise 2 C functions prism calls (`OpenImageDenoise/oidn.h`),
//! read from a library loaded at run time, behind one safe call: [`Oidn::filter`] runs one filter
//! over caller-owned images. The only `unsafe` code of the denoiser lives here.

use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::path::Path;
use std::ptr::NonNull;

/// `OIDN_DEVICE_TYPE_CPU` (`OIDNDeviceType`).
const DEVICE_TYPE_CPU: c_int = 1;
/// `OIDN_FORMAT_FLOAT3` (`OIDNFormat`): three packed f32 per pixel.
const FORMAT_FLOAT3: c_int = 3;
/// `OIDN_ERROR_NONE` (`OIDNError`).
const ERROR_NONE: c_int = 0;

type Handle = *mut c_void;
/// `OIDNDevice oidnNewDevice(OIDNDeviceType)`.
type NewDeviceFn = unsafe extern "C" fn(c_int) -> Handle;
/// `void oidnCommitDevice(OIDNDevice)`, `oidnReleaseDevice`, `oidnCommitFilter`,
/// `oidnExecuteFilter`, `oidnReleaseFilter`: one handle, nothing returned.
type HandleFn = unsafe extern "C" fn(Handle);
/// `void oidnSetDeviceInt(OIDNDevice, const char* name, int value)`.
type SetDeviceIntFn = unsafe extern "C" fn(Handle, *const c_char, c_int);
/// `int oidnGetDeviceInt(OIDNDevice, const char* name)` (the tests read a device's parameters).
#[cfg(test)]
type GetDeviceIntFn = unsafe extern "C" fn(Handle, *const c_char) -> c_int;
/// `OIDNError oidnGetDeviceError(OIDNDevice, const char** outMessage)`.
type GetDeviceErrorFn = unsafe extern "C" fn(Handle, *mut *const c_char) -> c_int;
/// `OIDNFilter oidnNewFilter(OIDNDevice, const char* type)`.
type NewFilterFn = unsafe extern "C" fn(Handle, *const c_char) -> Handle;
/// `void oidnSetSharedFilterImage(OIDNFilter, const char* name, void* devPtr, OIDNFormat,
/// size_t width, size_t height, size_t byteOffset, size_t pixelByteStride, size_t rowByteStride)`.
type SetSharedFilterImageFn =
    unsafe extern "C" fn(Handle, *const c_char, *mut c_void, c_int, usize, usize, usize, usize, usize);
/// `void oidnSetFilterBool(OIDNFilter, const char* name, bool value)`.
type SetFilterBoolFn = unsafe extern "C" fn(Handle, *const c_char, bool);

/// The loaded library and the functions read from it.
pub(super) struct Oidn {
    new_device: NewDeviceFn,
    commit_device: HandleFn,
    set_device_int: SetDeviceIntFn,
    #[cfg(test)]
    get_device_int: GetDeviceIntFn,
    release_device: HandleFn,
    get_device_error: GetDeviceErrorFn,
    new_filter: NewFilterFn,
    set_shared_filter_image: SetSharedFilterImageFn,
    set_filter_bool: SetFilterBoolFn,
    commit_filter: HandleFn,
    execute_filter: HandleFn,
    release_filter: HandleFn,
    /// Keeps the function pointers above valid.
    _library: libloading::Library,
}

/// One image a filter reads or writes: its OIDN name ("color", "albedo", "normal", "output").
pub(super) enum Image<'a> {
    /// An input, read only.
    In(&'static str, &'a [f32]),
    /// The output.
    Out(&'a mut [f32]),
}

impl Oidn {
    /// Loads the library at `path` (a bare file name is searched for as `dlopen` does).
    pub(super) fn load(path: &Path) -> Result<Self, libloading::Error> {
        // SAFETY: loading runs the library's initialisers; OIDN's (and oneTBB's, which it loads)
        // have no preconditions on the caller.
        let library = unsafe { libloading::Library::new(path) }?;
        // SAFETY: each symbol is read as the exact C signature oidn.h (OIDN 2) declares for it,
        // enums being C ints; the pointers stay valid because `library` is kept with them.
        unsafe {
            Ok(Oidn {
                new_device: *library.get(b"oidnNewDevice\0")?,
                commit_device: *library.get(b"oidnCommitDevice\0")?,
                set_device_int: *library.get(b"oidnSetDeviceInt\0")?,
                #[cfg(test)]
                get_device_int: *library.get(b"oidnGetDeviceInt\0")?,
                release_device: *library.get(b"oidnReleaseDevice\0")?,
                get_device_error: *library.get(b"oidnGetDeviceError\0")?,
                new_filter: *library.get(b"oidnNewFilter\0")?,
                set_shared_filter_image: *library.get(b"oidnSetSharedFilterImage\0")?,
                set_filter_bool: *library.get(b"oidnSetFilterBool\0")?,
                commit_filter: *library.get(b"oidnCommitFilter\0")?,
                execute_filter: *library.get(b"oidnExecuteFilter\0")?,
                release_filter: *library.get(b"oidnReleaseFilter\0")?,
                _library: library,
            })
        }
    }
}

/// A committed CPU device, released on drop.
pub(super) struct Device<'a> {
    oidn: &'a Oidn,
    raw: NonNull<c_void>,
}

impl<'a> Device<'a> {
    /// A new CPU device of `threads` worker threads (`None`: OIDN's default, every core),
    /// committed.
    pub(super) fn new(oidn: &'a Oidn, threads: Option<usize>) -> Result<Self, String> {
        // SAFETY: oidnNewDevice takes an OIDNDeviceType by value and returns a new handle or NULL.
        let raw = unsafe { (oidn.new_device)(DEVICE_TYPE_CPU) };
        error(oidn, raw)?;
        let device = Device { oidn, raw: NonNull::new(raw).ok_or("oidnNewDevice returned no device")? };
        if let Some(n) = threads {
            let n = c_int::try_from(n).map_err(|_| format!("{n} threads"))?;
            // SAFETY: a live device handle not yet committed (OIDN reads numThreads at commit)
            // and a NUL-terminated name.
            unsafe { (oidn.set_device_int)(device.raw.as_ptr(), c"numThreads".as_ptr(), n) };
        }
        // SAFETY: a live device handle, owned by `device`.
        unsafe { (oidn.commit_device)(device.raw.as_ptr()) };
        device.check()?;
        Ok(device)
    }

    /// Runs the filter `kind` (e.g. "RT") over `images`, each `width` × `height` packed RGB
    /// f32 (row-major), with the boolean parameters `flags`; the output is written when it
    /// returns. An error is OIDN's own message.
    pub(super) fn filter(
        &self,
        kind: &str,
        images: &mut [Image<'_>],
        flags: &[(&str, bool)],
        width: usize,
        height: usize,
    ) -> Result<(), String> {
        let n = width.checked_mul(height).and_then(|p| p.checked_mul(3)).ok_or("image too large")?;
        for image in images.iter() {
            let len = match image {
                Image::In(_, data) => data.len(),
                Image::Out(data) => data.len(),
            };
            if len != n {
                return Err(format!("an image holds {len} values, not {width}x{height}x3"));
            }
        }
        let cstr = |s: &str| CString::new(s).map_err(|_| format!("name {s:?} holds a NUL byte"));
        let kind = cstr(kind)?;
        let names: Vec<CString> = images
            .iter()
            .map(|i| cstr(if let Image::In(name, _) = i { name } else { "output" }))
            .collect::<Result<_, _>>()?;
        let flag_names: Vec<CString> = flags.iter().map(|(name, _)| cstr(name)).collect::<Result<_, _>>()?;
        let oidn = self.oidn;
        // SAFETY: a live device and a NUL-terminated filter type that outlives the call.
        let raw = unsafe { (oidn.new_filter)(self.raw.as_ptr(), kind.as_ptr()) };
        self.check()?;
        let filter = Filter { oidn, raw: NonNull::new(raw).ok_or("oidnNewFilter returned no filter")? };
        let stride = 3 * size_of::<f32>();
        for (image, name) in images.iter_mut().zip(&names) {
            let ptr = match image {
                // OIDN reads an input image and never writes it.
                Image::In(_, data) => data.as_ptr().cast_mut().cast::<c_void>(),
                Image::Out(data) => data.as_mut_ptr().cast::<c_void>(),
            };
            // SAFETY: a live filter; a NUL-terminated name; `ptr` points at width·height packed
            // FLOAT3 pixels (length checked above), host memory a CPU device can use, borrowed
            // (the output exclusively) until this function returns, after the filter has run
            // and been released.
            unsafe {
                (oidn.set_shared_filter_image)(
                    filter.raw.as_ptr(),
                    name.as_ptr(),
                    ptr,
                    FORMAT_FLOAT3,
                    width,
                    height,
                    0,
                    stride,
                    stride * width,
                )
            };
            self.check()?;
        }
        for ((_, value), name) in flags.iter().zip(&flag_names) {
            // SAFETY: a live filter and a NUL-terminated parameter name that outlives the call.
            unsafe { (oidn.set_filter_bool)(filter.raw.as_ptr(), name.as_ptr(), *value) };
            self.check()?;
        }
        // SAFETY: a live filter whose images are all set and valid (above).
        unsafe { (oidn.commit_filter)(filter.raw.as_ptr()) };
        self.check()?;
        // SAFETY: as above; oidnExecuteFilter returns once the output is written.
        unsafe { (oidn.execute_filter)(filter.raw.as_ptr()) };
        self.check()?;
        drop(filter);
        Ok(())
    }

    /// The device's pending error.
    /// The worker threads the committed device runs (its "numThreads" parameter).
    #[cfg(test)]
    pub(super) fn threads(&self) -> i32 {
        // SAFETY: a live device handle and a NUL-terminated name.
        unsafe { (self.oidn.get_device_int)(self.raw.as_ptr(), c"numThreads".as_ptr()) }
    }

    fn check(&self) -> Result<(), String> {
        error(self.oidn, self.raw.as_ptr())
    }
}

/// The pending error of device `raw` (or, for NULL, of a failed oidnNewDevice), as OIDN words
/// it, on one line.
fn error(oidn: &Oidn, raw: Handle) -> Result<(), String> {
    let mut message: *const c_char = std::ptr::null();
    // SAFETY: oidnGetDeviceError accepts a live device or NULL (the error of a failed
    // oidnNewDevice) and writes a pointer to a NUL-terminated message, or NULL, valid until
    // the next call on the device; it is copied at once.
    let code = unsafe { (oidn.get_device_error)(raw, &mut message) };
    if code == ERROR_NONE {
        return Ok(());
    }
    let text = if message.is_null() {
        String::new()
    } else {
        // SAFETY: non-NULL: a NUL-terminated string owned by OIDN, valid until the next call.
        unsafe { CStr::from_ptr(message) }.to_string_lossy().into_owned()
    };
    Err(match text.is_empty() {
        true => format!("error code {code}"),
        false => text.lines().collect::<Vec<_>>().join(" "),
    })
}

impl Drop for Device<'_> {
    fn drop(&mut self) {
        // SAFETY: the handle was returned by oidnNewDevice and is released once, after its
        // filters (each released within the call that made it).
        unsafe { (self.oidn.release_device)(self.raw.as_ptr()) };
    }
}

/// A filter handle, released on drop.
struct Filter<'a> {
    oidn: &'a Oidn,
    raw: NonNull<c_void>,
}

impl Drop for Filter<'_> {
    fn drop(&mut self) {
        // SAFETY: the handle was returned by oidnNewFilter and is released once.
        unsafe { (self.oidn.release_filter)(self.raw.as_ptr()) };
    }
}
