//! Shape parameters → geometry: inline meshes, mesh files, quadrics, curves.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec2;

use super::desc::ShapeGeometry;
use super::error::{Location, SceneError, Warning};
use super::mesh_io;
use super::params::ParamSet;
use crate::geometry::{bilinear, loop_subdivision, Mesh};

/// Loads the geometry of a Shape of type `kind` (a name from `names::PRISM_SHAPES`), marking
/// the geometry parameters used. Mesh files (`plymesh`, `objmesh`) are named by
/// [`mesh_file_path`] and read later by [`read_mesh_file`], all together.
pub fn load(
    kind: &str,
    ps: &ParamSet,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) -> Result<ShapeGeometry, SceneError> {
    let err = |m: String| SceneError::syntax(loc, &format!("Shape \"{kind}\""), m);
    match kind {
        k if super::quadric_params::KINDS.contains(&k) => {
            super::quadric_params::load(kind, ps).map(ShapeGeometry::Quadric).map_err(|e| err(e.to_string()))
        }
        "curve" => {
            let mut notes = Vec::new();
            let curves = super::curve_params::load(ps, &mut notes).map_err(|e| err(e.to_string()))?;
            warnings.extend(notes.into_iter().map(|n| Warning::note(loc, n)));
            Ok(ShapeGeometry::Curves(Arc::new(curves)))
        }
        "trianglemesh" => Ok(ShapeGeometry::Mesh(Arc::new(inline_mesh(ps, loc, 3)?))),
        "bilinearmesh" => Ok(ShapeGeometry::Mesh(Arc::new(inline_mesh(ps, loc, 4)?))),
        "loopsubdiv" => Ok(ShapeGeometry::Mesh(Arc::new(loop_subdivision(ps, loc, warnings)?))),
        _ => Err(err(format!("no geometry loader for shape type \"{kind}\""))),
    }
}

/// The file a `plymesh` or `objmesh` shape (`kind`) names, marking its parameters used.
pub fn mesh_file_path(
    kind: &str,
    ps: &ParamSet,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) -> Result<PathBuf, SceneError> {
    let Some(path) = ps.filename("filename") else {
        let message = format!("{kind} needs a \"string filename\" parameter");
        return Err(SceneError::syntax(loc, &format!("Shape \"{kind}\""), message));
    };
    if ps.texture("displacement").is_some() {
        warnings.push(Warning::unsupported(loc, "displacement mapping", "ignores it"));
        let _ = ps.float("edgelength");
    }
    Ok(path)
}

/// The mesh of the PLY (`kind` "plymesh") or OBJ ("objmesh") file `path`, named by the shape at
/// `loc`, and a note when it holds no triangles.
pub fn read_mesh_file(kind: &str, path: &Path, loc: &Location) -> Result<(Mesh, Option<Warning>), SceneError> {
    let bytes = super::input::read(path).map_err(|e| SceneError::Io {
        loc: loc.clone(),
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let mesh = if kind == "plymesh" { mesh_io::ply::parse(&bytes) } else { mesh_io::obj::parse(&bytes) };
    let mesh =
        mesh.map_err(|e| SceneError::Mesh { loc: loc.clone(), path: path.to_path_buf(), message: e.to_string() })?;
    // OBJ readers skip what they do not know, so a wrong file can parse to nothing.
    let note = mesh.indices.is_empty().then(|| {
        Warning::note(loc, format!("mesh file \"{}\" holds no triangles; the shape is empty", path.display()))
    });
    Ok((mesh, note))
}

/// `trianglemesh` (`corners` = 3) or `bilinearmesh` (`corners` = 4, triangulated on the patch's
/// own (u, v) within a stated error: `geometry::bilinear`) from "P", "indices", "N", "uv".
fn inline_mesh(ps: &ParamSet, loc: &Location, corners: usize) -> Result<Mesh, SceneError> {
    let decl = |name: &str, ty: &str| {
        let l = ps.iter().find(|p| *p.name == *name).map_or(loc.clone(), |p| p.loc.clone());
        (l, format!("{ty} {name}"))
    };
    let err = |name: &str, ty: &str, m: String| {
        let (l, t) = decl(name, ty);
        SceneError::syntax(&l, &t, m)
    };
    let Some(p) = ps.point3s("P") else {
        return Err(SceneError::syntax(loc, "Shape", "mesh needs a \"point3 P\" parameter"));
    };
    let n = p.len();
    let implicit = [0, 1, 2, 3];
    let indices: &[i32] = match ps.ints("indices") {
        Some(i) => i,
        None if n == corners => &implicit[..corners],
        None => {
            return Err(SceneError::syntax(
                loc,
                "Shape",
                format!(
                "mesh needs an \"integer indices\" parameter (only a single {corners}-vertex primitive may omit it)"
            ),
            ))
        }
    };
    if !indices.len().is_multiple_of(corners) {
        return Err(err(
            "indices",
            "integer",
            format!("has {} values; a multiple of {corners} is required", indices.len()),
        ));
    }
    let mut tris = Vec::with_capacity(indices.len() / corners * (corners - 2));
    let mut patches = Vec::new();
    let mut checked = [0u32; 4];
    for prim in indices.chunks_exact(corners) {
        for (c, &i) in checked.iter_mut().zip(prim) {
            if i < 0 || i as usize >= n {
                return Err(err("indices", "integer", format!("index {i} is out of range: the mesh has {n} vertices")));
            }
            *c = i as u32;
        }
        if corners == 3 {
            tris.push([checked[0], checked[1], checked[2]]);
        } else {
            // Bilinear patch vertex order is p00, p10, p01, p11.
            patches.push([checked[0], checked[1], checked[2], checked[3]]);
        }
    }
    let mut mesh = Mesh::new(p.to_vec(), tris);
    if let Some(nrm) = ps.normals("N") {
        if nrm.len() != n {
            return Err(err("N", "normal", format!("has {} normals for {n} vertices", nrm.len())));
        }
        mesh.normals = Some(nrm.iter().map(|v| v.normalize_or_zero()).collect());
    }
    let uv: Option<Vec<Vec2>> = ps.point2s("uv").map(<[Vec2]>::to_vec).or_else(|| {
        ps.floats("uv").or_else(|| ps.floats("st")).map(|f| f.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect())
    });
    if let Some(uv) = uv {
        if uv.len() != n {
            return Err(err("uv", "point2", format!("has {} texture coordinates for {n} vertices", uv.len())));
        }
        mesh.uvs = Some(uv);
    }
    if corners == 4 {
        mesh = bilinear::triangulate(&mesh.positions, &patches, mesh.normals.as_deref(), mesh.uvs.as_deref());
    }
    let _ = (ps.vector3s("S"), ps.ints("faceIndices"));
    Ok(mesh)
}

/// pbrt-v4's `loopsubdiv`: the triangles "indices" over "P" (both required) refined "levels"
/// times (default 3) and pushed to the limit surface, with limit normals. pbrt-v4 reads no other
/// parameter ("scheme" is read and ignored), so others are reported unused.
fn loop_subdivision(ps: &ParamSet, loc: &Location, warnings: &mut Vec<Warning>) -> Result<Mesh, SceneError> {
    let at = |name: &str| ps.iter().find(|p| *p.name == *name).map_or(loc.clone(), |p| p.loc.clone());
    let err = |m: String| SceneError::syntax(loc, "Shape \"loopsubdiv\"", m);
    let levels = ps.int_or("levels", 3);
    let _ = ps.string("scheme");
    let Some(p) = ps.point3s("P") else { return Err(err("needs a \"point3 P\" parameter".into())) };
    let Some(indices) = ps.ints("indices") else { return Err(err("needs an \"integer indices\" parameter".into())) };
    let bad_indices = |m: String| SceneError::syntax(&at("indices"), "integer indices", m);
    if indices.is_empty() || !indices.len().is_multiple_of(3) {
        return Err(bad_indices(format!("has {} values; a positive multiple of 3 is required", indices.len())));
    }
    if let Some(i) = indices.iter().find(|&&i| i < 0 || i as usize >= p.len()) {
        return Err(bad_indices(format!("index {i} is out of range: the mesh has {} vertices", p.len())));
    }
    if levels < 0 {
        // pbrt-v4 refines while i < levels: not at all.
        warnings.push(Warning::note(&at("levels"), format!("\"integer levels\" {levels} is negative; 0 is used")));
    }
    let triangles: Vec<[u32; 3]> = indices.chunks_exact(3).map(|t| [t[0] as u32, t[1] as u32, t[2] as u32]).collect();
    let mut mesh = loop_subdivision::subdivide(p, &triangles, levels.max(0) as u32).map_err(|e| err(e.to_string()))?;
    // pbrt-v4 takes S × T over rings it walks clockwise, so its normals face the side from
    // which the control triangles wind clockwise.
    for n in mesh.normals.iter_mut().flatten() {
        *n = -*n;
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::{parse_str, ParseOptions};
    use glam::Vec3;

    /// The geometry and warnings of the one shape in `world`, or the error as text.
    fn shape(world: &str) -> Result<(Mesh, Vec<String>), String> {
        let (desc, mut w) =
            parse_str(&format!("WorldBegin\n{world}\n"), &ParseOptions::default()).map_err(|e| e.to_string())?;
        w.extend(desc.report_unused());
        let ShapeGeometry::Mesh(m) = &desc.shapes[0].geometry else { panic!("not a mesh") };
        Ok(((**m).clone(), w.iter().map(|w| w.to_string()).collect()))
    }

    const TETRAHEDRON: &str =
        "\"point3 P\" [0 0 0  1 0 0  0 1 0  0 0 1] \"integer indices\" [0 2 1  0 1 3  0 3 2  1 2 3]";

    #[test]
    fn loopsubdiv_refines_to_the_limit_surface_with_pbrt_v4s_normals() {
        let (m, w) = shape(&format!("Shape \"loopsubdiv\" \"integer levels\" 2 {TETRAHEDRON}")).unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(m.len(), 4 * 16);
        // 4 control vertices, 6 + 24 inserted on the edges of levels 0 and 1.
        assert_eq!(m.positions.len(), 34);
        // Limit points of a convex control mesh lie strictly inside it.
        assert!(m.positions.iter().all(|p| p.min_element() > 0.0 && p.x + p.y + p.z < 1.0));
        // The tetrahedron is wound outward; pbrt-v4's limit normals point inward.
        let c = m.positions.iter().sum::<Vec3>() / m.positions.len() as f32;
        for (p, n) in m.positions.iter().zip(m.normals.as_ref().unwrap()) {
            assert!(n.dot(*p - c) < 0.0 && (n.length() - 1.0).abs() < 1e-5, "normal {n} at {p}");
        }
        // Default 3 levels; levels 0 keeps the control triangles (at their limit positions).
        assert_eq!(shape(&format!("Shape \"loopsubdiv\" {TETRAHEDRON}")).unwrap().0.len(), 4 * 64);
        let (m0, _) = shape(&format!("Shape \"loopsubdiv\" \"integer levels\" 0 {TETRAHEDRON}")).unwrap();
        assert_eq!((m0.len(), m0.positions[0]), (4, Vec3::splat(0.2)));
    }

    #[test]
    fn loopsubdiv_reports_what_pbrt_v4_ignores_and_rejects_bad_meshes_at_their_line() {
        let (_, w) = shape(&format!(
            "Shape \"loopsubdiv\" \"integer levels\" -1\n\"point2 uv\" [0 0 1 0 0 1 1 1] {TETRAHEDRON}"
        ))
        .unwrap();
        assert!(w.iter().any(|w| w.contains("\"point2 uv\"") && w.contains("not used")), "{w:?}");
        assert!(w.iter().any(|w| w.contains("negative")), "{w:?}");
        let three_on_an_edge = "Shape \"loopsubdiv\"\n \"point3 P\" [0 0 0  1 0 0  0 1 0  0 0 1  0 -1 0]\n \"integer indices\" [0 1 2  1 0 3  0 1 4]";
        let e = shape(three_on_an_edge).unwrap_err();
        assert!(e.starts_with("<string>:2:1:") && e.contains("non-manifold"), "{e}");
        let e = shape("Shape \"loopsubdiv\" \"point3 P\" [0 0 0  1 0 0  0 1 0]\n  \"integer indices\" [0 1 3]")
            .unwrap_err();
        assert!(e.starts_with("<string>:3:3:") && e.contains("out of range"), "{e}");
        assert!(shape("Shape \"loopsubdiv\" \"point3 P\" [0 0 0  1 0 0  0 1 0]").unwrap_err().contains("indices"));
        let e = shape(&format!("Shape \"loopsubdiv\" \"integer levels\" 99 {TETRAHEDRON}")).unwrap_err();
        assert!(e.contains("4^99"), "{e}");
    }
}
