//! What can be wrong with a mesh file.

use super::ply::MAX_FACE_VERTICES;

/// A malformed PLY or OBJ file; each renders as one line, OBJ errors naming the line.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// An OBJ file that is not UTF-8.
    #[error("file is not UTF-8 text")]
    NotUtf8,
    /// An OBJ number that does not parse or is not finite.
    #[error("line {line}: bad number in \"{text}\"")]
    BadNumber {
        /// 1-based line.
        line: usize,
        /// The line as written, trimmed.
        text: String,
    },
    /// An OBJ `v`, `vn` or `vt` line with too few numbers.
    #[error("line {line}: \"{keyword}\" needs {count} numbers")]
    TooFewNumbers {
        /// 1-based line.
        line: usize,
        /// The line's keyword.
        keyword: String,
        /// Numbers the keyword takes.
        count: usize,
    },
    /// An OBJ face index that is not an integer.
    #[error("line {line}: bad index \"{text}\"")]
    BadIndex {
        /// 1-based line.
        line: usize,
        /// The index as written.
        text: String,
    },
    /// An OBJ face index of no defined element.
    #[error("line {line}: {what} index {index} is out of range ({defined} defined)")]
    IndexOutOfRange {
        /// 1-based line.
        line: usize,
        /// "vertex", "texture" or "normal".
        what: &'static str,
        /// The index as written (negative: relative).
        index: i64,
        /// Elements of that kind defined before the line.
        defined: usize,
    },
    /// An OBJ face corner without a position index.
    #[error("line {line}: face corner \"{corner}\" has no vertex index")]
    NoVertexIndex {
        /// 1-based line.
        line: usize,
        /// The corner as written.
        corner: String,
    },
    /// More distinct OBJ corners than 32-bit indices address.
    #[error("too many vertices")]
    TooManyVertices,
    /// An OBJ face of fewer than 3 corners.
    #[error("line {line}: a face needs at least 3 corners")]
    TooFewCorners {
        /// 1-based line.
        line: usize,
    },
    /// PLY data that ends before the header's counts are read.
    #[error("unexpected end of data")]
    UnexpectedEnd,
    /// An ASCII PLY value that is not ASCII text.
    #[error("non-ASCII number")]
    NonAsciiNumber,
    /// An ASCII PLY value that is not a number.
    #[error("bad number \"{0}\"")]
    BadValue(String),
    /// A file that does not start with the "ply" magic.
    #[error("not a PLY file (missing \"ply\" magic)")]
    NotPly,
    /// A PLY format other than ascii and binary little or big endian.
    #[error("unknown format {0:?}")]
    UnknownFormat(String),
    /// A PLY element count that is not a non-negative integer.
    #[error("bad element count \"{0}\"")]
    BadElementCount(String),
    /// A PLY property line before any element line.
    #[error("property before any element")]
    PropertyBeforeElement,
    /// A PLY property of a type the format does not define.
    #[error("unknown property type \"{0}\"")]
    UnknownPropertyType(String),
    /// A PLY header line that is none of the known ones.
    #[error("malformed header line \"{0}\"")]
    MalformedHeaderLine(String),
    /// A PLY header without a format line.
    #[error("missing format line")]
    MissingFormat,
    /// A PLY header that does not end.
    #[error("missing end_header")]
    MissingEndHeader,
    /// A PLY header that is not ASCII.
    #[error("header is not ASCII")]
    HeaderNotAscii,
    /// A PLY element count the data that follows cannot hold.
    #[error("element \"{name}\" declares {count} entries but only {available} bytes of data follow")]
    CountExceedsData {
        /// The element's name.
        name: String,
        /// The count the header declares.
        count: usize,
        /// Bytes after the elements read so far.
        available: usize,
    },
    /// A PLY file with two vertex elements.
    #[error("more than one vertex element")]
    DuplicateVertexElement,
    /// A PLY vertex element without positions.
    #[error("vertex element lacks x, y, z")]
    NoPositions,
    /// A PLY vertex position that is infinite or NaN.
    #[error("vertex {0} is not finite")]
    NonFiniteVertex(usize),
    /// A PLY face element without a vertex index list.
    #[error("face element lacks a vertex_indices list")]
    NoFaceIndices,
    /// A PLY face index that is negative, fractional or beyond 32 bits.
    #[error("face {face} has invalid vertex index {index}")]
    InvalidFaceIndex {
        /// The face.
        face: usize,
        /// The index as read.
        index: f64,
    },
    /// A PLY face of fewer than 3 vertices.
    #[error("face {face} has {count} vertices; at least 3 are needed")]
    TooFewFaceVertices {
        /// The face.
        face: usize,
        /// Its vertex count.
        count: usize,
    },
    /// A PLY face index of no vertex in the file.
    #[error("vertex index {index} is out of range: the file has {count} vertices")]
    VertexIndexOutOfRange {
        /// The largest index of the first face found out of range.
        index: u32,
        /// Vertices in the file.
        count: usize,
    },
    /// A PLY list length that is negative, fractional or above [`MAX_FACE_VERTICES`].
    #[error("list length {length} is invalid (at most {})", MAX_FACE_VERTICES)]
    BadListLength {
        /// The length as read.
        length: f64,
    },
    /// A mesh too large for the memory available.
    #[error("out of memory: {count} {what} need {gib:.1} GiB")]
    OutOfMemory {
        /// Elements asked for.
        count: usize,
        /// "vertices" or "faces".
        what: &'static str,
        /// Their size [GiB].
        gib: f64,
    },
}
