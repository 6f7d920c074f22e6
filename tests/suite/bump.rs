//! Bump and normal maps as the renderer applies them: a white diffuse square facing the camera,
//! lit by a distant light from 45° to one side, direct light only. A flat square reflects
//! L ∝ n·l; a perturbed one L ∝ n′·l, so the ratio of the two images' means is n′·l / n·l,
//! which is worked out here from the height field or the map's texel alone.

use crate::common::{pbrt_scene, test_settings, tmpdir};
use prism::accel::AccelKind;
use prism::render::render;

/// The mean luminance Y of the square seen by an orthographic camera that it fills, and its
/// standard error over the pixels.
fn mean_y(material: &str, light_x: f32) -> (f64, f64) {
    let text = format!(
        r#"
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -0.9 0.9 -0.9 0.9 ]
WorldBegin
LightSource "distant" "point3 from" [ {light_x} 0 1 ] "point3 to" [ 0 0 0 ] "rgb L" [ 1 1 1 ]
{material}
Shape "trianglemesh" "point3 P" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]
  "point2 uv" [ 0 0  1 0  1 1  0 1 ] "integer indices" [ 0 1 2  0 2 3 ]
"#
    );
    let scene = pbrt_scene(&text, AccelKind::Obvhs);
    let (film, _) = render(&scene, &test_settings((16, 16), 16, 7, 1), |_| {}).unwrap();
    let ys: Vec<f64> = film.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect();
    let n = ys.len() as f64;
    let mean = ys.iter().sum::<f64>() / n;
    let var = ys.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (n - 1.0);
    assert!(mean > 0.01, "the square is black: {mean}");
    (mean, (var / n).sqrt())
}

fn assert_ratio(bumped: (f64, f64), flat: (f64, f64), want: f64, what: &str) {
    let got = bumped.0 / flat.0;
    let se = got * ((bumped.1 / bumped.0).powi(2) + (flat.1 / flat.0).powi(2)).sqrt();
    assert!((got - want).abs() <= 4.0 * se + 1e-3, "{what}: ratio {got:.4} ± {se:.4}, want {want:.4}");
}

const FLAT: &str = r#"Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]"#;

/// h(u, v) = a u on a square 2 wide in x over u ∈ [0, 1]: the surface rises by a/2 per unit x,
/// so n′ = (−a/2, 0, 1)/√(1 + a²/4). With l = (±1, 0, 1)/√2, n′·l / n·l = (1 ∓ a/2)/√(1 + a²/4):
/// dimmer lit from +x (the slope faces away), brighter from −x.
#[test]
fn a_sloped_displacement_tilts_the_shading_normal_the_way_the_height_rises() {
    let a = 1.0f64;
    let bumped = r#"Texture "h" "float" "bilerp" "float v00" [ 0 ] "float v10" [ 1 ] "float v01" [ 0 ] "float v11" [ 1 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ] "texture displacement" "h""#;
    let norm = (1.0 + a * a / 4.0).sqrt();
    for (light_x, want) in [(1.0, (1.0 - a / 2.0) / norm), (-1.0, (1.0 + a / 2.0) / norm)] {
        assert_ratio(mean_y(bumped, light_x), mean_y(FLAT, light_x), want, &format!("light from x = {light_x}"));
    }
}

/// A one-texel map (0.8, 0.5, 0.9) encodes the tangent-space normal (0.6, 0, 0.8); the frame is
/// (∂p/∂u, n × ∂p/∂u, n) = (x, y, z), so n′ = (0.6, 0, 0.8) and n′·l / n·l = 0.8 ∓ 0.6.
#[test]
fn a_normal_map_texel_sets_the_shading_normal_in_the_tangent_frame() {
    let dir = tmpdir("normal-map");
    let path = dir.join("n.exr");
    let img = prism::image::Image { width: 1, height: 1, channels: 3, data: vec![0.8, 0.5, 0.9] };
    prism::image::write(&path, &img).unwrap();
    let mapped =
        format!(r#"Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ] "string normalmap" "{}""#, path.display());
    for (light_x, want) in [(1.0, 0.8 + 0.6), (-1.0, 0.8 - 0.6)] {
        assert_ratio(mean_y(&mapped, light_x), mean_y(FLAT, light_x), want, &format!("light from x = {light_x}"));
    }
}
