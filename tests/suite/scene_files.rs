//! The example scenes under scenes/: their PLY meshes are generated here (run with
//! `PRISM_REGEN_MESHES=1` to rewrite them) and must match the committed bytes, and every scene
//! must parse without warnings into the expected entities.

use crate::common::test_settings;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use prism::geometry::{Mesh, Quadric};
use prism::pbrt::mesh_io::ply;
use prism::pbrt::{self, *};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// Torus about the z axis: major radius `big`, minor radius `small`, quads with seam copies
/// so uv is continuous; outward normals.
fn torus(big: f32, small: f32, nu: u32, nv: u32) -> (Mesh, Vec<Vec<u32>>) {
    let tau = std::f32::consts::TAU;
    let (mut p, mut n, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..=nu {
        for j in 0..=nv {
            let (u, v) = (i as f32 / nu as f32, j as f32 / nv as f32);
            let (cu, su, cv, sv) = ((u * tau).cos(), (u * tau).sin(), (v * tau).cos(), (v * tau).sin());
            p.push(Vec3::new((big + small * cv) * cu, (big + small * cv) * su, small * sv));
            n.push(Vec3::new(cv * cu, cv * su, sv));
            uv.push(Vec2::new(u, v));
        }
    }
    let id = |i: u32, j: u32| i * (nv + 1) + j;
    let faces = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
        .collect();
    let mut m = Mesh::new(p, vec![]);
    m.normals = Some(n);
    m.uvs = Some(uv);
    (m, faces)
}

/// Unit icosphere: prism's own generator, with its triangles as PLY faces.
fn icosphere(levels: u32) -> (Mesh, Vec<Vec<u32>>) {
    let m = prism::geometry::shapes::icosphere(Vec3::ZERO, 1.0, levels);
    let faces = m.indices.iter().map(|t| t.to_vec()).collect();
    let mut out = Mesh::new(m.positions, vec![]);
    out.normals = m.normals;
    (out, faces)
}

/// Floor grid on y = 0 over [−half, half]², `n`×`n` quads facing +y, uv over [0, 1]².
fn floor_grid(half: f32, n: u32) -> (Mesh, Vec<Vec<u32>>) {
    let mut m = Mesh::new(vec![], vec![]);
    let mut uv = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            m.positions.push(Vec3::new(-half + 2.0 * half * u, 0.0, -half + 2.0 * half * v));
            uv.push(Vec2::new(u, v));
        }
    }
    m.uvs = Some(uv);
    let id = |i: u32, j: u32| i * (n + 1) + j;
    let faces = (0..n)
        .flat_map(|i| (0..n).map(move |j| vec![id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]))
        .collect();
    (m, faces)
}

/// Every triangle's geometric normal agrees with the winding the generator intended.
fn check_outward(bytes: &[u8], outward: impl Fn(Vec3) -> Vec3) {
    let m = ply::parse(bytes).unwrap();
    for i in 0..m.len() {
        let [a, b, c] = m.triangle(i);
        let ng = (b - a).cross(c - a);
        let centre = (a + b + c) / 3.0;
        assert!(ng.dot(outward(centre)) > 0.0, "triangle {i} winds inward");
    }
}

#[test]
fn committed_meshes_match_their_generators() {
    let (t, tf) = torus(0.5, 0.18, 48, 24);
    let (s, sf) = icosphere(2);
    let (g, gf) = floor_grid(4.0, 8);
    let files = [
        ("torus.ply", ply::write(&t, &tf, true)),
        ("icosphere.ply", ply::write(&s, &sf, false)),
        ("floor_grid.ply", ply::write(&g, &gf, false)),
    ];
    check_outward(&files[0].1, |p| {
        let ring = Vec3::new(p.x, p.y, 0.0).normalize() * 0.5;
        p - ring
    });
    check_outward(&files[1].1, |p| p);
    check_outward(&files[2].1, |_| Vec3::Y);
    for (name, bytes) in files {
        let path = scenes().join("meshes").join(name);
        if std::env::var_os("PRISM_REGEN_MESHES").is_some() {
            std::fs::write(&path, &bytes).unwrap();
        }
        let committed = std::fs::read(&path).unwrap_or_default();
        assert!(committed == bytes, "{} differs from its generator; rerun with PRISM_REGEN_MESHES=1", path.display());
    }
}

fn load(name: &str) -> SceneDesc {
    let (d, w) = parse_file(&scenes().join(name), &ParseOptions { strict: true, ..Default::default() })
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(w.is_empty(), "{name}: {w:?}");
    d
}

fn mesh_triangles(s: &ShapeDesc) -> usize {
    match &s.geometry {
        ShapeGeometry::Mesh(m) => m.len(),
        ShapeGeometry::Quadric(_) | ShapeGeometry::Curves(_) => 0,
    }
}

#[test]
fn cornell_torus_parses() {
    let d = load("cornell_torus.pbrt");
    assert_eq!(d.film.params.int("xresolution"), Some(400));
    assert_eq!(d.named_materials.len(), 7);
    assert_eq!(d.shapes.len(), 8);
    let lights: Vec<&ShapeDesc> = d.shapes.iter().filter(|s| s.area_light.is_some()).collect();
    assert_eq!(lights.len(), 1);
    assert!(lights[0].reverse_orientation);
    let torus = d.shapes.iter().find(|s| s.kind == "plymesh").unwrap();
    assert_eq!(mesh_triangles(torus), 48 * 24 * 2);
    assert_eq!(d.material(&torus.material).unwrap().kind, "conductor");
    // Every wall faces the inside of the box; the light (after ReverseOrientation) faces down.
    let centre = Vec3::new(0.0, 1.6, 0.0);
    for s in &d.shapes[..5] {
        let ShapeGeometry::Mesh(m) = &s.geometry else { panic!("walls are meshes") };
        for i in 0..m.len() {
            let [a, b, c] = m.triangle(i);
            let faces_in = (b - a).cross(c - a).dot(centre - a) > 0.0;
            assert!(faces_in, "{}: wall triangle {i} faces out", s.loc);
        }
    }
    let ShapeGeometry::Mesh(light) = &lights[0].geometry else { panic!("the light is a mesh") };
    let [a, b, c] = light.triangle(0);
    let flip = if lights[0].reverse_orientation { -1.0 } else { 1.0 };
    assert!(flip * (b - a).cross(c - a).y < 0.0, "the ceiling light emits upwards");
    // Camera from the included file.
    assert!(d.camera.directive.loc.file().ends_with("common/studio_camera.pbrt"));
}

#[test]
fn instanced_orchard_parses() {
    let d = load("instanced_orchard.pbrt");
    assert_eq!(d.objects.len(), 1);
    assert_eq!(d.instances.len(), 13);
    let tree = &d.objects[0];
    assert_eq!(tree.shapes.len(), 2);
    assert_eq!(mesh_triangles(&tree.shapes[1]), 320);
    assert_eq!(d.material(&tree.shapes[1].material).unwrap().kind, "coateddiffuse");
    assert_eq!(d.lights.iter().map(|l| l.kind).collect::<Vec<_>>(), ["distant", "infinite"]);
    // Second instance of the first row: Translate −6 0 −3 then +3 in x.
    assert_eq!(d.instances[1].world_from_instance.w_axis.truncate(), Vec3::new(-3., 0., -3.));
}

#[test]
fn material_row_parses() {
    let d = load("material_row.pbrt");
    assert_eq!(d.lights.iter().map(|l| l.kind).collect::<Vec<_>>(), ["spot", "point"]);
    assert_eq!(d.instances.len(), 2);
    let kinds: Vec<&str> = d.shapes.iter().map(|s| d.material(&s.material).map_or("default", |m| m.kind)).collect();
    assert_eq!(kinds, ["diffuse", "diffuse", "dielectric", "conductor", "coateddiffuse"]);
    // The copper hemisphere sits at the "row" coordinate system + 1.1 x.
    assert_eq!(d.shapes[3].world_from_object.w_axis.truncate(), Vec3::new(1.1, 0.45, 0.));
    assert_eq!(mesh_triangles(&d.shapes[0]), 8 * 8 * 2);
    let ShapeGeometry::Quadric(Quadric::Sphere { z_max, .. }) = d.shapes[3].geometry else { panic!() };
    assert_eq!(z_max, 0.2);
}

#[test]
fn every_example_scene_builds_without_warnings_and_renders_finite_non_black() {
    use prism::accel::AccelKind;
    use prism::render::render;
    let mut names: Vec<PathBuf> = std::fs::read_dir(scenes())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "pbrt"))
        .collect();
    names.sort();
    assert!(names.len() >= 6, "{names:?}");
    for path in names {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let desc = load(&name);
        let mut warnings = Vec::new();
        let (builder, _) = pbrt::build(&desc, &mut warnings).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        let scene = builder.build(AccelKind::Obvhs).unwrap();
        let s = test_settings((24, 16), 2, 3, 4);
        let (film, stats) = render(&scene, &s, |_| {}).unwrap();
        assert_eq!(stats.nonfinite, 0, "{name}: {:?}", stats.nonfinite_at);
        let y: f64 = film.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).sum();
        assert!(y > 0.0, "{name}: black image");
    }
}
