//! PLY reader (Turk 1994, "The PLY Polygon File Format"): ASCII and binary little/big endian,
//! vertex x/y/z, nx/ny/nz, u/v (or s/t, texture_u/texture_v), faces via `vertex_indices` or
//! `vertex_index` lists; quads and larger convex polygons are split into a triangle fan whose
//! triangles share the polygon's face id (a quad is one shape in pbrt-v4: a bilinear patch).
//!
//! Counts in the header are checked against the bytes present before anything is allocated.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::MeshError;
use crate::geometry::Mesh;

/// Longest polygon accepted (a face list count above this is corrupt data, not geometry).
pub const MAX_FACE_VERTICES: usize = 64;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

#[derive(Debug)]
struct Property {
    name: String,
    /// `Some(count type)` for list properties.
    list: Option<Scalar>,
    ty: Scalar,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// Reads values from the body in either encoding.
struct Body<'a> {
    data: &'a [u8],
    pos: usize,
    format: Format,
}

impl Body<'_> {
    fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    fn value(&mut self, ty: Scalar) -> Result<f64, MeshError> {
        if self.format == Format::Ascii {
            while self.pos < self.data.len() && self.data[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let start = self.pos;
            while self.pos < self.data.len() && !self.data[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if start == self.pos {
                return Err(MeshError::UnexpectedEnd);
            }
            let s = std::str::from_utf8(&self.data[start..self.pos]).map_err(|_| MeshError::NonAsciiNumber)?;
            return s.parse::<f64>().map_err(|_| MeshError::BadValue(s.to_string()));
        }
        let n = ty.size();
        if self.remaining() < n {
            return Err(MeshError::UnexpectedEnd);
        }
        let v = binary_value(&self.data[self.pos..], ty, self.format);
        self.pos += n;
        Ok(v)
    }

    /// The next `n` bytes.
    fn take(&mut self, n: usize) -> Result<&[u8], MeshError> {
        if self.remaining() < n {
            return Err(MeshError::UnexpectedEnd);
        }
        self.pos += n;
        Ok(&self.data[self.pos - n..self.pos])
    }
}

/// The binary value of type `ty` that `bytes` starts with (`bytes` holds at least its size).
#[inline]
fn binary_value(bytes: &[u8], ty: Scalar, format: Format) -> f64 {
    let n = ty.size();
    let mut b = [0u8; 8];
    b[..n].copy_from_slice(&bytes[..n]);
    if format == Format::Big {
        b[..n].reverse();
    }
    {
        match ty {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        }
    }
}

fn parse_header(text: &str) -> Result<(Format, Vec<Element>), MeshError> {
    let mut lines = text.lines().map(str::trim);
    if lines.next() != Some("ply") {
        return Err(MeshError::NotPly);
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for line in lines {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                format = Some(match w.get(1).copied() {
                    Some("ascii") => Format::Ascii,
                    Some("binary_little_endian") => Format::Little,
                    Some("binary_big_endian") => Format::Big,
                    other => return Err(MeshError::UnknownFormat(other.unwrap_or("").to_string())),
                })
            }
            Some("element") if w.len() == 3 => {
                let count = w[2].parse::<usize>().map_err(|_| MeshError::BadElementCount(w[2].to_string()))?;
                elements.push(Element { name: w[1].into(), count, props: Vec::new() });
            }
            Some("property") => {
                let e = elements.last_mut().ok_or(MeshError::PropertyBeforeElement)?;
                let ty = |s: &str| Scalar::parse(s).ok_or_else(|| MeshError::UnknownPropertyType(s.to_string()));
                let p = match w[..] {
                    [_, "list", c, t, name] => Property { name: name.into(), list: Some(ty(c)?), ty: ty(t)? },
                    [_, t, name] => Property { name: name.into(), list: None, ty: ty(t)? },
                    _ => return Err(MeshError::MalformedHeaderLine(line.to_string())),
                };
                e.props.push(p);
            }
            Some("end_header") => return Ok((format.ok_or(MeshError::MissingFormat)?, elements)),
            _ => return Err(MeshError::MalformedHeaderLine(line.to_string())),
        }
    }
    Err(MeshError::MissingEndHeader)
}

/// Parses a PLY file into a mesh (object space). Errors are human-readable messages.
pub fn parse(bytes: &[u8]) -> Result<Mesh, MeshError> {
    let marker = b"end_header";
    let hdr_end = bytes.windows(marker.len()).position(|w| w == marker).ok_or(MeshError::MissingEndHeader)?;
    let mut body_start = hdr_end + marker.len();
    // The header ends with "end_header" and one line terminator (\n or \r\n).
    if bytes.get(body_start) == Some(&b'\r') {
        body_start += 1;
    }
    if bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let header = std::str::from_utf8(&bytes[..body_start]).map_err(|_| MeshError::HeaderNotAscii)?;
    let (format, elements) = parse_header(header)?;
    let mut body = Body { data: bytes, pos: body_start, format };

    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut uvs: Vec<Vec2> = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    // Each triangle's polygon, named by the index of its first triangle; recorded from the
    // first polygon of more than three vertices on (every triangle before it is its own).
    let mut faces: Option<Vec<u32>> = None;
    let mut have_vertices = false;
    // The largest index of the triangles read by the parallel path, and whether every triangle
    // was read by it.
    let (mut max_index, mut all_fast) = (0u32, true);
    for e in &elements {
        // Every element takes at least one byte (binary) or two characters (ASCII) per scalar
        // property; a count the remaining data cannot hold is rejected before allocating.
        let min_size: usize = e
            .props
            .iter()
            .map(|p| if format == Format::Ascii { 2 } else { p.list.unwrap_or(p.ty).size() })
            .sum::<usize>()
            .max(1);
        if e.count.checked_mul(min_size).is_none_or(|need| need > body.remaining() + 1) {
            return Err(MeshError::CountExceedsData {
                name: e.name.clone(),
                count: e.count,
                available: body.remaining(),
            });
        }
        let idx = |n: &str| e.props.iter().position(|p| p.name == n && p.list.is_none());
        let pick = |names: [&str; 2]| -> Option<[usize; 2]> { Some([idx(names[0])?, idx(names[1])?]) };
        match e.name.as_str() {
            "vertex" => {
                if have_vertices {
                    return Err(MeshError::DuplicateVertexElement);
                }
                have_vertices = true;
                let (Some(x), Some(y), Some(z)) = (idx("x"), idx("y"), idx("z")) else {
                    return Err(MeshError::NoPositions);
                };
                let n = [idx("nx"), idx("ny"), idx("nz")];
                let n = if n.iter().all(Option::is_some) { Some(n.map(Option::unwrap)) } else { None };
                let uv = pick(["u", "v"])
                    .or_else(|| pick(["s", "t"]))
                    .or_else(|| pick(["texture_u", "texture_v"]))
                    .or_else(|| pick(["texture_s", "texture_t"]));
                // One spare slot, as `Mesh::transformed` leaves, for Embree's reads in place.
                reserve(&mut positions, e.count + 1, "vertices")?;
                if format != Format::Ascii && e.props.iter().all(|p| p.list.is_none()) {
                    // Records of one size: decoded in parallel.
                    let offsets: Vec<usize> = e
                        .props
                        .iter()
                        .map(|p| p.ty.size())
                        .scan(0, |o, n| {
                            *o += n;
                            Some(*o - n)
                        })
                        .collect();
                    let stride: usize = e.props.iter().map(|p| p.ty.size()).sum();
                    let data = body.take(e.count * stride)?;
                    let records = || data.par_chunks_exact(stride).with_min_len(MIN_PARALLEL_RECORDS);
                    let get = |r: &[u8], k: usize| binary_value(&r[offsets[k]..], e.props[k].ty, format) as f32;
                    positions.par_extend(records().map(|r| Vec3::new(get(r, x), get(r, y), get(r, z))));
                    if let Some(i) =
                        positions.par_iter().with_min_len(MIN_PARALLEL_RECORDS).position_first(|p| !p.is_finite())
                    {
                        return Err(MeshError::NonFiniteVertex(i));
                    }
                    if let Some([a, b, c]) = n {
                        reserve(&mut normals, e.count, "vertices")?;
                        normals.par_extend(
                            records().map(|r| Vec3::new(get(r, a), get(r, b), get(r, c)).normalize_or_zero()),
                        );
                    }
                    if let Some([a, b]) = uv {
                        reserve(&mut uvs, e.count, "vertices")?;
                        uvs.par_extend(records().map(|r| Vec2::new(get(r, a), get(r, b))));
                    }
                    continue;
                }
                let mut vals = vec![0.0f64; e.props.len()];
                for _ in 0..e.count {
                    for (k, p) in e.props.iter().enumerate() {
                        if let Some(ct) = p.list {
                            // Lists in vertex elements carry nothing prism uses; skip them.
                            let len = body.value(ct)?;
                            for _ in 0..list_len(len)? {
                                body.value(p.ty)?;
                            }
                        } else {
                            vals[k] = body.value(p.ty)?;
                        }
                    }
                    let v = |i: usize| vals[i] as f32;
                    let p = Vec3::new(v(x), v(y), v(z));
                    if !p.is_finite() {
                        return Err(MeshError::NonFiniteVertex(positions.len()));
                    }
                    positions.push(p);
                    if let Some([a, b, c]) = n {
                        normals.push(Vec3::new(v(a), v(b), v(c)).normalize_or_zero());
                    }
                    if let Some([a, b]) = uv {
                        uvs.push(Vec2::new(v(a), v(b)));
                    }
                }
            }
            "face" => {
                let Some(li) = e
                    .props
                    .iter()
                    .position(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"))
                else {
                    return Err(MeshError::NoFaceIndices);
                };
                reserve(&mut tris, e.count, "faces")?;
                let mut poly = Vec::with_capacity(MAX_FACE_VERTICES);
                let p = &e.props[li];
                let one_list = e.props.len() == 1;
                if format != Format::Ascii
                    && one_list
                    && p.list.is_some_and(|c| c.size() == 1)
                    && matches!(p.ty, Scalar::I32 | Scalar::U32)
                {
                    // The common layout (an 8-bit count, then 32-bit indices) read without the
                    // general per-value path; when every face is a triangle, in parallel.
                    if let Some((t, max)) = binary_triangles(&body, e.count, format) {
                        if p.ty == Scalar::I32 && max > i32::MAX as u32 {
                            // A negative `int`: named as the one-by-one reader names it.
                            let f = t.par_iter().position_first(|t| t.iter().any(|&i| i > i32::MAX as u32));
                            let f = f.expect("an index above i32::MAX");
                            let index = t[f].map(|i| i as i32).into_iter().find(|&i| i < 0).unwrap_or_default();
                            return Err(MeshError::InvalidFaceIndex { face: f, index: index as f64 });
                        }
                        body.take(e.count * TRIANGLE_RECORD)?;
                        max_index = max_index.max(max);
                        if tris.is_empty() {
                            tris = t;
                        } else {
                            tris.extend_from_slice(&t);
                        }
                        continue;
                    }
                    all_fast = false;
                    let count_ty = p.list.expect("checked");
                    for f in 0..e.count {
                        let len = list_len(body.value(count_ty)?)?;
                        let data = body.take(len * 4)?;
                        poly.clear();
                        for i in data.chunks_exact(4).map(|b| binary_value(b, p.ty, format)) {
                            if !(i >= 0.0 && i <= u32::MAX as f64) {
                                return Err(MeshError::InvalidFaceIndex { face: f, index: i });
                            }
                            poly.push(i as u32);
                        }
                        push_polygon(&poly, f, &mut tris, &mut faces)?;
                    }
                    continue;
                }
                all_fast = false;
                for f in 0..e.count {
                    for (k, p) in e.props.iter().enumerate() {
                        match p.list {
                            Some(ct) => {
                                let len = list_len(body.value(ct)?)?;
                                poly.clear();
                                for _ in 0..len {
                                    let i = body.value(p.ty)?;
                                    if k == li {
                                        if !(i >= 0.0 && i <= u32::MAX as f64 && i.fract() == 0.0) {
                                            return Err(MeshError::InvalidFaceIndex { face: f, index: i });
                                        }
                                        poly.push(i as u32);
                                    }
                                }
                                if k == li {
                                    push_polygon(&poly, f, &mut tris, &mut faces)?;
                                }
                            }
                            None => {
                                body.value(p.ty)?;
                            }
                        }
                    }
                }
            }
            _ => {
                for _ in 0..e.count {
                    for p in &e.props {
                        if let Some(ct) = p.list {
                            for _ in 0..list_len(body.value(ct)?)? {
                                body.value(p.ty)?;
                            }
                        } else {
                            body.value(p.ty)?;
                        }
                    }
                }
            }
        }
    }
    let n = positions.len();
    // Triangles read by the fast path are known to be below `max_index`; others are checked.
    if !all_fast || max_index as usize >= n {
        if let Some(t) = tris.par_iter().find_first(|t| t.iter().any(|&i| i as usize >= n)) {
            return Err(MeshError::VertexIndexOutOfRange { index: t.iter().copied().max().unwrap_or(0), count: n });
        }
    }
    let mut mesh = Mesh::new(positions, tris);
    mesh.faces = faces;
    if !normals.is_empty() {
        mesh.normals = Some(normals);
    }
    if !uvs.is_empty() {
        mesh.uvs = Some(uvs);
    }
    Ok(mesh)
}

/// The fewest records a thread takes on in the parallel passes: a small mesh (of which a scene
/// may have thousands) is read on the calling thread alone.
const MIN_PARALLEL_RECORDS: usize = 1 << 13;

/// Bytes of a binary triangle record: an 8-bit count (3) and three 32-bit indices.
const TRIANGLE_RECORD: usize = 13;

/// The next `count` face records of `body` when all of them are binary triangles (an 8-bit
/// count of 3, then three 32-bit indices): their indices (a negative `int` becomes one above
/// i32::MAX) and the largest of them, decoded in one parallel pass that stops at the first
/// record that is not a triangle (`None`).
fn binary_triangles(body: &Body, count: usize, format: Format) -> Option<(Vec<[u32; 3]>, u32)> {
    const CHUNK: usize = 1 << 14;
    let len = count.checked_mul(TRIANGLE_RECORD)?;
    let data = body.data.get(body.pos..body.pos.checked_add(len)?)?;
    let mut tris = vec![[0u32; 3]; count];
    let max = tris
        .par_chunks_mut(CHUNK)
        .zip(data.par_chunks(CHUNK * TRIANGLE_RECORD))
        .map(|(out, records)| {
            let mut max = 0;
            for (t, r) in out.iter_mut().zip(records.chunks_exact(TRIANGLE_RECORD)) {
                if r[0] != 3 {
                    return None;
                }
                *t = triangle_record(r, format);
                max = t.iter().fold(max, |m, &i| m.max(i));
            }
            Some(max)
        })
        .try_reduce(|| 0, |a, b| Some(a.max(b)))?;
    Some((tris, max))
}

/// The three indices of a triangle record (as unsigned; a negative `int` becomes > i32::MAX).
#[inline]
fn triangle_record(r: &[u8], format: Format) -> [u32; 3] {
    let index = |k: usize| {
        let b = [r[1 + 4 * k], r[2 + 4 * k], r[3 + 4 * k], r[4 + 4 * k]];
        if format == Format::Big {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        }
    };
    [index(0), index(1), index(2)]
}

/// Adds polygon `poly` (face `f` of the file) as a triangle fan; from the first polygon of more
/// than three vertices on, `faces` records each triangle's polygon by the index of its first
/// triangle.
fn push_polygon(
    poly: &[u32],
    f: usize,
    tris: &mut Vec<[u32; 3]>,
    faces: &mut Option<Vec<u32>>,
) -> Result<(), MeshError> {
    if poly.len() < 3 {
        return Err(MeshError::TooFewFaceVertices { face: f, count: poly.len() });
    }
    if poly.len() > 3 && faces.is_none() {
        *faces = Some((0..tris.len() as u32).collect());
    }
    let face = tris.len() as u32;
    for j in 1..poly.len() - 1 {
        tris.push([poly[0], poly[j], poly[j + 1]]);
        if let Some(faces) = faces.as_mut() {
            faces.push(face);
        }
    }
    Ok(())
}

fn list_len(v: f64) -> Result<usize, MeshError> {
    if v >= 0.0 && v <= MAX_FACE_VERTICES as f64 && v.fract() == 0.0 {
        Ok(v as usize)
    } else {
        Err(MeshError::BadListLength { length: v })
    }
}

/// Writes a binary little-endian or ASCII PLY with positions, optional normals/uvs and faces
/// (for tests and scene generators).
pub fn write(mesh: &Mesh, faces: &[Vec<u32>], binary: bool) -> Vec<u8> {
    let mut h = String::from("ply\n");
    h += if binary { "format binary_little_endian 1.0\n" } else { "format ascii 1.0\n" };
    h += "comment written by prism\n";
    h += &format!("element vertex {}\nproperty float x\nproperty float y\nproperty float z\n", mesh.positions.len());
    if mesh.normals.is_some() {
        h += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if mesh.uvs.is_some() {
        h += "property float u\nproperty float v\n";
    }
    h += &format!("element face {}\nproperty list uchar int vertex_indices\nend_header\n", faces.len());
    let mut out = h.into_bytes();
    for (i, p) in mesh.positions.iter().enumerate() {
        let mut vals = p.to_array().to_vec();
        if let Some(n) = &mesh.normals {
            vals.extend(n[i].to_array());
        }
        if let Some(uv) = &mesh.uvs {
            vals.extend(uv[i].to_array());
        }
        if binary {
            vals.iter().for_each(|v| out.extend(v.to_le_bytes()));
        } else {
            let line: Vec<String> = vals.iter().map(|v| v.to_string()).collect();
            out.extend(format!("{}\n", line.join(" ")).into_bytes());
        }
    }
    for f in faces {
        if binary {
            out.push(f.len() as u8);
            f.iter().for_each(|&i| out.extend((i as i32).to_le_bytes()));
        } else {
            let line: Vec<String> = f.iter().map(|i| i.to_string()).collect();
            out.extend(format!("{} {}\n", f.len(), line.join(" ")).into_bytes());
        }
    }
    out
}

/// Room for `n` more elements, or an error naming the size when memory runs out (a real mesh
/// of that size, since counts were checked against the file's length).
fn reserve<T>(v: &mut Vec<T>, n: usize, what: &'static str) -> Result<(), MeshError> {
    v.try_reserve_exact(n).map_err(|_| {
        let gib = n as f64 * size_of::<T>() as f64 / (1u64 << 30) as f64;
        MeshError::OutOfMemory { count: n, what, gib }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mesh_too_large_for_memory_is_an_error_naming_its_size() {
        // More bytes than an allocation may have (isize::MAX): refused whatever the allocator
        // would do (a refused request the allocator sees may be optimised away in a release
        // build, where nothing reads the memory).
        let mut v: Vec<Vec3> = Vec::new();
        let e = reserve(&mut v, usize::MAX / 16, "vertices").unwrap_err().to_string();
        assert!(e.starts_with("out of memory: ") && e.contains(" vertices need ") && e.ends_with(" GiB"), "{e}");
        assert!(reserve(&mut v, 10, "vertices").is_ok() && v.capacity() >= 10);
    }

    fn quad() -> (Mesh, Vec<Vec<u32>>) {
        let mut m = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::new(1., 1., 0.), Vec3::Y, Vec3::Z], vec![]);
        m.normals = Some(vec![Vec3::Z; 5]);
        m.uvs = Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y, Vec2::ZERO]);
        (m, vec![vec![0, 1, 2, 3], vec![0, 1, 4]])
    }

    #[test]
    fn ascii_and_binary_round_trip_with_quads_split() {
        let (m, faces) = quad();
        for binary in [false, true] {
            let r = parse(&write(&m, &faces, binary)).unwrap();
            assert_eq!(r.positions, m.positions);
            assert_eq!(r.indices, vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]]);
            // The quad's two triangles are one face.
            assert_eq!(r.faces, Some(vec![0, 0, 2]));
            assert_eq!(r.normals, m.normals);
            assert_eq!(r.uvs, m.uvs);
        }
        // Triangles before the first quad are faces of their own; a mesh of triangles has no ids.
        let r = parse(&write(&m, &[faces[1].clone(), faces[0].clone()], false)).unwrap();
        assert_eq!(r.faces, Some(vec![0, 1, 1]));
        assert_eq!(parse(&write(&m, &faces[1..], false)).unwrap().faces, None);
    }

    #[test]
    fn big_endian_and_vertex_index_and_st() {
        let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n\
property double z\nproperty float s\nproperty float t\nelement face 1\nproperty list uchar uint vertex_index\nend_header\n"
            .to_vec();
        for p in [[0.0f64, 0., 0.], [1., 0., 0.], [0., 2., 0.]] {
            p.iter().for_each(|v| b.extend(v.to_be_bytes()));
            b.extend(0.25f32.to_be_bytes());
            b.extend(0.75f32.to_be_bytes());
        }
        b.push(3);
        [2u32, 1, 0].iter().for_each(|v| b.extend(v.to_be_bytes()));
        let m = parse(&b).unwrap();
        assert_eq!(m.positions[2], Vec3::new(0., 2., 0.));
        assert_eq!(m.indices, vec![[2, 1, 0]]);
        assert_eq!(m.uvs.unwrap()[1], Vec2::new(0.25, 0.75));
    }

    #[test]
    fn binary_triangles_read_in_parallel_as_one_by_one() {
        // Enough triangles for the parallel path to split them, each with distinct indices.
        let n = 5000u32;
        let positions = (0..n + 2).map(|i| Vec3::new(i as f32, (i % 7) as f32, 0.0)).collect();
        let faces: Vec<Vec<u32>> = (0..n).map(|i| vec![i, i + 1, (i * 7919 + 2) % (n + 2)]).collect();
        let m = Mesh::new(positions, vec![]);
        let bytes = write(&m, &faces, true);
        let r = parse(&bytes).unwrap();
        assert_eq!(r.indices, faces.iter().map(|f| [f[0], f[1], f[2]]).collect::<Vec<_>>());
        assert_eq!(r.faces, None);
        // A negative `int` index in face 1234 is named as the one-by-one reader names it.
        let mut bad = bytes.clone();
        let at = bad.len() - 13 * (n as usize - 1234) + 5;
        bad[at..at + 4].copy_from_slice(&(-3i32).to_le_bytes());
        assert_eq!(parse(&bad).unwrap_err().to_string(), "face 1234 has invalid vertex index -3");
        // An index of no vertex, found from the parallel pass's largest index.
        let mut bad = bytes.clone();
        bad[at..at + 4].copy_from_slice(&(n + 2).to_le_bytes());
        let e = parse(&bad).unwrap_err().to_string();
        assert_eq!(e, format!("vertex index {} is out of range: the file has {} vertices", n + 2, n + 2));
        // A quad late in the file sends the whole element to the one-by-one reader.
        let mut mixed = faces.clone();
        mixed[4321].push(0);
        let r = parse(&write(&m, &mixed, true)).unwrap();
        assert_eq!(r.indices.len(), n as usize + 1);
        assert_eq!(r.indices[4321..4323], [[4321, 4322, mixed[4321][2]], [4321, mixed[4321][2], 0]]);
        assert_eq!(r.faces.as_ref().map(|f| f[4322]), Some(4321));
    }

    #[test]
    fn errors_are_messages_not_panics() {
        let (m, faces) = quad();
        let good = write(&m, &faces, true);
        let s = |b: &[u8]| parse(b).unwrap_err().to_string();
        assert_eq!(s(b"plx\n"), "missing end_header");
        assert_eq!(s(b"plx\nend_header\n"), "not a PLY file (missing \"ply\" magic)");
        // A header that claims a billion vertices in a tiny file.
        let huge = String::from_utf8_lossy(&good).replace("element vertex 5", "element vertex 1000000000");
        let e = s(huge.as_bytes());
        assert!(e.starts_with("element \"vertex\" declares 1000000000 entries but only"), "{e}");
        // Truncated data.
        assert_eq!(s(&good[..good.len() - 3]), "unexpected end of data");
        // Index out of range.
        let mut bad = good.clone();
        let n = bad.len();
        bad[n - 4..].copy_from_slice(&9i32.to_le_bytes());
        assert_eq!(s(&bad), "vertex index 9 is out of range: the file has 5 vertices");
        let nan = String::from_utf8_lossy(&write(&m, &faces, false)).replacen("0 0 0 0 0 1", "nan 0 0 0 0 1", 1);
        assert_eq!(s(nan.as_bytes()), "vertex 0 is not finite");
    }
}
