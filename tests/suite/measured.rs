//! pbrt-v4's `measured` material end to end: `.bsdf` files tabulated from an analytic GGX
//! conductor (`prism::bsdf::measured::tabulate`) read by scene files, shared between the
//! materials that name them, refused with their location when malformed, and rendered beside
//! the analytic conductor they were made from.

use crate::common::{film, prism, stderr, tmpdir};
use prism::accel::AccelKind;
use prism::bsdf::measured::tabulate::{tabulate, GgxConductor, Grid};
use prism::material::Material;
use prism::pbrt::{self, parse_str, ParseOptions};
use std::path::Path;

/// The unit tests' conductor (src/bsdf/tests/measured.rs): α = 0.3, η and k linear in λ.
const CONDUCTOR: GgxConductor = GgxConductor { alpha: 0.3, eta: (1.5, 0.15), k: (1.8, 5.0) };
/// The tabulation's relative error of f, as a bias of the image: twice the RMS bound of the
/// unit tests (0.005 up to 80°), for the silhouette's grazing angles that bound does not cover.
const TABULATION_RMS: f64 = 0.01;

fn write_conductor(path: &Path) {
    let t = tabulate(&CONDUCTOR, &Grid::regular(16, 10.0, 64, 32), "GGX conductor α = 0.3");
    std::fs::write(path, t.to_bytes()).unwrap();
}

fn materials(text: &str) -> Result<Vec<Material>, String> {
    let (d, mut w) = parse_str(text, &ParseOptions::default()).map_err(|e| e.to_string())?;
    let (b, _) = pbrt::build(&d, &mut w).map_err(|e| e.to_string())?;
    assert!(w.is_empty(), "{w:?}");
    Ok(b.build(AccelKind::Obvhs).unwrap().materials().to_vec())
}

#[test]
fn a_bsdf_file_named_twice_is_read_once_and_bad_files_are_errors_at_their_parameter() {
    let d = tmpdir("measured-files");
    let file = d.join("c.bsdf");
    write_conductor(&file);
    let f = file.display();
    let sphere = "Shape \"sphere\"";
    let text = format!(
        "WorldBegin\nMaterial \"measured\" \"string filename\" \"{f}\"\n{sphere}\n\
         AttributeBegin\nMaterial \"measured\" \"string filename\" \"{f}\"\n{sphere}\nAttributeEnd\n"
    );
    let m = materials(&text).unwrap();
    let [Material::Measured(a), Material::Measured(b)] = &m[..] else { panic!("{m:?}") };
    assert!(std::sync::Arc::ptr_eq(a, b), "the file was read twice");

    let missing =
        materials("WorldBegin\nMaterial \"measured\" \"string filename\" \"/no/such.bsdf\"\nShape \"sphere\"");
    let missing = missing.unwrap_err();
    assert!(missing.starts_with("<string>:2:21: cannot read \"/no/such.bsdf\""), "{missing}");
    let none = materials("WorldBegin\nMaterial \"measured\"\nShape \"sphere\"").unwrap_err();
    assert!(none.contains("needs a \"string filename\""), "{none}");

    let mut bytes = std::fs::read(&file).unwrap();
    bytes.truncate(bytes.len() - 7);
    let short = d.join("short.bsdf");
    std::fs::write(&short, &bytes).unwrap();
    let text = format!("WorldBegin\nMaterial \"measured\" \"string filename\" \"{}\"\n{sphere}", short.display());
    let e = materials(&text);
    let e = e.unwrap_err();
    assert!(e.starts_with("<string>:2:21: ") && e.contains("short.bsdf: truncated"), "{e}");
}

/// The scene: the measured sphere on the left, the analytic one mirrored on the right, under a
/// uniform sky and a distant light in the mirror plane; one bounce, so neither sees the other.
fn scene(spp: u32) -> String {
    format!(
        r#"Film "rgb" "integer xresolution" 96 "integer yresolution" 48
LookAt 0 0 6  0 0 0  0 1 0
Camera "perspective" "float fov" 30
Sampler "independent" "integer pixelsamples" {spp}
Integrator "path" "integer maxdepth" 1
WorldBegin
LightSource "infinite" "rgb L" [0.5 0.5 0.5]
LightSource "distant" "point3 from" [0 1 1] "point3 to" [0 0 0] "rgb L" [3 3 3]
AttributeBegin
  Translate -1.1 0 0
  Material "measured" "string filename" "conductor.bsdf"
  Shape "sphere" "float radius" 1
AttributeEnd
AttributeBegin
  Translate 1.1 0 0
  Material "conductor" "spectrum eta" [360 1.5 830 0.15] "spectrum k" [360 1.8 830 5]
    "float roughness" 0.3 "bool remaproughness" false
  Shape "sphere" "float radius" 1
AttributeEnd
"#
    )
}

#[test]
fn measured_sphere_renders_as_the_analytic_conductor_it_tabulates() {
    let d = tmpdir("measured-render");
    write_conductor(&d.join("conductor.bsdf"));
    let path = d.join("spheres.pbrt");
    std::fs::write(&path, scene(64)).unwrap();
    let out = d.join("spheres.film");
    let o = prism().arg("render").arg(&path).args(["--threads", "2", "--seed", "3", "-o"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let film = film(&out);
    // Each left pixel against its mirror image: independent estimates, so the mean difference
    // has the standard error of the differences over √n.
    let y = |x: u32, yy: u32| {
        let p = &film.pixels[(yy * film.width + x) as usize];
        p.xyz_sum.y / p.weight_sum
    };
    let (mut d_sum, mut d2, mut y_sum, mut n) = (0.0, 0.0, 0.0, 0.0);
    for yy in 0..film.height {
        for x in 0..film.width / 2 {
            let (a, b) = (y(x, yy), y(film.width - 1 - x, yy));
            d_sum += a - b;
            d2 += (a - b) * (a - b);
            y_sum += b;
            n += 1.0;
        }
    }
    let mean = d_sum / n;
    let se = ((d2 / n - mean * mean) / (n - 1.0)).sqrt();
    let mean_y = y_sum / n;
    eprintln!("measured − analytic: {mean:.5} ± {se:.5} (mean Y of the analytic half {mean_y:.4})");
    assert!(mean_y > 0.05, "the spheres are dark: {mean_y}");
    // 4 standard errors plus the tabulation's error of f, which is a bias, not noise.
    assert!(mean.abs() <= 4.0 * se + TABULATION_RMS * mean_y, "{mean} ± {se} of {mean_y}");
}
