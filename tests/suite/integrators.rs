//! The one integrator interface end to end: every command takes the integrator the scene needs,
//! and Russian roulette ends every path of the volumetric loop too.

use crate::common::{film, prism, stderr, tmpdir, wait_within};
use std::path::Path;
use std::process::Stdio;
use std::time::Duration;

/// A closed white sphere (reflectance 1, normals inward) filled with a purely scattering medium,
/// a point light and the camera inside, no depth limit: every scattering keeps the throughput at
/// 1, so only a survival probability below 1 (the 0.95 cap) ends its paths.
const WHITE_FURNACE: &str = r#"
LookAt 0 0 0  0 0 1  0 1 0
MakeNamedMedium "fog" "string type" "homogeneous"
    "spectrum sigma_a" [300 0 900 0] "spectrum sigma_s" [300 0.5 900 0.5]
MediumInterface "fog" "fog"
Camera "perspective" "float fov" [60]
Film "rgb" "integer xresolution" [8] "integer yresolution" [8] "string filename" "furnace.exr"
Sampler "independent" "integer pixelsamples" [1]
Integrator "volpath" "integer maxdepth" [-1]
WorldBegin
LightSource "point" "point3 from" [0 1 2] "spectrum I" [300 1 900 1]
AttributeBegin
  MediumInterface "fog" "fog"
  ReverseOrientation
  Material "diffuse" "spectrum reflectance" [300 1 900 1]
  Shape "sphere" "float radius" [5]
AttributeEnd
"#;

#[test]
fn an_unbounded_volumetric_path_in_a_closed_white_scattering_sphere_ends() {
    let dir = tmpdir("white-furnace");
    let scene = dir.join("furnace.pbrt");
    std::fs::write(&scene, WHITE_FURNACE).unwrap();
    let out = dir.join("furnace.film");
    let mut child = prism()
        .args(["render", scene.to_str().unwrap(), "--threads", "1", "-o", out.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status = wait_within(&mut child, Duration::from_secs(60))
        .expect("an 8x8, 1 spp render did not end in 60 s: some path never ends");
    assert!(status.success());
    let f = film(&out);
    let lit = f.pixels.iter().filter(|p| p.xyz_sum.y > 0.0).count();
    assert!(lit > 0, "the furnace is black");
}

/// An emitter of constant radiance two units in front of the camera, through a purely absorbing
/// medium of σ_a = `sigma_a` that fills the camera's side.
fn absorbing_scene(sigma_a: f32) -> String {
    format!(
        r#"
LookAt 0 0 0  0 0 1  0 1 0
MakeNamedMedium "smoke" "string type" "homogeneous"
    "spectrum sigma_a" [300 {sigma_a} 900 {sigma_a}] "spectrum sigma_s" [300 0 900 0]
MediumInterface "" "smoke"
Camera "perspective" "float fov" [4]
Film "rgb" "integer xresolution" [4] "integer yresolution" [4] "string filename" "smoke.exr"
Sampler "independent" "integer pixelsamples" [256]
PixelFilter "box"
WorldBegin
AttributeBegin
  MediumInterface "" "smoke"
  AreaLightSource "diffuse" "spectrum L" [300 1 900 1] "bool twosided" true
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
      "point3 P" [-50 -50 2  50 -50 2  50 50 2  -50 50 2]
AttributeEnd
"#
    )
}

/// Luminance [cd/m²] and its standard error, as `prism measure radiance --json` prints them.
fn measured_luminance(scene: &Path) -> (f64, f64) {
    let o = prism()
        .args(["measure", "radiance", scene.to_str().unwrap(), "--at", "0,0,0", "--dir", "0,0,-1"])
        .args(["--samples", "20000", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    (v["luminance"]["mean"].as_f64().unwrap(), v["luminance"]["std_err"].as_f64().unwrap())
}

/// Mean Y over the film's pixels and its standard error (pixels are independent estimates).
fn rendered_y(scene: &Path, out: &Path) -> (f64, f64) {
    let o = prism().args(["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let y: Vec<f64> = film(out).pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect();
    let n = y.len() as f64;
    let m = y.iter().sum::<f64>() / n;
    (m, (y.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0) / n).sqrt())
}

/// Radiance seen through σ_a d = 1 of absorber is e⁻¹ of the clear view (Beer–Lambert), by the
/// measuring instrument as by the render: both take the integrator the scene's media need.
#[test]
fn measure_and_render_both_see_the_medium() {
    let dir = tmpdir("measure-medium");
    let (clear, smoke) = (dir.join("clear.pbrt"), dir.join("smoke.pbrt"));
    std::fs::write(&clear, absorbing_scene(0.0)).unwrap();
    std::fs::write(&smoke, absorbing_scene(0.5)).unwrap();
    let expected = (-1.0f64).exp();
    let ratio = |(a, sa): (f64, f64), (b, sb): (f64, f64)| {
        assert!(a > 0.0 && b > 0.0, "black: {a} {b}");
        let r = a / b;
        (r, r * ((sa / a).powi(2) + (sb / b).powi(2)).sqrt())
    };
    let (m, m_se) = ratio(measured_luminance(&smoke), measured_luminance(&clear));
    let (r, r_se) = ratio(rendered_y(&smoke, &dir.join("smoke.film")), rendered_y(&clear, &dir.join("clear.film")));
    eprintln!("transmittance e^-1 = {expected:.4}: measured {m:.4} ± {m_se:.4}, rendered {r:.4} ± {r_se:.4}");
    assert!((m - expected).abs() < 4.0 * m_se, "measure: {m} ± {m_se}, expected {expected}");
    // The pixels' rays are at most 2.8° off the axis: their path through the absorber is
    // longer by at most 0.12%, well inside the noise.
    assert!((r - expected).abs() < 4.0 * r_se, "render: {r} ± {r_se}, expected {expected}");
}
