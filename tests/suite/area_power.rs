//! pbrt-v4's `power` on an area light is each face's flux: pbrt-v4 makes one `DiffuseAreaLight`
//! per shape it creates, and a mesh creates one shape per face — a triangle of a triangle mesh,
//! of a subdivided mesh's last level or of a PLY file, a bilinear patch of a bilinear mesh or a
//! PLY quad — each normalised by its own area. Checked by measuring the luminance each face sends
//! out and summing luminance × 2π × area (a two-sided Lambertian emitter) over the face, with the
//! areas taken from the file's geometry: each face emits `power`, F faces F × `power`.

use crate::common::{pbrt_scene, tmpdir};
use glam::Vec3;
use prism::accel::AccelKind;
use prism::integrator::Integrator;
use prism::light::photometry::lumens_per_unit_y;
use prism::light::Light;
use prism::measure::{radiance, Estimate};
use prism::scene::Scene;

const POWER: f64 = 5.0;
/// Luminance estimates per measured point.
const SAMPLES: u64 = 3000;

/// A face as triangles of the plane z = 0, which together cover it.
type Face = Vec<[Vec3; 3]>;

fn area(t: &[Vec3; 3]) -> f64 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length() as f64
}

fn centroid(t: &[Vec3; 3]) -> Vec3 {
    (t[0] + t[1] + t[2]) / 3.0
}

/// The scene of an emitter given as `shape` (two-sided, black, `power` 5, in the plane z = 0).
fn emitter(shape: &str, light: &str) -> Scene {
    pbrt_scene(
        &format!(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n\
             AreaLightSource \"diffuse\" {light} \"float power\" {POWER} \"bool twosided\" true\n\
             Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n{shape}\n"
        ),
        AccelKind::Obvhs,
    )
}

/// The luminance [cd/m²] the emitter sends along +z from `p`.
fn luminance(scene: &Scene, p: Vec3, seed: u64) -> Estimate {
    let integrator = Integrator { max_depth: 0, ..Default::default() };
    radiance(scene, &integrator, p, Vec3::Z, SAMPLES, seed).luminance
}

/// Luminous flux [lm] a two-sided face sends out, 2π ∫ L dA, from the luminance at each
/// triangle's centroid (uniform over the face), and its standard error.
fn face_flux(scene: &Scene, face: &Face, seed: u64) -> Estimate {
    let (mut mean, mut var) = (0.0, 0.0);
    for (k, t) in face.iter().enumerate() {
        let l = luminance(scene, centroid(t), seed + k as u64);
        let w = 2.0 * std::f64::consts::PI * area(t);
        mean += w * l.mean;
        var += (w * l.std_err).powi(2);
    }
    Estimate { mean, std_err: var.sqrt() }
}

/// Each face emits `power` and all of them F × `power` (luminous flux in prism's unit: `power`
/// × K_m ∫ȳ, as pbrt-v4's photometric normalisation), within 4 standard errors.
fn assert_each_face_emits_the_power(what: &str, scene: &Scene, faces: &[Face]) {
    let expected = POWER * lumens_per_unit_y() as f64;
    let areas: Vec<f64> = faces.iter().map(|f| f.iter().map(area).sum()).collect();
    assert!(areas.iter().any(|&a| (a - areas[0]).abs() > 0.2 * areas[0]), "{what}: faces of equal area {areas:?}");
    let (mut total, mut var) = (0.0, 0.0);
    for (i, face) in faces.iter().enumerate() {
        let phi = face_flux(scene, face, 100 * i as u64);
        assert!(phi.mean > 0.0, "{what}: face {i} is black");
        let tol = 4.0 * phi.std_err + 1e-4 * expected;
        assert!(
            (phi.mean - expected).abs() <= tol,
            "{what}: face {i} (area {}) emits {} ± {} lm, expected {expected}",
            areas[i],
            phi.mean,
            phi.std_err
        );
        total += phi.mean;
        var += phi.std_err.powi(2);
    }
    let n = faces.len() as f64;
    assert!(
        (total - n * expected).abs() <= 4.0 * var.sqrt() + 1e-4 * n * expected,
        "{what}: {n} faces emit {total} ± {} lm, expected {}",
        var.sqrt(),
        n * expected
    );
}

fn v(x: f32, y: f32) -> Vec3 {
    Vec3::new(x, y, 0.0)
}

/// The quadrilateral a, b, c, d (in order around it, convex and planar) as two triangles.
fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Face {
    vec![[a, b, c], [a, c, d]]
}

#[test]
fn each_triangle_of_a_triangle_mesh_emits_the_power() {
    let scene = emitter(
        r#"Shape "trianglemesh" "point3 P" [0 0 0  1 0 0  0 2 0  4 3 0] "integer indices" [0 1 2  1 3 2]"#,
        r#""blackbody L" 4000"#,
    );
    let faces = vec![vec![[v(0., 0.), v(1., 0.), v(0., 2.)]], vec![[v(1., 0.), v(4., 3.), v(0., 2.)]]];
    assert_each_face_emits_the_power("trianglemesh", &scene, &faces);
}

/// A bilinear mesh of a 1 × 1 square, a 3 × 2 rectangle and a planar trapezoid: the trapezoid
/// is not a parallelogram, so it is cut into many cells, which must still share its power.
#[test]
fn each_patch_of_a_bilinear_mesh_emits_the_power() {
    let scene = emitter(
        r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 0
                                          2 0 0  5 0 0  2 2 0  5 2 0
                                          0 3 0  3 3 0  0 4 0  1 4 0]
           "integer indices" [0 1 2 3  4 5 6 7  8 9 10 11]"#,
        r#""blackbody L" 4000"#,
    );
    let n = scene.lights().len();
    assert!(n > 6, "the trapezoid is one cell: {n} triangles");
    let faces = vec![
        quad(v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)),
        quad(v(2., 0.), v(5., 0.), v(5., 2.), v(2., 2.)),
        quad(v(0., 3.), v(3., 3.), v(1., 4.), v(0., 4.)),
    ];
    assert_each_face_emits_the_power("bilinearmesh", &scene, &faces);
}

/// A PLY file of a triangle, a 3 × 2 rectangle and a trapezoid (quads in order around them):
/// pbrt-v4 reads the triangle as a triangle and each quad as one bilinear patch.
#[test]
fn each_triangle_and_quad_of_a_ply_file_emits_the_power() {
    let dir = tmpdir("area-power-ply");
    let path = dir.join("faces.ply");
    let ply = "ply\nformat ascii 1.0\nelement vertex 11\nproperty float x\nproperty float y\nproperty float z\n\
               element face 3\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0\n1 0 0\n0 1 0\n2 0 0\n5 0 0\n5 2 0\n2 2 0\n0 3 0\n3 3 0\n2 4 0\n0 4 0\n\
               3 0 1 2\n4 3 4 5 6\n4 7 8 9 10\n";
    std::fs::write(&path, ply).unwrap();
    let scene = emitter(&format!(r#"Shape "plymesh" "string filename" "{}""#, path.display()), r#""blackbody L" 3000"#);
    let faces = vec![
        vec![[v(0., 0.), v(1., 0.), v(0., 1.)]],
        quad(v(2., 0.), v(5., 0.), v(5., 2.), v(2., 2.)),
        quad(v(0., 3.), v(3., 3.), v(2., 4.), v(0., 4.)),
    ];
    assert_each_face_emits_the_power("plymesh", &scene, &faces);
}

/// A subdivided planar mesh: pbrt-v4 makes one triangle shape per triangle of the last level,
/// so each of them, of whatever size, emits the power. (The limit surface of a planar control
/// mesh is planar; its triangles are read back from the scene.)
#[test]
fn each_triangle_of_a_subdivided_mesh_emits_the_power() {
    let scene = emitter(
        r#"Shape "loopsubdiv" "integer levels" 1 "point3 P" [0 0 0  4 0 0  0 1 0  3 3 0] "integer indices" [0 1 2  1 3 2]"#,
        r#""blackbody L" 6500"#,
    );
    let faces: Vec<Face> = scene
        .lights()
        .iter()
        .map(|l| match l {
            Light::Area(a) => {
                assert!(a.p.iter().all(|p| p.z.abs() < 1e-5), "not planar: {:?}", a.p);
                vec![a.p]
            }
            _ => panic!("not a triangle"),
        })
        .collect();
    assert_eq!(faces.len(), 8, "two control triangles, each cut in four");
    assert_each_face_emits_the_power("loopsubdiv", &scene, &faces);
}

/// With an image, pbrt-v4 divides by the image's mean luminance as well as the face's area, so
/// a patch whose (u, v) spans the image still emits the power: two patches of areas 1 and 6,
/// each showing a red and a green texel, are measured at u = ⅛ and ⅞ (where each shows one
/// texel alone) and the face's flux is the mean of the two halves.
#[test]
fn each_patch_showing_an_image_emits_the_power() {
    let dir = tmpdir("area-power-image");
    let file = dir.join("rg.exr");
    let mut img = prism::image::Image::new(2, 1, 3);
    img.data = vec![1.0, 0.2, 0.0, 0.0, 1.0, 0.4];
    prism::image::write(&file, &img).unwrap();
    let scene = emitter(
        r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 0  2 0 0  5 0 0  2 2 0  5 2 0]
           "point2 uv" [0 0  1 0  0 1  1 1  0 0  1 0  0 1  1 1] "integer indices" [0 1 2 3  4 5 6 7]"#,
        &format!(r#""string filename" "{}""#, file.display()),
    );
    let expected = POWER * lumens_per_unit_y() as f64;
    for (i, (x0, width, height)) in [(0.0f32, 1.0f32, 1.0f32), (2.0, 3.0, 2.0)].into_iter().enumerate() {
        let half = |u: f32| luminance(&scene, v(x0 + u * width, 0.5 * height), 10 * i as u64 + (u * 8.0) as u64);
        let (red, green) = (half(0.125), half(0.875));
        assert!(red.mean > 0.0 && green.mean > 0.0 && (red.mean - green.mean).abs() > 0.1 * red.mean);
        let w = 2.0 * std::f64::consts::PI * (width * height) as f64 / 2.0;
        let phi = w * (red.mean + green.mean);
        let err = w * (red.std_err.powi(2) + green.std_err.powi(2)).sqrt();
        assert!(
            (phi - expected).abs() <= 4.0 * err + 1e-4 * expected,
            "patch {i}: {phi} ± {err} lm, expected {expected}"
        );
    }
}
