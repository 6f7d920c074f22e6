//! The built-in default scene: the Cornell box with the dimensions, camera and spectra measured at
//! the Cornell Program of Computer Graphics ("Cornell Box Data",
//! www.graphics.cornell.edu/online/box/data.html). Units are millimetres; reflectances are
//! measured at 400–700 nm every 4 nm and held constant beyond the measured range; the light's
//! spectrum is given at 400/500/600/700 nm and is zero outside it.

use super::SceneBuilder;
use crate::geometry::Mesh;
use crate::material::Material;
use crate::spectrum::Spectrum;
use glam::{Mat4, Vec3};

const REFL_START: f32 = 400.0;
const REFL_STEP: f32 = 4.0;

const WHITE: [f32; 76] = [
    0.343, 0.445, 0.551, 0.624, 0.665, 0.687, 0.708, 0.723, 0.715, 0.710, 0.745, 0.758, 0.739, 0.767, 0.777, 0.765,
    0.751, 0.745, 0.748, 0.729, 0.745, 0.757, 0.753, 0.750, 0.746, 0.747, 0.735, 0.732, 0.739, 0.734, 0.725, 0.721,
    0.733, 0.725, 0.732, 0.743, 0.744, 0.748, 0.728, 0.716, 0.733, 0.726, 0.713, 0.740, 0.754, 0.764, 0.752, 0.736,
    0.734, 0.741, 0.740, 0.732, 0.745, 0.755, 0.751, 0.744, 0.731, 0.733, 0.744, 0.731, 0.712, 0.708, 0.729, 0.730,
    0.727, 0.707, 0.703, 0.729, 0.750, 0.760, 0.751, 0.739, 0.724, 0.730, 0.740, 0.737,
];
const GREEN: [f32; 76] = [
    0.092, 0.096, 0.098, 0.097, 0.098, 0.095, 0.095, 0.097, 0.095, 0.094, 0.097, 0.098, 0.096, 0.101, 0.103, 0.104,
    0.107, 0.109, 0.112, 0.115, 0.125, 0.140, 0.160, 0.187, 0.229, 0.285, 0.343, 0.390, 0.435, 0.464, 0.472, 0.476,
    0.481, 0.462, 0.447, 0.441, 0.426, 0.406, 0.373, 0.347, 0.337, 0.314, 0.285, 0.277, 0.266, 0.250, 0.230, 0.207,
    0.186, 0.171, 0.160, 0.148, 0.141, 0.136, 0.130, 0.126, 0.123, 0.121, 0.122, 0.119, 0.114, 0.115, 0.117, 0.117,
    0.118, 0.120, 0.122, 0.128, 0.132, 0.139, 0.144, 0.146, 0.150, 0.152, 0.157, 0.159,
];
const RED: [f32; 76] = [
    0.040, 0.046, 0.048, 0.053, 0.049, 0.050, 0.053, 0.055, 0.057, 0.056, 0.059, 0.057, 0.061, 0.061, 0.060, 0.062,
    0.062, 0.062, 0.061, 0.062, 0.060, 0.059, 0.057, 0.058, 0.058, 0.058, 0.056, 0.055, 0.056, 0.059, 0.057, 0.055,
    0.059, 0.059, 0.058, 0.059, 0.061, 0.061, 0.063, 0.063, 0.067, 0.068, 0.072, 0.080, 0.090, 0.099, 0.124, 0.154,
    0.192, 0.255, 0.287, 0.349, 0.402, 0.443, 0.487, 0.513, 0.558, 0.584, 0.620, 0.606, 0.609, 0.651, 0.612, 0.610,
    0.650, 0.638, 0.627, 0.620, 0.630, 0.628, 0.642, 0.639, 0.657, 0.639, 0.635, 0.642,
];
/// Light emission at 400, 500, 600, 700 nm (relative; scaled to radiance by `LIGHT_SCALE`).
const LIGHT: [(f32, f32); 4] = [(400.0, 0.0), (500.0, 8.0), (600.0, 15.6), (700.0, 18.4)];
/// Radiance of the light per unit of the measured emission values [W/(sr·m²·nm)].
const LIGHT_SCALE: f32 = 1.0;

/// Reflectance measured on the 4 nm grid, extended flat to 360–830 nm.
fn measured_reflectance(values: &[f32; 76]) -> Spectrum {
    let mut l = vec![360.0];
    let mut v = vec![values[0]];
    for (i, &x) in values.iter().enumerate() {
        l.push(REFL_START + REFL_STEP * i as f32);
        v.push(x);
    }
    l.push(830.0);
    v.push(values[75]);
    Spectrum::piecewise_linear(&l, &v).expect("the measured table is sorted")
}

fn quads(quads: &[[[f32; 3]; 4]]) -> Mesh {
    let mut m = Mesh::default();
    for q in quads {
        let base = m.positions.len() as u32;
        m.positions.extend(q.iter().map(|p| Vec3::from_array(*p)));
        m.indices.push([base, base + 1, base + 2]);
        m.indices.push([base, base + 2, base + 3]);
    }
    m
}

/// Adds the Cornell box to `b` and sets its camera (35 mm focal length, 25 mm sensor).
pub fn add_cornell_box(b: &mut SceneBuilder) {
    let white = b.add_material(Material::diffuse(measured_reflectance(&WHITE)));
    let red = b.add_material(Material::diffuse(measured_reflectance(&RED)));
    let green = b.add_material(Material::diffuse(measured_reflectance(&GREEN)));
    let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));

    // Floor, ceiling, back wall (white).
    b.add_mesh(
        quads(&[
            [[552.8, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 559.2], [549.6, 0.0, 559.2]],
            [[556.0, 548.8, 0.0], [556.0, 548.8, 559.2], [0.0, 548.8, 559.2], [0.0, 548.8, 0.0]],
            [[549.6, 0.0, 559.2], [0.0, 0.0, 559.2], [0.0, 548.8, 559.2], [556.0, 548.8, 559.2]],
        ]),
        white,
        None,
    );
    // Right wall (green) and left wall (red), as seen from the camera.
    b.add_mesh(quads(&[[[0.0, 0.0, 559.2], [0.0, 0.0, 0.0], [0.0, 548.8, 0.0], [0.0, 548.8, 559.2]]]), green, None);
    b.add_mesh(
        quads(&[[[552.8, 0.0, 0.0], [549.6, 0.0, 559.2], [556.0, 548.8, 559.2], [556.0, 548.8, 0.0]]]),
        red,
        None,
    );
    // Short and tall blocks.
    b.add_mesh(
        quads(&[
            [[130.0, 165.0, 65.0], [82.0, 165.0, 225.0], [240.0, 165.0, 272.0], [290.0, 165.0, 114.0]],
            [[290.0, 0.0, 114.0], [290.0, 165.0, 114.0], [240.0, 165.0, 272.0], [240.0, 0.0, 272.0]],
            [[130.0, 0.0, 65.0], [130.0, 165.0, 65.0], [290.0, 165.0, 114.0], [290.0, 0.0, 114.0]],
            [[82.0, 0.0, 225.0], [82.0, 165.0, 225.0], [130.0, 165.0, 65.0], [130.0, 0.0, 65.0]],
            [[240.0, 0.0, 272.0], [240.0, 165.0, 272.0], [82.0, 165.0, 225.0], [82.0, 0.0, 225.0]],
        ]),
        white,
        None,
    );
    b.add_mesh(
        quads(&[
            [[423.0, 330.0, 247.0], [265.0, 330.0, 296.0], [314.0, 330.0, 456.0], [472.0, 330.0, 406.0]],
            [[423.0, 0.0, 247.0], [423.0, 330.0, 247.0], [472.0, 330.0, 406.0], [472.0, 0.0, 406.0]],
            [[472.0, 0.0, 406.0], [472.0, 330.0, 406.0], [314.0, 330.0, 456.0], [314.0, 0.0, 456.0]],
            [[314.0, 0.0, 456.0], [314.0, 330.0, 456.0], [265.0, 330.0, 296.0], [265.0, 0.0, 296.0]],
            [[265.0, 0.0, 296.0], [265.0, 330.0, 296.0], [423.0, 330.0, 247.0], [423.0, 0.0, 247.0]],
        ]),
        white,
        None,
    );
    // The light: measured at y = 548.8 (the ceiling's height); lowered 0.1 mm so the two
    // coplanar surfaces do not fight. Faces down; its surface is black.
    let (ll, lv): (Vec<f32>, Vec<f32>) = LIGHT.iter().copied().unzip();
    let light = Spectrum::piecewise_linear(&ll, &lv).expect("the measured table is sorted");
    b.add_mesh(
        quads(&[[[343.0, 548.7, 227.0], [343.0, 548.7, 332.0], [213.0, 548.7, 332.0], [213.0, 548.7, 227.0]]]),
        black,
        Some(super::Emission { spectrum: light, scale: LIGHT_SCALE, two_sided: false }),
    );

    // Camera at (278, 273, -800) looking along +z; focal length 35 mm, sensor 25 mm × 25 mm:
    // fov = 2 atan(12.5 / 35) = 39.3077°.
    let fov = 2.0 * (12.5f32 / 35.0).atan().to_degrees();
    // The data is right-handed while pbrt-style camera space is left-handed: mirror x so the red
    // wall appears on the left, as in Cornell's photographs.
    let cam = crate::camera::Camera::look_at(Vec3::new(278.0, 273.0, -800.0), Vec3::new(278.0, 273.0, 0.0), Vec3::Y)
        * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    b.set_camera(cam, fov);
}
