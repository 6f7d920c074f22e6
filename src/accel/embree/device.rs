//! An Embree device: created once per accelerator, released in Drop. Embree's error callback
//! reports into the log and keeps the last message so failures become a clear error.

pub use super::error::EmbreeError;
use super::ffi;
use std::ffi::{c_char, c_void, CStr};
use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::Mutex;

/// Owns an `RTCDevice`. The boxed `last_error` and `bytes` are callback user pointers, so they
/// must not move.
pub struct Device {
    raw: ffi::RTCDevice,
    last_error: Box<Mutex<Option<String>>>,
    /// Bytes Embree has allocated through this device and not yet freed (its memory monitor).
    bytes: Box<AtomicI64>,
}

// SAFETY: an RTCDevice is reference counted and internally synchronised; Embree allows using it
// from any thread. The error slot is behind a Mutex.
unsafe impl Send for Device {}
// SAFETY: see above; shared references only read the handle or lock the Mutex.
unsafe impl Sync for Device {}

unsafe extern "C" fn on_error(user: *mut c_void, code: ffi::RTCError, msg: *const c_char) {
    let text = if msg.is_null() {
        format!("code {code}")
    } else {
        // SAFETY: Embree passes a NUL-terminated message valid for the duration of the call.
        format!("{} (code {code})", unsafe { CStr::from_ptr(msg) }.to_string_lossy())
    };
    log::error!("embree: {text}");
    // SAFETY: `user` is the address of the Device's boxed Mutex, alive as long as the device.
    let slot = unsafe { &*(user as *const Mutex<Option<String>>) };
    if let Ok(mut s) = slot.lock() {
        *s = Some(text);
    }
}

unsafe extern "C" fn on_memory(user: *mut c_void, bytes: isize, _post: bool) -> bool {
    // SAFETY: `user` is the address of the Device's boxed counter, alive as long as the device.
    let counter = unsafe { &*(user as *const AtomicI64) };
    counter.fetch_add(bytes as i64, Ordering::Relaxed);
    // Never veto an allocation: the counter only measures.
    true
}

/// Environment variable holding an Embree device configuration string (Embree's
/// `rtcNewDevice` syntax, e.g. `threads=2,verbose=1`); empty or unset means the defaults.
pub const CONFIG_ENV: &str = "PRISM_EMBREE_CONFIG";

/// Embree's `RTCError` codes by name (rtcore_device.h; 7 exists in Embree ≥ 4.3 only), so an
/// error says what went wrong.
pub fn error_name(code: u32) -> &'static str {
    match code {
        0 => "no error",
        1 => "unknown error",
        2 => "invalid argument",
        3 => "invalid operation",
        4 => "out of memory",
        5 => "unsupported CPU",
        6 => "cancelled",
        7 => "GPU ray tracing support missing",
        _ => "unrecognised error code",
    }
}

impl Device {
    /// Creates a device from an Embree configuration string, without the library check
    /// ([`Device::with_config`] runs it). A failure (an unknown option, an unsupported CPU, no
    /// memory) is an error carrying Embree's code and message.
    pub(super) fn unchecked(config: &str) -> Result<Self, EmbreeError> {
        let c = std::ffi::CString::new(config)
            .map_err(|_| EmbreeError::Device(format!("configuration {config:?} contains a NUL byte")))?;
        // SAFETY: `c` is a valid NUL-terminated string for the duration of the call.
        let raw = unsafe { ffi::rtcNewDevice(if config.is_empty() { std::ptr::null() } else { c.as_ptr() }) };
        if raw.is_null() {
            // SAFETY: querying the error of a null device reports device-creation errors.
            let code = unsafe { ffi::rtcGetDeviceError(std::ptr::null_mut()) };
            // Embree reports a malformed configuration (e.g. `threads=abc`) as an unknown error.
            let hint = match code {
                1 | 2 if !config.is_empty() => format!(" (check the configuration {config:?} in {CONFIG_ENV})"),
                4 => " (not enough memory)".into(),
                5 => " (this CPU lacks the instruction set Embree was built for)".into(),
                _ => String::new(),
            };
            return Err(EmbreeError::Device(format!(
                "rtcNewDevice failed: {} (code {code}){hint}",
                error_name(code as u32)
            )));
        }
        let last_error = Box::new(Mutex::new(None));
        let user = &*last_error as *const Mutex<Option<String>> as *mut c_void;
        // SAFETY: `raw` is a valid device; `user` stays valid until Drop releases the device.
        unsafe { ffi::rtcSetDeviceErrorFunction(raw, Some(on_error), user) };
        let bytes = Box::new(AtomicI64::new(0));
        let counter = &*bytes as *const AtomicI64 as *mut c_void;
        // SAFETY: as above; the counter outlives the device.
        unsafe { ffi::rtcSetDeviceMemoryMonitorFunction(raw, Some(on_memory), counter) };
        Ok(Self { raw, last_error, bytes })
    }

    /// The raw handle, for the scene module.
    pub(super) fn raw(&self) -> ffi::RTCDevice {
        self.raw
    }

    /// Bytes currently allocated by Embree for this device's scenes and buffers.
    pub fn memory_bytes(&self) -> usize {
        self.bytes.load(Ordering::Relaxed).max(0) as usize
    }

    /// Takes the last error the callback reported, if any.
    pub fn take_error(&self) -> Option<String> {
        self.last_error.lock().ok().and_then(|mut s| s.take())
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: `raw` came from rtcNewDevice and is released exactly once.
        unsafe { ffi::rtcReleaseDevice(self.raw) };
    }
}
