//! Meshes moved out of the description into the scene (`build_moving_meshes`, as `prism render`
//! reads a file) make the scene that copies of them make (`build_with`): PLY meshes with normals
//! and (u, v) at the identity, under a mirroring transform, reversed, moving, emitting and inside
//! an object definition render the same to the bit.

use crate::common::{test_settings, tmpdir};
use glam::{Vec2, Vec3};
use prism::accel::AccelKind;
use prism::geometry::Mesh;
use prism::pbrt::{build_moving_meshes, build_with, mesh_io::ply, parse_str, ParseOptions, ShapeGeometry};
use prism::render::render;

const SCENE: &str = r#"LookAt 0 -5 3  0 0 0.5  0 0 1
Camera "perspective" "float fov" 50
WorldBegin
LightSource "distant" "point3 from" [ 1 -2 3 ] "blackbody L" 5000
LightSource "infinite" "rgb L" [ 0.1 0.1 0.1 ]
Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
Shape "plymesh" "string filename" "grid.ply"
AttributeBegin
  Translate 1.2 0 0.3  Rotate 30 0 0 1  Scale -1 1 1
  Shape "plymesh" "string filename" "grid.ply"
AttributeEnd
AttributeBegin
  ReverseOrientation  Translate -1.2 0 0.6
  Shape "plymesh" "string filename" "grid.ply"
AttributeEnd
AttributeBegin
  Translate 0 1 0.2  ActiveTransform EndTime  Translate 0.3 0 0  ActiveTransform All
  Shape "plymesh" "string filename" "grid.ply"
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 2 1.5 1 ]
  Translate 0 0 2.5  Scale 0.3 0.3 0.3
  Shape "plymesh" "string filename" "grid.ply"
AttributeEnd
ObjectBegin "grid"
  Shape "plymesh" "string filename" "grid.ply"
ObjectEnd
AttributeBegin
  Translate 0 -1.5 0.1  Scale 0.5 0.5 0.5
  ObjectInstance "grid"
AttributeEnd
"#;

/// A bent 8 × 8 grid over [-1, 1]² with normals and (u, v).
fn grid() -> (Mesh, Vec<Vec<u32>>) {
    let n = 8u32;
    let at = |i: u32, j: u32| Vec2::new(i as f32 / n as f32, j as f32 / n as f32);
    let mut mesh = Mesh::new(Vec::new(), Vec::new());
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for j in 0..=n {
        for i in 0..=n {
            let uv = at(i, j);
            let (x, y) = (2.0 * uv.x - 1.0, 2.0 * uv.y - 1.0);
            mesh.positions.push(Vec3::new(x, y, 0.3 * x * x));
            normals.push(Vec3::new(-0.6 * x, 0.0, 1.0).normalize());
            uvs.push(uv);
        }
    }
    mesh.normals = Some(normals);
    mesh.uvs = Some(uvs);
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let faces = (0..n * n)
        .flat_map(|k| {
            let (i, j) = (k % n, k / n);
            [vec![id(i, j), id(i + 1, j), id(i + 1, j + 1)], vec![id(i, j), id(i + 1, j + 1), id(i, j + 1)]]
        })
        .collect();
    (mesh, faces)
}

#[test]
fn meshes_moved_into_the_scene_render_as_copies_of_them() {
    let d = tmpdir("moved-meshes");
    let (mesh, faces) = grid();
    std::fs::write(d.join("grid.ply"), ply::write(&mesh, &faces, true)).unwrap();
    let opts = ParseOptions { base_dir: Some(d.clone()), ..Default::default() };
    let settings = test_settings((40, 30), 4, 7, 3);
    let (desc, mut warnings) = parse_str(SCENE, &opts).unwrap();
    let (copied, _) = build_with(&desc, &mut warnings, opts.quadrics).unwrap();
    let (mut desc, mut warnings) = parse_str(SCENE, &opts).unwrap();
    let (moved, _) = build_moving_meshes(&mut desc, &mut warnings, opts.quadrics).unwrap();
    // The static world shapes gave their meshes up; the moving one kept its own.
    let triangles: Vec<usize> = desc
        .shapes
        .iter()
        .map(|s| match &s.geometry {
            ShapeGeometry::Mesh(m) => m.len(),
            _ => panic!("a mesh"),
        })
        .collect();
    assert_eq!(triangles, [0, 0, 0, 128, 0]);
    let copied = render(&copied.build(AccelKind::Obvhs).unwrap(), &settings, |_| {}).unwrap().0;
    let moved = render(&moved.build(AccelKind::Obvhs).unwrap(), &settings, |_| {}).unwrap().0;
    let y = |f: &prism::film::Film| f.pixels.iter().map(|p| p.xyz_sum.y).collect::<Vec<_>>();
    assert!(y(&copied).iter().filter(|&&v| v > 0.01).count() > 600, "too few lit pixels");
    assert_eq!(y(&copied), y(&moved));
}
