//! Safe wrapper over the OpenImageIO C++ shim (`cpp/oiio_shim.{h,cpp}`), a shared library that
//! build.rs compiles and this module loads on first use, so that a process which never needs
//! OpenImageIO does not pay for loading it (~260 shared libraries, 0.26 s).
//!
//! The only `unsafe` code of the image module lives here. The shim catches every C++
//! exception and reports failures through a caller-owned message buffer.

use std::ffi::{c_char, c_int, CString};
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use super::format::FileFormat;
use super::{srgb, ExrSample, Image, WriteOptions};

// Pixel format codes, mirroring `enum prism_oiio_format` in cpp/oiio_shim.h.
const HALF: c_int = 0;
const FLOAT: c_int = 1;
const UINT8: c_int = 2;
const UINT16: c_int = 3;

/// Size of the message buffer handed to the shim; longer messages are truncated.
const ERR_LEN: usize = 1024;

/// Why the shim could not be loaded; kept for the process, so it is `Clone`.
#[derive(Clone, Debug, thiserror::Error)]
pub(crate) enum ShimError {
    /// No candidate path holds the shim.
    #[error("the OpenImageIO shim libprism_oiio_shim.so was not found (set PRISM_OIIO_SHIM to its path)")]
    NotFound,
    /// The library or one of its symbols failed to load.
    #[error("cannot load the OpenImageIO shim {}: {cause}", path.display())]
    Load { path: PathBuf, cause: Arc<libloading::Error> },
}

/// Why OpenImageIO could not write or read a file.
#[derive(Debug, thiserror::Error)]
pub(crate) enum OiioError {
    /// The shim is unavailable.
    #[error(transparent)]
    Shim(#[from] ShimError),
    /// The path cannot be passed to C as UTF-8.
    #[error("path is not valid UTF-8")]
    NonUtf8Path,
    /// The path cannot be passed to C as a NUL-terminated string.
    #[error("path contains a NUL byte")]
    NulInPath,
    /// A size beyond the C `int` the shim takes.
    #[error("{what} {value} is too large for OpenImageIO")]
    TooLargeForInt { what: &'static str, value: u32 },
    /// OpenImageIO's own message, as the shim reports it.
    #[error("{0}")]
    Library(String),
    /// The file's header gives no pixels.
    #[error("image reports an empty size {width}x{height}x{channels}")]
    EmptySize { width: c_int, height: c_int, channels: c_int },
    /// width·height·channels overflows.
    #[error("image too large")]
    TooLarge,
    /// The samples cannot be allocated.
    #[error("cannot allocate {0} samples")]
    Alloc(usize),
    /// The header's size is refused before reading ([`super::check_read_size`]).
    #[error(transparent)]
    Refused(Box<super::ImageError>),
}

// Attribute types, mirroring `enum prism_oiio_attr_type` in cpp/oiio_shim.h.
const ATTR_FLOAT: c_int = 0;
const ATTR_INT: c_int = 1;
const ATTR_STRING: c_int = 2;
const ATTR_M44F: c_int = 3;
const ATTR_FLOAT8: c_int = 4;

/// `struct prism_oiio_attr` of cpp/oiio_shim.h: a header attribute by OpenImageIO's name.
#[repr(C)]
struct Attr {
    name: *const c_char,
    kind: c_int,
    values: *const f32,
    int_value: c_int,
    text: *const c_char,
}

/// An attribute's owned parts, which the [`Attr`] handed to the shim point into.
struct OwnedAttr {
    name: CString,
    kind: c_int,
    values: Vec<f32>,
    int_value: c_int,
    text: Option<CString>,
}

impl OwnedAttr {
    fn new(name: &str, kind: c_int, values: Vec<f32>, int_value: c_int, text: Option<&str>) -> Option<Self> {
        let text = match text {
            Some(t) => Some(CString::new(t).ok()?),
            None => None,
        };
        Some(Self { name: CString::new(name).ok()?, kind, values, int_value, text })
    }

    /// The C view, valid while `self` lives.
    fn as_c(&self) -> Attr {
        Attr {
            name: self.name.as_ptr(),
            kind: self.kind,
            values: if self.values.is_empty() { std::ptr::null() } else { self.values.as_ptr() },
            int_value: self.int_value,
            text: self.text.as_ref().map_or(std::ptr::null(), |t| t.as_ptr()),
        }
    }
}

/// The OpenEXR header attributes of `meta` by OpenImageIO's names (it writes `chromaticities`,
/// `worldtocamera` and `worldtoNDC` as OpenEXR's standard attributes, the rest by name), as the
/// pure-Rust writer writes them. A text holding a NUL byte is left out.
fn exr_attributes(meta: &super::ImageMeta) -> Vec<OwnedAttr> {
    let mut v = Vec::new();
    if let Some(c) = meta.color_space {
        let [r, g, b] = c.primaries;
        let xy = vec![r[0], r[1], g[0], g[1], b[0], b[1], c.white[0], c.white[1]];
        v.extend(OwnedAttr::new("chromaticities", ATTR_FLOAT8, xy, 0, None));
    }
    if let Some(t) = meta.render_time_seconds {
        v.extend(OwnedAttr::new("renderTimeSeconds", ATTR_FLOAT, vec![t as f32], 0, None));
    }
    if let Some(e) = meta.estimated_error {
        v.extend(OwnedAttr::new("prism:estimatedError", ATTR_FLOAT, vec![e as f32], 0, None));
    }
    if let Some(n) = meta.samples_per_pixel {
        v.extend(OwnedAttr::new(
            "samplesPerPixel",
            ATTR_INT,
            Vec::new(),
            c_int::try_from(n).unwrap_or(c_int::MAX),
            None,
        ));
    }
    for (name, m) in [("worldtocamera", meta.world_to_camera), ("worldtoNDC", meta.world_to_ndc)] {
        if let Some(m) = m {
            v.extend(OwnedAttr::new(name, ATTR_M44F, m.as_flattened().to_vec(), 0, None));
        }
    }
    for (name, text) in meta.exr_strings() {
        v.extend(OwnedAttr::new(name, ATTR_STRING, Vec::new(), 0, Some(&text)));
    }
    v
}

/// `int prism_oiio_write_meta(const char*, int, int, int, const float*, int, int, const int*,
/// const struct prism_oiio_attr*, int, char*, size_t)`.
type WriteFn = unsafe extern "C" fn(
    *const c_char,
    c_int,
    c_int,
    c_int,
    *const f32,
    c_int,
    c_int,
    *const c_int,
    *const Attr,
    c_int,
    *mut c_char,
    usize,
) -> c_int;
/// `int prism_oiio_read_info(const char*, int*, int*, int*, int*, char*, size_t)`.
type ReadInfoFn =
    unsafe extern "C" fn(*const c_char, *mut c_int, *mut c_int, *mut c_int, *mut c_int, *mut c_char, usize) -> c_int;
/// `int prism_oiio_read(const char*, int, int, int, float*, size_t, char*, size_t)`.
type ReadFn = unsafe extern "C" fn(*const c_char, c_int, c_int, c_int, *mut f32, usize, *mut c_char, usize) -> c_int;

/// The shim's three entry points, resolved from the loaded library (cpp/oiio_shim.h).
struct Shim {
    write: WriteFn,
    read_info: ReadInfoFn,
    read: ReadFn,
    /// Keeps the library mapped for as long as the pointers above are used (the whole process).
    _library: libloading::Library,
}

/// Where the shim may be: `PRISM_OIIO_SHIM` at run time, beside the executable, then where the
/// build script wrote it.
fn shim_candidates() -> Vec<PathBuf> {
    const NAME: &str = "libprism_oiio_shim.so";
    let mut paths: Vec<PathBuf> = std::env::var_os("PRISM_OIIO_SHIM").map(PathBuf::from).into_iter().collect();
    if let Some(dir) = std::env::current_exe().ok().as_deref().and_then(Path::parent) {
        paths.push(dir.join(NAME));
    }
    paths.push(PathBuf::from(env!("PRISM_OIIO_SHIM")));
    paths
}

/// The shim, loaded (with OpenImageIO and its dependencies) on the first call.
fn shim() -> Result<&'static Shim, ShimError> {
    static SHIM: OnceLock<Result<Shim, ShimError>> = OnceLock::new();
    SHIM.get_or_init(|| {
        let path = shim_candidates().into_iter().find(|p| p.is_file()).ok_or(ShimError::NotFound)?;
        let fail = |e: libloading::Error| ShimError::Load { path: path.clone(), cause: Arc::new(e) };
        // SAFETY: the library is prism's own shim built by build.rs from cpp/oiio_shim.cpp, whose
        // initialisers (and OpenImageIO's) have no preconditions on the caller.
        let library = unsafe { libloading::Library::new(&path) }.map_err(fail)?;
        // SAFETY: each symbol is declared in cpp/oiio_shim.h with exactly the C signature of the
        // type it is read as; the pointers stay valid because `library` is kept with them.
        unsafe {
            Ok(Shim {
                write: *library.get::<WriteFn>(b"prism_oiio_write_meta\0").map_err(fail)?,
                read_info: *library.get::<ReadInfoFn>(b"prism_oiio_read_info\0").map_err(fail)?,
                read: *library.get::<ReadFn>(b"prism_oiio_read\0").map_err(fail)?,
                _library: library,
            })
        }
    })
    .as_ref()
    .map_err(Clone::clone)
}

fn c_path(path: &Path) -> Result<CString, OiioError> {
    let s = path.to_str().ok_or(OiioError::NonUtf8Path)?;
    CString::new(s).map_err(|_| OiioError::NulInPath)
}

fn message(buf: &[c_char; ERR_LEN]) -> OiioError {
    // The shim always NUL-terminates within the buffer; guard anyway by bounding the scan.
    let bytes: Vec<u8> = buf.iter().take_while(|&&c| c != 0).map(|&c| c as u8).collect();
    let msg = String::from_utf8_lossy(&bytes).trim().to_string();
    if msg.is_empty() {
        OiioError::Library("OpenImageIO reported an error without a message".into())
    } else {
        OiioError::Library(msg)
    }
}

fn to_c_int(v: u32, what: &'static str) -> Result<c_int, OiioError> {
    c_int::try_from(v).map_err(|_| OiioError::TooLargeForInt { what, value: v })
}

/// Writes `img` (already validated for `format`) to `path` through OpenImageIO.
pub(crate) fn write(path: &Path, format: FileFormat, img: &Image, opts: &WriteOptions) -> Result<(), OiioError> {
    let shim = shim()?;
    let cpath = c_path(path)?;
    let c = img.channels as usize;
    // Integer formats: quantise here exactly as the Rust path does (code / max is exact
    // enough that OIIO's own round(v·max) returns the same code), so both backends agree.
    let (pixels, code): (std::borrow::Cow<[f32]>, c_int) = match format {
        FileFormat::Exr => (
            img.data.as_slice().into(),
            match opts.exr_sample {
                ExrSample::Half => HALF,
                ExrSample::Float => FLOAT,
            },
        ),
        FileFormat::Hdr => (img.data.as_slice().into(), FLOAT),
        FileFormat::Tiff if opts.tiff_16bit => (
            srgb::encode_to_codes(&img.data, c, 65535)
                .into_iter()
                .map(|v| v as f32 / 65535.0)
                .collect::<Vec<f32>>()
                .into(),
            UINT16,
        ),
        FileFormat::Png | FileFormat::Jpeg | FileFormat::Tiff => (
            srgb::encode_to_codes(&img.data, c, 255).into_iter().map(|v| v as f32 / 255.0).collect::<Vec<f32>>().into(),
            UINT8,
        ),
    };
    let quality = if format == FileFormat::Jpeg { c_int::from(opts.jpeg_quality.clamp(1, 100)) } else { 0 };
    // x, y of the first pixel and the full size; zeros: the image is whole.
    let window = match (format, opts.window) {
        (FileFormat::Exr, Some(w)) => [
            to_c_int(w.x0, "crop origin")?,
            to_c_int(w.y0, "crop origin")?,
            to_c_int(w.full_width, "full width")?,
            to_c_int(w.full_height, "full height")?,
        ],
        _ => [0; 4],
    };
    let owned = if format == FileFormat::Exr { exr_attributes(&opts.meta) } else { Vec::new() };
    let attrs: Vec<Attr> = owned.iter().map(OwnedAttr::as_c).collect();
    let mut err = [0 as c_char; ERR_LEN];
    // SAFETY: `cpath` is a live NUL-terminated string; `window` is 4 live integers; `pixels` holds exactly
    // width·height·channels floats (checked by `Image::validate` before we get here) and
    // outlives the call; `attrs` points into `owned` (NUL-terminated names and texts, 1, 8 or
    // 16 floats as each type needs), both alive for the call, and we pass its length; `err` is
    // a writable buffer of ERR_LEN bytes whose length we pass.
    let rc = unsafe {
        (shim.write)(
            cpath.as_ptr(),
            to_c_int(img.width, "width")?,
            to_c_int(img.height, "height")?,
            to_c_int(img.channels, "channel count")?,
            pixels.as_ptr(),
            code,
            quality,
            window.as_ptr(),
            attrs.as_ptr(),
            attrs.len() as c_int,
            err.as_mut_ptr(),
            ERR_LEN,
        )
    };
    if rc == 0 {
        Ok(())
    } else {
        Err(message(&err))
    }
}

/// Reads `path` through OpenImageIO into linear floats (integer formats are sRGB-decoded).
pub(crate) fn read(path: &Path) -> Result<Image, OiioError> {
    let shim = shim()?;
    let cpath = c_path(path)?;
    let (mut w, mut h, mut c, mut fmt): (c_int, c_int, c_int, c_int) = (0, 0, 0, 0);
    let mut err = [0 as c_char; ERR_LEN];
    // SAFETY: `cpath` is a live NUL-terminated string; the four out-pointers point at live
    // local integers; `err` is a writable buffer of ERR_LEN bytes whose length we pass.
    let rc = unsafe { (shim.read_info)(cpath.as_ptr(), &mut w, &mut h, &mut c, &mut fmt, err.as_mut_ptr(), ERR_LEN) };
    if rc != 0 {
        return Err(message(&err));
    }
    if w <= 0 || h <= 0 || c <= 0 {
        return Err(OiioError::EmptySize { width: w, height: h, channels: c });
    }
    super::check_read_size(path, w as u64, h as u64).map_err(|e| OiioError::Refused(Box::new(e)))?;
    let count =
        (w as usize).checked_mul(h as usize).and_then(|n| n.checked_mul(c as usize)).ok_or(OiioError::TooLarge)?;
    let mut data: Vec<f32> = Vec::new();
    data.try_reserve_exact(count).map_err(|_| OiioError::Alloc(count))?;
    data.resize(count, 0.0);
    // SAFETY: `data` holds exactly `count` = w·h·c writable floats and the shim writes at
    // most `pixel_count` of them; `cpath` and `err` are as above.
    let rc = unsafe { (shim.read)(cpath.as_ptr(), w, h, c, data.as_mut_ptr(), count, err.as_mut_ptr(), ERR_LEN) };
    if rc != 0 {
        return Err(message(&err));
    }
    match fmt {
        UINT8 => srgb::decode_normalised_in_place(&mut data, c as usize, 255),
        UINT16 => srgb::decode_normalised_in_place(&mut data, c as usize, 65535),
        _ => {}
    }
    Ok(Image { width: w as u32, height: h as u32, channels: c as u32, data })
}
