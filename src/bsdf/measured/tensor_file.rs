//! The tensor-file container of the RGL material database (`.bsdf` files; Dupuy & Jakob 2018),
//! as Mitsuba 3's `TensorFile` and pbrt-v4's `Tensor` read it.
//!
//! Layout, little-endian: the 12 bytes `"tensor_file\0"`, the version (two bytes, 1 and 0), the
//! number of fields (u32), then per field its name length (u16), name (bytes), number of
//! dimensions (u16), element type (u8: 1 = u8, 2 = i8, 3 = u16, 4 = i16, 5 = u32, 6 = i32,
//! 7 = u64, 8 = i64, 9 = f16, 10 = f32, 11 = f64), the absolute byte offset of its data (u64)
//! and its shape (one u64 per dimension, C order: the last index is contiguous).

use std::collections::HashMap;

/// The 12 bytes every tensor file starts with.
pub const MAGIC: &[u8; 12] = b"tensor_file\0";

/// Element type of a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// `uint8_t`.
    U8,
    /// `int8_t`.
    I8,
    /// `uint16_t`.
    U16,
    /// `int16_t`.
    I16,
    /// `uint32_t`.
    U32,
    /// `int32_t`.
    I32,
    /// `uint64_t`.
    U64,
    /// `int64_t`.
    I64,
    /// IEEE half.
    F16,
    /// IEEE single.
    F32,
    /// IEEE double.
    F64,
}

impl Dtype {
    /// The code the file stores.
    pub fn code(self) -> u8 {
        self as u8 + 1
    }

    fn from_code(c: u8) -> Option<Self> {
        use Dtype::*;
        [U8, I8, U16, I16, U32, I32, U64, I64, F16, F32, F64].get((c as usize).wrapping_sub(1)).copied()
    }

    /// Bytes per element.
    pub fn size(self) -> usize {
        use Dtype::*;
        match self {
            U8 | I8 => 1,
            U16 | I16 | F16 => 2,
            U32 | I32 | F32 => 4,
            U64 | I64 | F64 => 8,
        }
    }
}

/// Why a tensor file cannot be read.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TensorError {
    /// The file ends inside the header or a field's data.
    #[error("truncated: {what} needs bytes {start}..{end}, the file has {len}")]
    Truncated {
        /// What was being read.
        what: String,
        /// First byte needed.
        start: u64,
        /// One past the last byte needed.
        end: u64,
        /// File size.
        len: usize,
    },
    /// Not a tensor file.
    #[error("not a tensor file (the first 12 bytes are not \"tensor_file\\0\")")]
    BadMagic,
    /// A version other than 1.0.
    #[error("tensor file version {0}.{1}; only 1.0 is known")]
    Version(u8, u8),
    /// An element type code outside 1..=11.
    #[error("field \"{field}\": unknown element type {code}")]
    UnknownDtype {
        /// Field name.
        field: String,
        /// The code read.
        code: u8,
    },
    /// A field name that is not UTF-8.
    #[error("a field name is not UTF-8")]
    BadName,
    /// A field's shape overflows the address space.
    #[error("field \"{0}\": its shape is too large")]
    TooLarge(String),
    /// A field that a reader needs is absent.
    #[error("no field \"{0}\"")]
    Missing(String),
    /// A field of another element type than the reader needs.
    #[error("field \"{field}\" is {found:?}, {expected:?} is required")]
    WrongDtype {
        /// Field name.
        field: String,
        /// Its type.
        found: Dtype,
        /// The type needed.
        expected: Dtype,
    },
    /// A field whose shape does not fit the others.
    #[error("field \"{field}\" has shape {shape:?}; {expected}")]
    WrongShape {
        /// Field name.
        field: String,
        /// Its shape.
        shape: Vec<usize>,
        /// What the shape must be.
        expected: String,
    },
}

/// One field: its type, shape and raw little-endian bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Element type.
    pub dtype: Dtype,
    /// Shape (C order).
    pub shape: Vec<usize>,
    /// `shape.product() × dtype.size()` bytes.
    pub data: Vec<u8>,
}

impl Field {
    /// A field of f32 values.
    pub fn f32(shape: Vec<usize>, values: &[f32]) -> Self {
        Self { dtype: Dtype::F32, shape, data: values.iter().flat_map(|v| v.to_le_bytes()).collect() }
    }

    /// A field of bytes.
    pub fn u8(shape: Vec<usize>, values: &[u8]) -> Self {
        Self { dtype: Dtype::U8, shape, data: values.to_vec() }
    }
}

/// A parsed tensor file: named fields.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TensorFile {
    /// Fields by name.
    pub fields: HashMap<String, Field>,
}

/// A bounds-checked little-endian cursor.
struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], TensorError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(TensorError::Truncated {
                what: what.into(),
                start: self.pos as u64,
                end: self.pos as u64 + n as u64,
                len: self.bytes.len(),
            });
        };
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], TensorError> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N, what)?);
        Ok(a)
    }
    fn u16(&mut self, what: &str) -> Result<u16, TensorError> {
        Ok(u16::from_le_bytes(self.array(what)?))
    }
    fn u64(&mut self, what: &str) -> Result<u64, TensorError> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }
}

impl TensorFile {
    /// Parses a whole file's bytes; every malformed case is an error, never a panic.
    pub fn parse(bytes: &[u8]) -> Result<Self, TensorError> {
        let mut r = Reader { bytes, pos: 0 };
        if r.take(12, "the header").map_err(|_| TensorError::BadMagic)? != MAGIC {
            return Err(TensorError::BadMagic);
        }
        let [major, minor] = r.array("the version")?;
        if (major, minor) != (1, 0) {
            return Err(TensorError::Version(major, minor));
        }
        let n_fields = u32::from_le_bytes(r.array("the field count")?);
        let mut fields = HashMap::new();
        for i in 0..n_fields {
            let what = format!("field {i}'s header");
            let name_len = r.u16(&what)? as usize;
            let name = std::str::from_utf8(r.take(name_len, &what)?).map_err(|_| TensorError::BadName)?.to_string();
            let ndim = r.u16(&what)? as usize;
            let [code] = r.array(&what)?;
            let dtype =
                Dtype::from_code(code).ok_or_else(|| TensorError::UnknownDtype { field: name.clone(), code })?;
            let offset = r.u64(&what)?;
            let mut shape = Vec::with_capacity(ndim.min(64));
            for _ in 0..ndim {
                shape.push(usize::try_from(r.u64(&what)?).map_err(|_| TensorError::TooLarge(name.clone()))?);
            }
            let n_bytes = shape
                .iter()
                .try_fold(dtype.size(), |a, &s| a.checked_mul(s))
                .ok_or_else(|| TensorError::TooLarge(name.clone()))?;
            let start = usize::try_from(offset).unwrap_or(usize::MAX);
            let data = start
                .checked_add(n_bytes)
                .and_then(|end| bytes.get(start..end))
                .ok_or_else(|| TensorError::Truncated {
                    what: format!("field \"{name}\"'s data"),
                    start: offset,
                    end: offset.saturating_add(n_bytes as u64),
                    len: bytes.len(),
                })?
                .to_vec();
            fields.insert(name, Field { dtype, shape, data });
        }
        Ok(Self { fields })
    }

    /// The file's bytes: header, field table (in name order), then each field's data.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut names: Vec<&String> = self.fields.keys().collect();
        names.sort();
        let header_len: usize =
            12 + 2 + 4 + names.iter().map(|n| 2 + n.len() + 2 + 1 + 8 + 8 * self.fields[*n].shape.len()).sum::<usize>();
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&[1, 0]);
        out.extend_from_slice(&(names.len() as u32).to_le_bytes());
        let mut offset = header_len as u64;
        for n in &names {
            let f = &self.fields[*n];
            out.extend_from_slice(&(n.len() as u16).to_le_bytes());
            out.extend_from_slice(n.as_bytes());
            out.extend_from_slice(&(f.shape.len() as u16).to_le_bytes());
            out.push(f.dtype.code());
            out.extend_from_slice(&offset.to_le_bytes());
            for &s in &f.shape {
                out.extend_from_slice(&(s as u64).to_le_bytes());
            }
            offset += f.data.len() as u64;
        }
        for n in &names {
            out.extend_from_slice(&self.fields[*n].data);
        }
        out
    }

    /// A field that must exist.
    pub fn field(&self, name: &str) -> Result<&Field, TensorError> {
        self.fields.get(name).ok_or_else(|| TensorError::Missing(name.into()))
    }

    /// A field's values as f32, checked to have `ndim` dimensions.
    pub fn f32s(&self, name: &str, ndim: usize) -> Result<(Vec<f32>, &[usize]), TensorError> {
        let f = self.typed(name, Dtype::F32, ndim)?;
        let values = f.data.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        Ok((values, &f.shape))
    }

    /// A field's values as bytes, checked to have `ndim` dimensions.
    pub fn bytes(&self, name: &str, ndim: usize) -> Result<&[u8], TensorError> {
        Ok(&self.typed(name, Dtype::U8, ndim)?.data)
    }

    fn typed(&self, name: &str, dtype: Dtype, ndim: usize) -> Result<&Field, TensorError> {
        let f = self.field(name)?;
        if f.dtype != dtype {
            return Err(TensorError::WrongDtype { field: name.into(), found: f.dtype, expected: dtype });
        }
        if f.shape.len() != ndim {
            return Err(TensorError::WrongShape {
                field: name.into(),
                shape: f.shape.clone(),
                expected: format!("{ndim} dimensions are required"),
            });
        }
        Ok(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> TensorFile {
        let mut t = TensorFile::default();
        t.fields.insert("theta_i".into(), Field::f32(vec![3], &[0.0, 0.5, 1.0]));
        t.fields.insert("description".into(), Field::u8(vec![2], b"hi"));
        t
    }

    /// A file written by hand, byte by byte, from the layout in the module documentation.
    fn by_hand() -> Vec<u8> {
        let mut b = b"tensor_file\0".to_vec();
        b.extend_from_slice(&[1, 0]);
        b.extend_from_slice(&1u32.to_le_bytes());
        b.extend_from_slice(&1u16.to_le_bytes());
        b.push(b'x');
        b.extend_from_slice(&2u16.to_le_bytes());
        b.push(10);
        let offset = (b.len() + 8 + 16) as u64;
        b.extend_from_slice(&offset.to_le_bytes());
        b.extend_from_slice(&1u64.to_le_bytes());
        b.extend_from_slice(&2u64.to_le_bytes());
        b.extend_from_slice(&1.5f32.to_le_bytes());
        b.extend_from_slice(&(-2.0f32).to_le_bytes());
        b
    }

    #[test]
    fn reads_a_file_laid_out_by_hand() {
        let t = TensorFile::parse(&by_hand()).unwrap();
        let (v, shape) = t.f32s("x", 2).unwrap();
        assert_eq!((v, shape), (vec![1.5, -2.0], &[1usize, 2][..]));
        assert_eq!(TensorFile::parse(&t.to_bytes()).unwrap(), t);
    }

    #[test]
    fn round_trips() {
        let t = sample();
        let back = TensorFile::parse(&t.to_bytes()).unwrap();
        assert_eq!(back, t);
        assert_eq!(back.bytes("description", 1).unwrap(), b"hi");
    }

    #[test]
    fn every_malformed_file_is_an_error() {
        let good = sample().to_bytes();
        // Every truncation, from the empty file to one byte short.
        for n in 0..good.len() {
            assert!(TensorFile::parse(&good[..n]).is_err(), "{n} bytes parsed");
        }
        let mut bad = good.clone();
        bad[0] = b'T';
        assert_eq!(TensorFile::parse(&bad), Err(TensorError::BadMagic));
        let mut bad = good.clone();
        bad[12] = 2;
        assert_eq!(TensorFile::parse(&bad), Err(TensorError::Version(2, 0)));
        // The first field ("description", sorted first): its dtype byte follows the name and ndim.
        let dtype_at = 12 + 2 + 4 + 2 + "description".len() + 2;
        let mut bad = good.clone();
        bad[dtype_at] = 12;
        assert!(matches!(TensorFile::parse(&bad), Err(TensorError::UnknownDtype { code: 12, .. })));
        // A huge shape or offset is an error, not an allocation.
        let mut bad = good.clone();
        bad[dtype_at + 1 + 8..dtype_at + 1 + 16].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(TensorFile::parse(&bad).is_err());
        let mut bad = good;
        bad[dtype_at + 1..dtype_at + 9].copy_from_slice(&(u64::MAX - 1).to_le_bytes());
        assert!(matches!(TensorFile::parse(&bad), Err(TensorError::Truncated { .. })));
        // Typed access checks type, dimensions and presence.
        let t = sample();
        assert!(matches!(t.f32s("description", 1), Err(TensorError::WrongDtype { .. })));
        assert!(matches!(t.f32s("theta_i", 2), Err(TensorError::WrongShape { .. })));
        assert_eq!(t.field("ndf"), Err(TensorError::Missing("ndf".into())));
    }
}
