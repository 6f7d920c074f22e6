//! Shape parameters → geometry: inline meshes, mesh files, spheres; plus mesh helpers.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::desc::ShapeGeometry;
use super::error::{Location, SceneError, Warning};
use super::mesh_io;
use super::params::ParamSet;
use crate::geometry::Mesh;

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
        "sphere" => {
            let radius = ps.float_or("radius", 1.0);
            if radius <= 0.0 {
                return Err(err(format!("sphere radius must be positive, got {radius}")));
            }
            let z_min = ps.float_or("zmin", -radius).clamp(-radius, radius);
            let z_max = ps.float_or("zmax", radius).clamp(-radius, radius);
            let phi_max = ps.float_or("phimax", 360.0);
            if z_min >= z_max {
                return Err(err(format!("sphere zmin ({z_min}) must be below zmax ({z_max})")));
            }
            if !(phi_max > 0.0 && phi_max <= 360.0) {
                return Err(err(format!("sphere phimax must be in (0, 360] degrees, got {phi_max}")));
            }
            Ok(ShapeGeometry::Sphere { radius, z_min, z_max, phi_max })
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

/// `trianglemesh` (`corners` = 3) or `bilinearmesh` (`corners` = 4, split into two triangles:
/// exact for planar patches) from "P", "indices", "N", "uv".
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
            tris.push([checked[0], checked[1], checked[3]]);
            tris.push([checked[0], checked[3], checked[2]]);
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
    } else if corners == 4 && n == 4 {
        // One patch: pbrt-v4's default (u, v) are the patch's own parameters, (0, 0) at p00 to
        // (1, 1) at p11, which the two triangles reproduce exactly on a parallelogram.
        mesh.uvs = Some(vec![Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE]);
    }
    let _ = (ps.vector3s("S"), ps.ints("faceIndices"));
    Ok(mesh)
}

/// Default latitude bands of [`tessellate_sphere`] (longitude segments scale with φmax, 96 for
/// a full sphere): area within 0.1 % of the analytic sphere, about 9 000 triangles.
pub const SPHERE_BANDS: u32 = 48;

/// pbrt's sphere (`radius`, z clip range, `phi_max` in degrees) as a triangle mesh at the
/// default resolution, for backends without an analytic sphere.
pub fn tessellate_sphere(radius: f32, z_min: f32, z_max: f32, phi_max: f32) -> Mesh {
    let n_phi = ((2 * SPHERE_BANDS) as f32 * phi_max / 360.0).ceil() as u32;
    tessellate_sphere_n(radius, z_min, z_max, phi_max, SPHERE_BANDS, n_phi)
}

/// A triangle mesh approximating pbrt's sphere with `n_theta` × `n_phi` quads; outward
/// normals, zero-area pole triangles left out. Texture coordinates as pbrt-v4's sphere:
/// u = φ/φmax, v = (θ − θ(z_min))/(θ(z_max) − θ(z_min)), so v runs from 0 at z_min to 1 at z_max.
pub fn tessellate_sphere_n(radius: f32, z_min: f32, z_max: f32, phi_max: f32, n_theta: u32, n_phi: u32) -> Mesh {
    let (n_theta, n_phi) = (n_theta.max(2), n_phi.max(3));
    let theta_lo = (z_max / radius).clamp(-1.0, 1.0).acos();
    let theta_hi = (z_min / radius).clamp(-1.0, 1.0).acos();
    let phi_max = phi_max.to_radians();
    let mut pos = Vec::new();
    let mut nrm = Vec::new();
    let mut uvs = Vec::new();
    for i in 0..=n_theta {
        let v = i as f32 / n_theta as f32;
        let theta = theta_lo + v * (theta_hi - theta_lo);
        for j in 0..=n_phi {
            let u = j as f32 / n_phi as f32;
            let phi = u * phi_max;
            // sin θ from cos θ keeps the poles exact (f32 sin(π) is not 0), so pole triangles
            // are detected as degenerate below.
            let z = theta.cos();
            let s = (1.0 - z * z).max(0.0).sqrt();
            let d = Vec3::new(s * phi.cos(), s * phi.sin(), z);
            pos.push(radius * d);
            nrm.push(d);
            // `v` runs down from z_max here; pbrt's v runs up from z_min.
            uvs.push(Vec2::new(u, 1.0 - v));
        }
    }
    let row = n_phi + 1;
    let mut tris = Vec::new();
    for i in 0..n_theta {
        for j in 0..n_phi {
            let (a, b, c, d) = (i * row + j, i * row + j + 1, (i + 1) * row + j, (i + 1) * row + j + 1);
            // Skip the zero-area triangles at the poles.
            if pos[a as usize] != pos[b as usize] {
                tris.push([a, c, b]);
            }
            if pos[c as usize] != pos[d as usize] {
                tris.push([b, c, d]);
            }
        }
    }
    Mesh { positions: pos, indices: tris, normals: Some(nrm), uvs: Some(uvs) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tessellated_sphere_area_converges_to_4_pi_r2() {
        let m = tessellate_sphere(2.0, -2.0, 2.0, 360.0);
        let exact = 4.0 * std::f32::consts::PI * 4.0;
        // Inscribed polygons underestimate by O(h²): with 48×96 cells the deficit is < 0.1 %.
        let rel = (exact - m.area()) / exact;
        assert!(rel > 0.0 && rel < 1e-3, "relative deficit {rel}");
        // A clipped, partial sphere: zone area 2πr·(zmax − zmin)·φmax/360.
        let part = tessellate_sphere(1.0, -0.5, 0.5, 180.0);
        let exact = std::f32::consts::PI;
        let rel = (exact - part.area()) / exact;
        assert!(rel > 0.0 && rel < 1e-3, "relative deficit {rel}");
        assert!(m.indices.iter().all(|t| t.iter().all(|&i| (i as usize) < m.positions.len())));
        // Outward winding: geometric normal agrees with the vertex normal.
        for i in 0..m.len() {
            let [a, b, c] = m.triangle(i);
            let ng = (b - a).cross(c - a);
            assert!(ng.dot(a + b + c) > 0.0, "triangle {i} faces inward");
        }
    }

    #[test]
    fn sphere_uv_follows_pbrt() {
        // pbrt-v4: u = φ/φmax with φ = atan2(y, x) ∈ [0, 2π), v = 0 at z_min and 1 at z_max,
        // linear in θ = acos(z/r).
        let (r, z_min, z_max) = (2.0f32, -1.0f32, 1.5f32);
        let m = tessellate_sphere(r, z_min, z_max, 270.0);
        let uvs = m.uvs.as_ref().unwrap();
        let (t_min, t_max) = ((z_min / r).acos(), (z_max / r).acos());
        for (p, uv) in m.positions.iter().zip(uvs) {
            let theta = (p.z / r).clamp(-1.0, 1.0).acos();
            let v = (theta - t_min) / (t_max - t_min);
            assert!((uv.y - v).abs() < 1e-4, "{p}: v {} vs {v}", uv.y);
            let mut phi = p.y.atan2(p.x);
            if phi < -1e-4 {
                phi += 2.0 * std::f32::consts::PI;
            }
            // The seam vertex at φ = 0 carries u = 0 (and its twin at φmax u = 1).
            let u = phi / 270f32.to_radians();
            if p.x * p.x + p.y * p.y > 1e-6 && uv.x < 0.999 {
                assert!((uv.x - u).abs() < 1e-4, "{p}: u {} vs {u}", uv.x);
            }
        }
    }
}
