//! Shape parameters → geometry: inline meshes, mesh files, quadrics.

use std::sync::Arc;

use glam::Vec2;

use super::desc::ShapeGeometry;
use super::error::{Location, SceneError, Warning};
use super::mesh_io;
use super::params::ParamSet;
use crate::geometry::{bilinear, Mesh};

/// Loads the geometry of a Shape of type `kind` (a name from `names::PRISM_SHAPES`), marking
/// the geometry parameters used.
pub fn load(
    kind: &str,
    ps: &ParamSet,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) -> Result<ShapeGeometry, SceneError> {
    let err = |m: String| SceneError::syntax(loc, &format!("Shape \"{kind}\""), m);
    match kind {
        "sphere" | "disk" | "cylinder" => {
            super::quadric_params::load(kind, ps).map(ShapeGeometry::Quadric).map_err(err)
        }
        "trianglemesh" => Ok(ShapeGeometry::Mesh(Arc::new(inline_mesh(ps, loc, 3)?))),
        "bilinearmesh" => Ok(ShapeGeometry::Mesh(Arc::new(inline_mesh(ps, loc, 4)?))),
        "loopsubdiv" => {
            let _ = ps.int("levels");
            warnings.push(Warning::unsupported(loc, "loop subdivision", "renders the control mesh"));
            Ok(ShapeGeometry::Mesh(Arc::new(inline_mesh(ps, loc, 3)?)))
        }
        "plymesh" | "objmesh" => {
            let Some(path) = ps.filename("filename") else {
                return Err(err(format!("{kind} needs a \"string filename\" parameter")));
            };
            if ps.texture("displacement").is_some() {
                warnings.push(Warning::unsupported(loc, "displacement mapping", "ignores it"));
                let _ = ps.float("edgelength");
            }
            let bytes = super::input::read(&path).map_err(|e| SceneError::Io {
                loc: loc.clone(),
                path: path.clone(),
                reason: e.to_string(),
            })?;
            let mesh = if kind == "plymesh" { mesh_io::ply::parse(&bytes) } else { mesh_io::obj::parse(&bytes) };
            let mesh = mesh.map_err(|message| SceneError::Mesh { loc: loc.clone(), path: path.clone(), message })?;
            if mesh.indices.is_empty() {
                // OBJ readers skip what they do not know, so a wrong file can parse to nothing.
                let message = format!("mesh file \"{}\" holds no triangles; the shape is empty", path.display());
                warnings.push(Warning::note(loc, message));
            }
            Ok(ShapeGeometry::Mesh(Arc::new(mesh)))
        }
        _ => Err(err(format!("no geometry loader for shape type \"{kind}\""))),
    }
}

/// `trianglemesh` (`corners` = 3) or `bilinearmesh` (`corners` = 4, triangulated on the patch's
/// own (u, v) within a stated error: `geometry::bilinear`) from "P", "indices", "N", "uv".
fn inline_mesh(ps: &ParamSet, loc: &Location, corners: usize) -> Result<Mesh, SceneError> {
    let decl = |name: &str, ty: &str| {
        let l = ps.iter().find(|p| p.name == name).map_or(loc.clone(), |p| p.loc.clone());
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
    let indices: Vec<i32> = match ps.ints("indices") {
        Some(i) => i.to_vec(),
        None if n == corners => (0..corners as i32).collect(),
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
    let mut checked = Vec::with_capacity(corners);
    for prim in indices.chunks_exact(corners) {
        checked.clear();
        for &i in prim {
            if i < 0 || i as usize >= n {
                return Err(err("indices", "integer", format!("index {i} is out of range: the mesh has {n} vertices")));
            }
            checked.push(i as u32);
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
