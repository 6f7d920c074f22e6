//! Writes prism's built-in 1M-triangle terrain (`builtin:terrain`) as PLY meshes and a pbrt-v4
//! scene file that reads them, so another renderer can load exactly the same triangles:
//!
//!     cargo run --release --example terrain_ply -- DIR
//!
//! DIR receives `ground.ply`, `ball.ply`, `light.ply` (binary little-endian) and `terrain.pbrt`.
//! The file is then parsed back with prism's own loader and checked against the built-in scene:
//! every vertex, index and normal, the reflectance of every material, the light's radiance and
//! the camera. A mismatch is an error, so the file on disk is the built-in scene or nothing.

use glam::Mat4;
use prism::accel::AccelKind;
use prism::bench::terrain_scene;
use prism::geometry::Mesh;
use prism::light::Light;
use prism::material::{Material, SpectrumTexture};
use prism::pbrt::mesh_io::ply;
use prism::pbrt::{self, parse_file, ParseOptions};
use prism::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The meshes of `terrain_scene()`, in the order it adds them.
const MESH_FILES: [&str; 3] = ["ground.ply", "ball.ply", "light.ply"];

/// The built-in scene in pbrt-v4's language. Scene units are metres. pbrt's own `LookAt` camera
/// is the built-in one (no `Scale -1 1 1`, which the Cornell box's file needs).
const SCENE_FILE: &str = r#"# prism's built-in terrain (src/bench/terrain.rs) for renderers that read pbrt-v4 files:
# a 600x600-cell heightfield (720,000 triangles) and an icosphere (327,680 triangles) under a
# 60 m x 60 m D65 panel of luminance 5, 60 m up. Written by examples/terrain_ply.rs.
LookAt 0 40 80  0 5 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 256 ] "integer yresolution" [ 256 ] "string filename" "terrain.exr"
PixelFilter "box"
Sampler "zsobol" "integer pixelsamples" [ 64 ]
Integrator "path" "integer maxdepth" [ 8 ]

WorldBegin

AttributeBegin
  Material "diffuse" "spectrum reflectance" [ 360 0.5 830 0.5 ]
  Shape "plymesh" "string filename" "ground.ply"
AttributeEnd

AttributeBegin
  Material "diffuse" "spectrum reflectance" [ 360 0.8 830 0.8 ]
  Shape "plymesh" "string filename" "ball.ply"
AttributeEnd

AttributeBegin
  AreaLightSource "diffuse" "spectrum L" "stdillum-D65" "float scale" [ 5 ]
  Material "diffuse" "spectrum reflectance" [ 360 0 830 0 ]
  Shape "plymesh" "string filename" "light.ply"
AttributeEnd
"#;

/// Wavelengths [nm] at which spectra are compared.
const CHECK_LAMBDAS: [f32; 6] = [360.0, 420.0, 500.0, 555.0, 640.0, 830.0];

fn main() -> ExitCode {
    let Some(dir) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: terrain_ply DIR");
        return ExitCode::from(2);
    };
    match export(&dir) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("terrain_ply: {e}");
            ExitCode::FAILURE
        }
    }
}

fn export(dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let builtin = terrain_scene().build(AccelKind::Obvhs).map_err(|e| e.to_string())?;
    let meshes: Vec<&Mesh> = (0..builtin.primitives().len() as u32)
        .filter(|&i| builtin.primitives()[i as usize].shape.mesh().is_some())
        .map(|i| builtin.mesh(i))
        .collect();
    if meshes.len() != MESH_FILES.len() {
        return Err(format!("the built-in terrain has {} meshes, expected {}", meshes.len(), MESH_FILES.len()));
    }
    for (mesh, name) in meshes.iter().zip(MESH_FILES) {
        let faces: Vec<Vec<u32>> = mesh.indices.iter().map(|t| t.to_vec()).collect();
        let path = dir.join(name);
        std::fs::write(&path, ply::write(mesh, &faces, true)).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let scene_path = dir.join("terrain.pbrt");
    std::fs::write(&scene_path, SCENE_FILE).map_err(|e| format!("{}: {e}", scene_path.display()))?;

    let (desc, mut warnings) = parse_file(&scene_path, &ParseOptions::default()).map_err(|e| e.to_string())?;
    let (builder, _) = pbrt::build(&desc, &mut warnings).map_err(|e| e.to_string())?;
    if let Some(w) = warnings.first() {
        return Err(format!("{}: {w}", scene_path.display()));
    }
    let parsed = builder.build(AccelKind::Obvhs).map_err(|e| e.to_string())?;
    same_scene(&builtin, &parsed)?;
    let triangles = builtin.triangle_count();
    println!("{}: {triangles} triangles, identical to builtin:terrain", scene_path.display());
    Ok(())
}

/// Checks that `b` (read from the files) is the scene `a` (built in).
fn same_scene(a: &Scene, b: &Scene) -> Result<(), String> {
    let (pa, pb) = (a.primitives(), b.primitives());
    if pa.len() != pb.len() {
        return Err(format!("{} meshes read back, {} built in", pb.len(), pa.len()));
    }
    for (i, (a_prim, b_prim)) in pa.iter().zip(pb).enumerate() {
        let what = MESH_FILES[i];
        if a_prim.shape.mesh().is_none() || b_prim.shape.mesh().is_none() {
            return Err(format!("{what}: not a triangle mesh"));
        }
        let (ma, mb) = (a.mesh(i as u32), b.mesh(i as u32));
        if ma.positions != mb.positions || ma.indices != mb.indices {
            return Err(format!("{what}: the triangles read back differ from the built-in ones"));
        }
        let normal_error = match (&ma.normals, &mb.normals) {
            (None, None) => 0.0,
            (Some(na), Some(nb)) if na.len() == nb.len() => {
                na.iter().zip(nb).map(|(x, y)| (*x - *y).length()).fold(0.0, f32::max)
            }
            _ => f32::INFINITY,
        };
        // The loader renormalises normals, which moves them by an ulp or so.
        if normal_error > 1e-6 {
            return Err(format!("{what}: normals read back differ from the built-in ones by up to {normal_error}"));
        }
        let (ra, rb) = (reflectance(a, i)?, reflectance(b, i)?);
        for &l in &CHECK_LAMBDAS {
            if (ra.eval(l) - rb.eval(l)).abs() > 1e-6 {
                return Err(format!(
                    "{what}: reflectance at {l} nm is {} read back, {} built in",
                    rb.eval(l),
                    ra.eval(l)
                ));
            }
        }
    }
    let (ea, eb) = (emission(a)?, emission(b)?);
    for (&l, (&va, &vb)) in CHECK_LAMBDAS.iter().zip(ea.iter().zip(&eb)) {
        if (va - vb).abs() > 1e-4 * va.abs().max(1e-3) {
            return Err(format!("light radiance at {l} nm is {vb} read back, {va} built in"));
        }
    }
    let (ca, cb) = (&a.camera, &b.camera);
    if !matrices_close(&ca.camera_to_world, &cb.camera_to_world) || (ca.fov_deg - cb.fov_deg).abs() > 1e-5 {
        return Err(format!(
            "camera read back {:?} fov {}, built in {:?} fov {}",
            cb.camera_to_world, cb.fov_deg, ca.camera_to_world, ca.fov_deg
        ));
    }
    Ok(())
}

/// The constant Lambertian reflectance of mesh `i`.
fn reflectance(s: &Scene, i: usize) -> Result<&prism::spectrum::Spectrum, String> {
    match &s.materials()[s.primitives()[i].material as usize] {
        Material::Diffuse { reflectance: SpectrumTexture::Constant(r) } => Ok(r),
        other => Err(format!("{}: expected a constant diffuse material, found {other:?}", MESH_FILES[i])),
    }
}

/// Radiance of the one area light at [`CHECK_LAMBDAS`], all its triangles alike.
fn emission(s: &Scene) -> Result<Vec<f32>, String> {
    let mut out: Option<Vec<f32>> = None;
    for l in s.lights() {
        let Light::Area(a) = l else { return Err("a light that is not an area light".into()) };
        let v: Vec<f32> = CHECK_LAMBDAS.iter().map(|&l| a.spectrum.eval(l) * a.scale).collect();
        match &out {
            Some(o) if *o != v => return Err("the light's triangles differ in radiance".into()),
            _ => out = Some(v),
        }
    }
    out.ok_or_else(|| "no area light".into())
}

fn matrices_close(a: &Mat4, b: &Mat4) -> bool {
    a.to_cols_array().iter().zip(b.to_cols_array()).all(|(x, y)| (x - y).abs() <= 1e-5 * x.abs().max(1.0))
}
