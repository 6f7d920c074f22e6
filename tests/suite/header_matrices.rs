//! pbrt-v4's `worldToCamera` and `worldToNDC` OpenEXR attributes: for a known LookAt and field
//! of view, the matrices read back with the `exr` crate equal the ones derived here by hand.

use crate::common::{prism, stderr, tmpdir};
use std::path::Path;

/// The layer's `worldToCamera` and `worldToNDC` (16 floats, row by row) of an OpenEXR file.
fn matrices(path: &Path) -> (Option<[f32; 16]>, Option<[f32; 16]>) {
    let meta = exr::meta::MetaData::read_from_file(path, false).unwrap();
    let a = &meta.headers[0].own_attributes;
    (a.world_to_camera, a.world_to_normalized_device)
}

/// Renders a camera at (1, 2, 3) looking at (4, 2, 7) with up +y and a 40° field of view, on a
/// 40 × 20 film with extra Film parameters `film`, to an OpenEXR; its matrices.
fn render(dir: &Path, name: &str, camera: &str, film: &str) -> (Option<[f32; 16]>, Option<[f32; 16]>) {
    let text = format!(
        "LookAt 1 2 3  4 2 7  0 1 0\n\
         {camera}\n\
         Sampler \"independent\" \"integer pixelsamples\" 1\n\
         Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 20 {film}\n\
         WorldBegin\n\
         LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
    );
    let file = dir.join(format!("{name}.pbrt"));
    std::fs::write(&file, text).unwrap();
    let out = dir.join(format!("{name}.exr"));
    let o = prism().arg("render").arg(&file).arg("-o").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    matrices(&out)
}

fn close(a: &[f32; 16], b: &[f64; 16]) -> bool {
    a.iter().zip(b).all(|(&x, &y)| (x as f64 - y).abs() <= 1e-5 * y.abs().max(1.0))
}

/// x · M for the 4×4 matrix `m` given row by row, applied to the column vector `p`.
fn apply(m: &[f32; 16], p: [f64; 4]) -> [f64; 4] {
    std::array::from_fn(|r| (0..4).map(|c| m[4 * r + c] as f64 * p[c]).sum())
}

#[test]
fn world_to_camera_and_ndc_are_pbrt_v4s() {
    let dir = tmpdir("header-matrices");
    // The view direction d = (3, 0, 4)/5; pbrt's right = up × d = (0.8, 0, −0.6), its up
    // d × right = (0, 1, 0). Camera from world: rows right, up, d, each with −(row · eye) last.
    let camera_from_world = [
        0.8, 0.0, -0.6, 1.0, // right · (1, 2, 3) = −1
        0.0, 1.0, 0.0, -2.0, // up · eye = 2
        0.6, 0.0, 0.8, -3.0, // d · eye = 3
        0.0, 0.0, 0.0, 1.0,
    ];
    // NDC from camera: Translate(½)·Scale(½)·Perspective(40°, 0.01, 1000): x and y scaled by
    // ½/tan 20° plus ½ z (w = z), z by ½·f/(f − n) + ½ minus ½·f·n/(f − n).
    let (n, f) = (0.01f64, 1000.0f64);
    let a = 0.5 / 20f64.to_radians().tan();
    let ndc_from_camera = [
        [a, 0.0, 0.5, 0.0],
        [0.0, a, 0.5, 0.0],
        [0.0, 0.0, 0.5 * f / (f - n) + 0.5, -0.5 * f * n / (f - n)],
        [0.0, 0.0, 1.0, 0.0],
    ];
    let ndc_from_world: [f64; 16] =
        std::array::from_fn(|i| (0..4).map(|k| ndc_from_camera[i / 4][k] * camera_from_world[4 * k + i % 4]).sum());

    let plain = render(&dir, "perspective", "Camera \"perspective\" \"float fov\" 40", "");
    let (Some(wc), Some(ndc)) = plain else { panic!("no matrices: {plain:?}") };
    assert!(close(&wc, &camera_from_world), "worldToCamera {wc:?}");
    assert!(close(&ndc, &ndc_from_world), "worldToNDC {ndc:?}");
    // What they mean: the target lies 5 ahead on the axis, in the middle of NDC; a point 20°
    // above the axis (the shorter, vertical half-angle of this 40 × 20 film) is at NDC y = 1.
    let p = apply(&wc, [4.0, 2.0, 7.0, 1.0]);
    assert!(p[0].abs() < 1e-5 && p[1].abs() < 1e-5 && (p[2] - 5.0).abs() < 1e-5, "{p:?}");
    let q = apply(&ndc, [4.0, 2.0 + 5.0 * 20f64.to_radians().tan(), 7.0, 1.0]);
    assert!((q[0] / q[3] - 0.5).abs() < 1e-5 && (q[1] / q[3] - 1.0).abs() < 1e-5, "{q:?}");

    // A crop and a screen window leave them as they are (pbrt-v4 records the camera's).
    let cropped = render(
        &dir,
        "cropped",
        "Camera \"perspective\" \"float fov\" 40 \"float screenwindow\" [-1 1 -0.5 0.5]",
        "\"float cropwindow\" [0.25 0.75 0 0.5]",
    );
    assert_eq!(cropped, plain);
    // Orthographic: NDC is ½ + ½ camera x, y, z; a spherical camera records no NDC.
    let (Some(wc), Some(ndc)) = render(&dir, "ortho", "Camera \"orthographic\"", "") else { panic!("no matrices") };
    let ortho: [f64; 16] = std::array::from_fn(|i| {
        let (r, c) = (i / 4, i % 4);
        if r == 3 {
            camera_from_world[i]
        } else {
            0.5 * camera_from_world[i] + if c == 3 { 0.5 } else { 0.0 }
        }
    });
    assert!(close(&wc, &camera_from_world) && close(&ndc, &ortho), "orthographic {ndc:?}");
    let (wc, ndc) = render(&dir, "spherical", "Camera \"spherical\"", "");
    assert!(wc.is_some_and(|m| close(&m, &camera_from_world)) && ndc.is_none(), "spherical {wc:?} {ndc:?}");
}
