//! NanoVDB files (Museth 2021, "NanoVDB: A GPU-friendly and portable VDB data structure for
//! real-time rendering and simulation", SIGGRAPH Talks), read in Rust without the C++ library.
//!
//! A `.nvdb` file is a sequence of segments: a 16-byte header (magic "NanoVDB0", version,
//! grid count, codec), one 176-byte record and a name per grid, then each grid's buffer, stored
//! as it is in memory (codec NONE) or zlib-compressed (ZIP) ([`file`]). A grid buffer holds the
//! grid's header (name, index-to-world map, world bounding box, voxel size, class, value type),
//! the tree's node offsets and counts, the root's table of 4096³ tiles, and three levels of
//! nodes: upper internal nodes of 32³ children (128³ voxels each), lower internal nodes of 16³
//! (8³ voxels each) and leaves of 8³ voxels ([`grid`]). An internal node's table entry is either
//! a child (its child-mask bit set) or a tile value; a voxel's value is looked up by descending
//! from the root by its (i, j, k).
//!
//! Supported: the file layout of NanoVDB major version 32 (OpenVDB 10's NanoVDB, 32.4, and
//! every 32.x: minor versions keep the layout), grids of `float` values, codecs NONE and ZIP.
//! Refused with a [`NanoVdbError`]: other major versions, BLOSC compression, other value types
//! (double, half, the quantised Fp4/Fp8/Fp16/FpN, vectors, masks, index grids) and every
//! malformed or truncated file.

pub mod file;
pub mod grid;
#[cfg(test)]
pub(crate) mod tests;

pub use file::{read_float_grids, NanoVdbFile};
pub use grid::FloatGrid;

/// Why a NanoVDB file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum NanoVdbError {
    /// The operating system's error reading the file.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The file does not start with NanoVDB's magic number.
    #[error("not a NanoVDB file (no \"NanoVDB0\" magic number)")]
    NotNanoVdb,
    /// Written on a big-endian machine.
    #[error("the NanoVDB file has reversed (big-endian) byte order")]
    ReversedEndianness,
    /// A major version whose layout prism does not read.
    #[error("NanoVDB version {major}.{minor}.{patch} is not supported (prism reads major version 32)")]
    UnsupportedVersion {
        /// Major version (the layout).
        major: u32,
        /// Minor version.
        minor: u32,
        /// Patch version.
        patch: u32,
    },
    /// A compression prism does not decode.
    #[error("the NanoVDB file is {0}-compressed; prism reads uncompressed and ZIP files (convert it with `nanovdb_convert -z`)")]
    UnsupportedCodec(&'static str),
    /// A codec number that NanoVDB does not define.
    #[error("unknown NanoVDB codec {0}")]
    UnknownCodec(u16),
    /// The file ends before what its headers announce.
    #[error("the NanoVDB file is truncated: {0}")]
    Truncated(String),
    /// A ZIP-compressed grid that does not decompress to its announced size.
    #[error("grid \"{grid}\": ZIP data is corrupt: {reason}")]
    Zip {
        /// The grid's name.
        grid: String,
        /// What went wrong.
        reason: String,
    },
    /// No grid of that name.
    #[error("no grid named \"{name}\" (the file has: {})", available.join(", "))]
    NoGrid {
        /// The name looked for.
        name: String,
        /// The names the file has.
        available: Vec<String>,
    },
    /// A grid whose values are not 32-bit floats.
    #[error("grid \"{grid}\" holds {value_type} values; prism reads float grids only")]
    UnsupportedValueType {
        /// The grid's name.
        grid: String,
        /// NanoVDB's name of its value type.
        value_type: &'static str,
    },
    /// A grid buffer whose contents contradict themselves (offsets out of range, counts that do
    /// not fit, a singular map).
    #[error("grid \"{grid}\" is malformed: {reason}")]
    Malformed {
        /// The grid's name.
        grid: String,
        /// What is wrong.
        reason: String,
    },
}

/// NanoVDB's magic number, "NanoVDB0" read as a little-endian u64.
pub const MAGIC: u64 = 0x3042_4456_6f6e_614e;

/// The major version whose layout this reader knows.
pub const MAJOR_VERSION: u32 = 32;

/// (major, minor, patch) of NanoVDB's packed version (11, 11 and 10 bits).
pub fn version_parts(v: u32) -> (u32, u32, u32) {
    (v >> 21, (v >> 10) & 0x7ff, v & 0x3ff)
}

/// An error unless `v` is a version of major [`MAJOR_VERSION`].
pub fn check_version(v: u32) -> Result<(), NanoVdbError> {
    let (major, minor, patch) = version_parts(v);
    if major == MAJOR_VERSION {
        Ok(())
    } else {
        Err(NanoVdbError::UnsupportedVersion { major, minor, patch })
    }
}

/// NanoVDB's name of grid type `t` (`GridType` in NanoVDB.h).
pub fn value_type_name(t: u32) -> &'static str {
    const NAMES: [&str; 20] = [
        "unknown", "float", "double", "int16", "int32", "int64", "Vec3f", "Vec3d", "mask", "half", "uint32", "bool",
        "RGBA8", "Fp4", "Fp8", "Fp16", "FpN", "Vec4f", "Vec4d", "index",
    ];
    NAMES.get(t as usize).copied().unwrap_or("unknown")
}

/// Little-endian reads from a byte buffer, `None` past its end.
pub(crate) struct Bytes<'a>(pub &'a [u8]);

impl Bytes<'_> {
    fn array<const N: usize>(&self, at: u64) -> Option<[u8; N]> {
        let at = usize::try_from(at).ok()?;
        self.0.get(at..at.checked_add(N)?)?.try_into().ok()
    }
    pub fn u16(&self, at: u64) -> Option<u16> {
        self.array(at).map(u16::from_le_bytes)
    }
    pub fn u32(&self, at: u64) -> Option<u32> {
        self.array(at).map(u32::from_le_bytes)
    }
    pub fn i32(&self, at: u64) -> Option<i32> {
        self.array(at).map(i32::from_le_bytes)
    }
    pub fn u64(&self, at: u64) -> Option<u64> {
        self.array(at).map(u64::from_le_bytes)
    }
    pub fn i64(&self, at: u64) -> Option<i64> {
        self.array(at).map(i64::from_le_bytes)
    }
    pub fn f32(&self, at: u64) -> Option<f32> {
        self.array(at).map(f32::from_le_bytes)
    }
    pub fn f64(&self, at: u64) -> Option<f64> {
        self.array(at).map(f64::from_le_bytes)
    }
}
