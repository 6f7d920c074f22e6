//! The estimators that start paths at the lights (`lightpath`, `bdpt`, `mlt`) in participating
//! media, against the volumetric path tracer: a fog sphere seen from outside and lit by an area
//! light, a camera and a point light inside unbounded fog, and a heterogeneous (grid) medium lit
//! by a spotlight. Per block of the image, and over the whole image, the mean over independent
//! renders (seeds) and its standard error are measured; the two estimators must agree within 4
//! standard errors of their difference.

use crate::bidirectional::block_means;
use crate::common::pbrt_scene;
use prism::accel::AccelKind;
use prism::integrator::IntegratorKind;
use prism::scene::Scene;

/// A floor under a sphere of coloured, forward-scattering fog (an interface surface, no BSDF),
/// lit by a small area light above it, facing down; the camera outside.
const FOG_SPHERE: &str = r#"
LookAt 0 1.2 4  0 0.6 0  0 1 0
Camera "perspective" "float fov" [45]
WorldBegin
MakeNamedMedium "fog" "string type" "homogeneous"
    "rgb sigma_a" [0.1 0.2 0.4] "rgb sigma_s" [1.5 1.0 0.6] "float g" 0.4
AttributeBegin
  AreaLightSource "diffuse" "spectrum L" [300 8 900 8]
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
      "point3 P" [-0.5 2.2 -0.5  0.5 2.2 -0.5  0.5 2.2 0.5  -0.5 2.2 0.5]
AttributeEnd
Material "diffuse" "spectrum reflectance" [300 0.5 900 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-3 0 -3  -3 0 3  3 0 3  3 0 -3]
AttributeBegin
  MediumInterface "fog" ""
  Material "interface"
  Translate 0 0.8 0
  Shape "sphere" "float radius" [0.8]
AttributeEnd
"#;

/// Fog everywhere (the camera's medium and the point light's), over a floor and a back wall.
const CAMERA_IN_FOG: &str = r#"
LookAt 0 1 3  0 0.7 0  0 1 0
MakeNamedMedium "fog" "string type" "homogeneous"
    "spectrum sigma_a" [300 0.05 900 0.05] "spectrum sigma_s" [300 0.3 900 0.3] "float g" -0.3
MediumInterface "fog" "fog"
Camera "perspective" "float fov" [50]
WorldBegin
MediumInterface "fog" "fog"
LightSource "point" "point3 from" [0.3 1.6 0.5] "spectrum I" [300 4 900 4]
Material "diffuse" "spectrum reflectance" [300 0.6 900 0.6]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-3 0 -3  -3 0 3  3 0 3  3 0 -3]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-3 0 -1  3 0 -1  3 3 -1  -3 3 -1]
"#;

/// A density grid in a box of interface surfaces, lit by a spotlight from above, over a floor.
const GRID_BOX: &str = r#"
LookAt 0 1.5 4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [40]
WorldBegin
MakeNamedMedium "smoke" "string type" "uniformgrid"
    "spectrum sigma_a" [300 0.5 900 0.5] "spectrum sigma_s" [300 3 900 3]
    "integer nx" [2] "integer ny" [2] "integer nz" [2]
    "float density" [0.1 1 0.6 0.2  1 0.3 0.05 0.8]
    "point3 p0" [-0.7 0 -0.7] "point3 p1" [0.7 1.4 0.7]
LightSource "spot" "point3 from" [0.4 3 0.4] "point3 to" [0 0 0] "float coneangle" [35]
    "spectrum I" [300 20 900 20]
Material "diffuse" "spectrum reflectance" [300 0.5 900 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-3 0 -3  -3 0 3  3 0 3  3 0 -3]
AttributeBegin
  MediumInterface "smoke" ""
  Material "interface"
  Shape "trianglemesh" "integer indices"
      [0 1 2  0 2 3  4 6 5  4 7 6  0 5 1  0 4 5  3 6 7  3 2 6  0 7 4  0 3 7  1 6 2  1 5 6]
      "point3 P" [-0.7 0.001 -0.7  0.7 0.001 -0.7  0.7 0.001 0.7  -0.7 0.001 0.7
                  -0.7 1.4 -0.7  0.7 1.4 -0.7  0.7 1.4 0.7  -0.7 1.4 0.7]
AttributeEnd
"#;

/// A box of fog on a floor whose lid is a two-sided area light, fog below it and vacuum above,
/// under a diffuse ceiling: light subpaths leave the lid into the fog or into the vacuum by the
/// side they leave from.
const FOG_UNDER_A_TWO_SIDED_LID: &str = r#"
LookAt 0 1.5 4  0 0.9 0  0 1 0
Camera "perspective" "float fov" [55]
WorldBegin
MakeNamedMedium "fog" "string type" "homogeneous"
    "spectrum sigma_a" [300 0.3 900 0.3] "spectrum sigma_s" [300 1.2 900 1.2]
Material "diffuse" "spectrum reflectance" [300 0.5 900 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-3 0 -3  -3 0 3  3 0 3  3 0 -3]
Shape "trianglemesh" "integer indices" [0 2 1 0 3 2]
    "point3 P" [-3 2 -3  -3 2 3  3 2 3  3 2 -3]
AttributeBegin
  MediumInterface "fog" ""
  AreaLightSource "diffuse" "bool twosided" true "spectrum L" [300 3 900 3]
  Shape "trianglemesh" "integer indices" [0 2 1 0 3 2]
      "point3 P" [-0.7 1 -0.7  0.7 1 -0.7  0.7 1 0.7  -0.7 1 0.7]
AttributeEnd
AttributeBegin
  MediumInterface "fog" ""
  Material "interface"
  Shape "trianglemesh" "integer indices" [0 1 2  0 2 3  0 5 1  0 4 5  3 6 7  3 2 6  0 7 4  0 3 7  1 6 2  1 5 6]
      "point3 P" [-0.7 0.001 -0.7  0.7 0.001 -0.7  0.7 0.001 0.7  -0.7 0.001 0.7
                  -0.7 1 -0.7  0.7 1 -0.7  0.7 1 0.7  -0.7 1 0.7]
AttributeEnd
"#;

/// Asserts that `kind` renders `text`'s scene as the volumetric path tracer does, block by
/// block (`spp` of volpath and of `kind`, 8 seeds each).
fn agrees_with_volpath(text: &str, kind: IntegratorKind, spp: (u64, u64), max_depth: u32) {
    let scene: Scene = pbrt_scene(text, AccelKind::Obvhs);
    let reference = block_means(&scene, IntegratorKind::VolPath, spp.0, max_depth, 8);
    let tested = block_means(&scene, kind, spp.1, max_depth, 8);
    assert!(reference.last().unwrap().0 > 1e-3, "the scene is black");
    for (b, ((m0, s0), (m1, s1))) in reference.iter().zip(&tested).enumerate() {
        let sigma = (s0 * s0 + s1 * s1).sqrt();
        assert!(
            (m0 - m1).abs() <= 4.0 * sigma + 1e-6 * m0.abs(),
            "{kind:?}, block {b}: {m1:.5} ± {s1:.5} vs volpath {m0:.5} ± {s0:.5} ({:.1}σ)",
            (m0 - m1).abs() / sigma
        );
    }
}

#[test]
fn bidirectional_path_tracing_renders_a_fog_sphere_under_an_area_light_as_volpath_does() {
    agrees_with_volpath(FOG_SPHERE, IntegratorKind::Bdpt, (32, 16), 5);
}

#[test]
fn light_tracing_renders_a_fog_sphere_under_an_area_light_as_volpath_does() {
    agrees_with_volpath(FOG_SPHERE, IntegratorKind::LightPath, (32, 32), 5);
}

#[test]
fn bidirectional_path_tracing_renders_a_camera_and_a_point_light_in_fog_as_volpath_does() {
    agrees_with_volpath(CAMERA_IN_FOG, IntegratorKind::Bdpt, (32, 16), 5);
}

#[test]
fn light_tracing_renders_a_camera_and_a_point_light_in_fog_as_volpath_does() {
    agrees_with_volpath(CAMERA_IN_FOG, IntegratorKind::LightPath, (32, 32), 5);
}

#[test]
fn bidirectional_path_tracing_renders_a_grid_medium_under_a_spotlight_as_volpath_does() {
    agrees_with_volpath(GRID_BOX, IntegratorKind::Bdpt, (32, 16), 5);
}

#[test]
fn bidirectional_path_tracing_starts_a_two_sided_lights_paths_in_the_medium_of_their_side() {
    agrees_with_volpath(FOG_UNDER_A_TWO_SIDED_LID, IntegratorKind::Bdpt, (32, 16), 5);
}

#[test]
fn light_tracing_starts_a_two_sided_lights_paths_in_the_medium_of_their_side() {
    agrees_with_volpath(FOG_UNDER_A_TWO_SIDED_LID, IntegratorKind::LightPath, (32, 32), 5);
}

#[test]
fn metropolis_light_transport_renders_a_fog_sphere_as_volpath_does() {
    agrees_with_volpath(FOG_SPHERE, IntegratorKind::Mlt, (32, 16), 5);
}

#[test]
fn bidirectional_estimators_say_they_ignore_an_emitting_medium_and_fail_under_strict() {
    // pbrt-v4's bdpt, lightpath and mlt record a medium vertex's scattering alone: an emitting
    // medium's light is lost, which prism reproduces and says, once; under --strict it stops.
    use crate::common::{prism, stderr, tmpdir};
    let dir = tmpdir("bidirectional-emitting-medium");
    let emitting = FOG_SPHERE.replace("\"float g\" 0.4", "\"float g\" 0.4 \"rgb Le\" [1 0.5 0.2]");
    assert_ne!(emitting, FOG_SPHERE);
    for (name, text, warns) in [("plain", FOG_SPHERE.to_string(), false), ("emitting", emitting, true)] {
        for integrator in ["bdpt", "lightpath", "mlt"] {
            let file = dir.join(format!("{name}-{integrator}.pbrt"));
            let film = "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n";
            let text = text.replace("WorldBegin", &format!("{film}Integrator \"{integrator}\"\nWorldBegin"));
            std::fs::write(&file, text).unwrap();
            let run = |strict: bool| {
                let mut c = prism();
                c.arg("render").arg(&file).args(["--spp", "1", "-o"]).arg(dir.join("out.exr"));
                if strict {
                    c.arg("--strict");
                }
                c.output().unwrap()
            };
            let why = "it ignores the emission of participating media";
            let o = run(false);
            assert!(o.status.success(), "{}", stderr(&o));
            assert_eq!(stderr(&o).contains(why), warns, "{name} {integrator}: {}", stderr(&o));
            let o = run(true);
            assert_eq!(o.status.success(), !warns, "{name} {integrator}: {}", stderr(&o));
            if warns {
                let e = stderr(&o);
                assert!(e.contains(&format!("integrator \"{integrator}\" for this scene: {why}")), "{e}");
            }
        }
    }
}
