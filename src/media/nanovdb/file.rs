//! The `.nvdb` container (NanoVDB's `util/IO.h`): segments of a header, per-grid records and
//! grid buffers, each buffer stored raw (codec NONE) or as one zlib stream preceded by its
//! compressed size (ZIP). Everything is little-endian.
//!
//! | segment part | bytes | fields |
//! |---|---|---|
//! | header | 16 | magic u64, version u32, grid count u16, codec u16 |
//! | record (per grid) | 176 | grid size u64, file size u64, name hash u64, voxel count u64, type u32, class u32, world bbox 6×f64, index bbox 6×i32, voxel size 3×f64, name size u32 (with its NUL), node counts 4×u32, tile counts 3×u32, codec u16, padding u16, version u32 |
//! | name (per grid) | name size | the grid's name, NUL-terminated |
//! | data (per grid) | file size | the grid buffer (NONE) or compressed size u64 + zlib stream (ZIP) |

use super::grid::FloatGrid;
use super::{check_version, value_type_name, Bytes, NanoVdbError, MAGIC};
use std::io::Read;
use std::path::Path;

/// Size of a segment header.
const HEADER_SIZE: u64 = 16;
/// Size of a grid record before its name.
const RECORD_SIZE: u64 = 176;

/// How grid buffers are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Codec {
    None,
    Zip,
}

/// One grid as the file lists it.
#[derive(Clone, Debug)]
pub struct GridRecord {
    /// The grid's name.
    pub name: String,
    /// NanoVDB's value type number (1: float).
    pub grid_type: u32,
    /// Size of the decoded grid buffer [bytes].
    grid_size: u64,
    codec: Codec,
    /// Where the stored data starts in the file, and its length [bytes].
    data: (u64, u64),
}

/// A NanoVDB file's bytes and its list of grids.
#[derive(Clone, Debug)]
pub struct NanoVdbFile {
    bytes: Vec<u8>,
    /// The grids, in file order.
    pub grids: Vec<GridRecord>,
}

impl NanoVdbFile {
    /// Reads and indexes the file at `path` (gzip is not a NanoVDB codec: the bytes are taken as
    /// they are).
    pub fn open(path: &Path) -> Result<Self, NanoVdbError> {
        Self::parse(std::fs::read(path)?)
    }

    /// Indexes the segments of a file's bytes.
    pub fn parse(bytes: Vec<u8>) -> Result<Self, NanoVdbError> {
        let b = Bytes(&bytes);
        let truncated = |what: &str| NanoVdbError::Truncated(what.to_string());
        let mut grids = Vec::new();
        let mut at = 0u64;
        while at < bytes.len() as u64 {
            let magic = b.u64(at).ok_or_else(|| truncated("segment header"))?;
            if magic != MAGIC {
                return Err(if magic == MAGIC.swap_bytes() {
                    NanoVdbError::ReversedEndianness
                } else {
                    NanoVdbError::NotNanoVdb
                });
            }
            let version = b.u32(at + 8).ok_or_else(|| truncated("segment header"))?;
            check_version(version)?;
            let count = b.u16(at + 12).ok_or_else(|| truncated("segment header"))?;
            let codec = match b.u16(at + 14).ok_or_else(|| truncated("segment header"))? {
                0 => Codec::None,
                1 => Codec::Zip,
                2 => return Err(NanoVdbError::UnsupportedCodec("BLOSC")),
                c => return Err(NanoVdbError::UnknownCodec(c)),
            };
            at += HEADER_SIZE;
            let mut segment = Vec::with_capacity(count as usize);
            for _ in 0..count {
                let field = |off: u64| b.u64(at + off).ok_or_else(|| truncated("grid record"));
                let (grid_size, file_size) = (field(0)?, field(8)?);
                let grid_type = b.u32(at + 32).ok_or_else(|| truncated("grid record"))?;
                let name_size = b.u32(at + 136).ok_or_else(|| truncated("grid record"))? as u64;
                let start = at + RECORD_SIZE;
                let name_bytes = usize::try_from(start)
                    .ok()
                    .and_then(|s| bytes.get(s..s.checked_add(name_size as usize)?))
                    .ok_or_else(|| truncated("grid name"))?;
                let end = name_bytes.iter().position(|&c| c == 0).unwrap_or(name_bytes.len());
                let name = String::from_utf8_lossy(&name_bytes[..end]).into_owned();
                at = start + name_size;
                segment.push(GridRecord { name, grid_type, grid_size, codec, data: (0, file_size) });
            }
            for g in &mut segment {
                let len = g.data.1;
                if at.checked_add(len).is_none_or(|end| end > bytes.len() as u64) {
                    return Err(NanoVdbError::Truncated(format!("grid \"{}\" announces {len} bytes", g.name)));
                }
                g.data.0 = at;
                at += len;
            }
            grids.extend(segment);
        }
        if grids.is_empty() {
            return Err(truncated("no grid"));
        }
        Ok(Self { bytes, grids })
    }

    /// The decoded buffer of the grid named `name`.
    fn buffer(&self, name: &str) -> Result<Vec<u8>, NanoVdbError> {
        let g = self.grids.iter().find(|g| g.name == name).ok_or_else(|| NanoVdbError::NoGrid {
            name: name.to_string(),
            available: self.grids.iter().map(|g| format!("\"{}\"", g.name)).collect(),
        })?;
        let (start, len) = (g.data.0 as usize, g.data.1 as usize);
        let stored = &self.bytes[start..start + len];
        match g.codec {
            Codec::None => {
                if g.grid_size != len as u64 {
                    let reason = format!("its record gives {} bytes, its data {len}", g.grid_size);
                    return Err(NanoVdbError::Malformed { grid: g.name.clone(), reason });
                }
                Ok(stored.to_vec())
            }
            Codec::Zip => {
                let zip_error = |reason: String| NanoVdbError::Zip { grid: g.name.clone(), reason };
                let compressed = Bytes(stored).u64(0).ok_or_else(|| zip_error("no compressed size".into()))?;
                if compressed != len as u64 - 8 {
                    return Err(zip_error(format!("{compressed} compressed bytes announced, {} stored", len - 8)));
                }
                // Read at most one byte more than announced, so that a corrupt stream can neither
                // grow without bound nor pass for the right size.
                let mut out = Vec::new();
                flate2::read::ZlibDecoder::new(&stored[8..])
                    .take(g.grid_size.saturating_add(1))
                    .read_to_end(&mut out)
                    .map_err(|e| zip_error(e.to_string()))?;
                if out.len() as u64 != g.grid_size {
                    return Err(zip_error(format!("{} bytes decoded, {} announced", out.len(), g.grid_size)));
                }
                Ok(out)
            }
        }
    }

    /// The float grid named `name`, decoded.
    pub fn float_grid(&self, name: &str) -> Result<FloatGrid, NanoVdbError> {
        let record = self.grids.iter().find(|g| g.name == name);
        if let Some(g) = record.filter(|g| g.grid_type != 1) {
            return Err(NanoVdbError::UnsupportedValueType {
                grid: g.name.clone(),
                value_type: value_type_name(g.grid_type),
            });
        }
        FloatGrid::decode(name, &self.buffer(name)?)
    }

    /// Whether the file has a grid named `name`.
    pub fn has(&self, name: &str) -> bool {
        self.grids.iter().any(|g| g.name == name)
    }
}

/// The float grids `names` of the file at `path`, each `None` where the file has no grid of
/// that name.
pub fn read_float_grids(path: &Path, names: &[&str]) -> Result<Vec<Option<FloatGrid>>, NanoVdbError> {
    let file = NanoVdbFile::open(path)?;
    names.iter().map(|n| if file.has(n) { file.float_grid(n).map(Some) } else { Ok(None) }).collect()
}
