//! Wavefront OBJ reader for prism's "objmesh" shape: `v`, `vt`, `vn`, `f` (with `v`, `v/vt`,
//! `v//vn`, `v/vt/vn` corners, negative = relative indices), polygons split into triangle fans.
//! Groups, objects and materials are ignored: one OBJ file is one mesh with one material.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::MeshError;
use crate::geometry::Mesh;

/// Parses OBJ text into a mesh (object space). Errors name the line.
pub fn parse(bytes: &[u8]) -> Result<Mesh, MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|_| MeshError::NotUtf8)?;
    let (mut v, mut vt, mut vn) = (Vec::new(), Vec::new(), Vec::new());
    // Corners (v, vt, vn) are de-duplicated into single-index vertices.
    let mut corner_ids: HashMap<(usize, Option<usize>, Option<usize>), u32> = HashMap::new();
    let mut corners: Vec<(usize, Option<usize>, Option<usize>)> = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let ln = ln + 1;
        let line = line.split('#').next().unwrap_or("");
        let mut w = line.split_whitespace();
        let Some(kw) = w.next() else { continue };
        let nums = |w: std::str::SplitWhitespace, n: usize| -> Result<Vec<f32>, MeshError> {
            let f: Vec<f32> = w
                .take(n)
                .map(|s| s.parse::<f32>().ok().filter(|x| x.is_finite()))
                .collect::<Option<_>>()
                .ok_or_else(|| MeshError::BadNumber { line: ln, text: line.trim().to_string() })?;
            if f.len() < n {
                return Err(MeshError::TooFewNumbers { line: ln, keyword: kw.to_string(), count: n });
            }
            Ok(f)
        };
        match kw {
            "v" => {
                let f = nums(w, 3)?;
                v.push(Vec3::new(f[0], f[1], f[2]));
            }
            "vn" => {
                let f = nums(w, 3)?;
                vn.push(Vec3::new(f[0], f[1], f[2]).normalize_or_zero());
            }
            "vt" => {
                let f = nums(w, 2)?;
                vt.push(Vec2::new(f[0], f[1]));
            }
            "f" => {
                let mut poly = Vec::new();
                for c in w {
                    let mut parts = c.split('/');
                    let resolve = |s: Option<&str>, n: usize, what: &'static str| -> Result<Option<usize>, MeshError> {
                        match s {
                            None | Some("") => Ok(None),
                            Some(s) => {
                                let i: i64 =
                                    s.parse().map_err(|_| MeshError::BadIndex { line: ln, text: s.to_string() })?;
                                let r = if i > 0 { i - 1 } else { n as i64 + i };
                                if i == 0 || r < 0 || r >= n as i64 {
                                    return Err(MeshError::IndexOutOfRange { line: ln, what, index: i, defined: n });
                                }
                                Ok(Some(r as usize))
                            }
                        }
                    };
                    let pi = resolve(parts.next(), v.len(), "vertex")?
                        .ok_or_else(|| MeshError::NoVertexIndex { line: ln, corner: c.to_string() })?;
                    let ti = resolve(parts.next(), vt.len(), "texture")?;
                    let ni = resolve(parts.next(), vn.len(), "normal")?;
                    let key = (pi, ti, ni);
                    let id = match corner_ids.get(&key) {
                        Some(&id) => id,
                        None => {
                            let id = u32::try_from(corners.len()).map_err(|_| MeshError::TooManyVertices)?;
                            corners.push(key);
                            corner_ids.insert(key, id);
                            id
                        }
                    };
                    poly.push(id);
                }
                if poly.len() < 3 {
                    return Err(MeshError::TooFewCorners { line: ln });
                }
                for j in 1..poly.len() - 1 {
                    tris.push([poly[0], poly[j], poly[j + 1]]);
                }
            }
            _ => {} // o, g, s, usemtl, mtllib, l, p: not geometry prism uses.
        }
    }
    let mut mesh = Mesh::new(corners.iter().map(|c| v[c.0]).collect(), tris);
    if !corners.is_empty() && corners.iter().all(|c| c.2.is_some()) {
        mesh.normals = Some(corners.iter().filter_map(|c| c.2.map(|i| vn[i])).collect());
    }
    if !corners.is_empty() && corners.iter().all(|c| c.1.is_some()) {
        mesh.uvs = Some(corners.iter().filter_map(|c| c.1.map(|i| vt[i])).collect());
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_with_shared_corners_and_relative_indices() {
        let src = "# a unit quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 2\nvt 0 0\nvt 1 1\n\
                   f 1/1/1 2/1/1 3/2/1 -1/2/-1\n";
        let m = parse(src.as_bytes()).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.positions[3], Vec3::Y);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::Z);
        assert_eq!(m.uvs.as_ref().unwrap()[2], Vec2::ONE);
        assert!((m.area() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn errors_name_the_line() {
        let e = |b: &[u8]| parse(b).unwrap_err().to_string();
        assert_eq!(e(b"v 0 0 0\nf 1 2 3\n"), "line 2: vertex index 2 is out of range (1 defined)");
        assert_eq!(e(b"v 0 0\n"), "line 1: \"v\" needs 3 numbers");
        assert_eq!(e(b"v 0 nan 0\n"), "line 1: bad number in \"v 0 nan 0\"");
        assert_eq!(e(b"v 0 0 0\nf 1 1\n"), "line 2: a face needs at least 3 corners");
    }
}
