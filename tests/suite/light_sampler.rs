//! The BVH light sampler against the power sampler on a scene of many small emitters of
//! different power: the same irradiance at floor points (both are unbiased), and less noise from
//! the BVH, which weighs each emitter by its importance at the point.

use crate::common::pbrt_scene;
use glam::Vec3;
use prism::accel::AccelKind;
use prism::integrator::{DirectStrategy, Integrator};
use prism::measure::irradiance;

/// A 6 × 6 grid of small downward-facing emitters at height 1 over a floor, their radiance
/// growing across the grid, with `lightsampler` `kind`.
fn scene(kind: &str) -> String {
    let mut s = format!("Integrator \"path\" \"string lightsampler\" \"{kind}\"\nCamera \"perspective\" WorldBegin\n");
    for i in 0..6 {
        for j in 0..6 {
            let (x, y, h) = (-2.5 + i as f32, -2.5 + j as f32, 0.05);
            let l = 1.0 + 3.0 * (i * 6 + j) as f32;
            s += &format!(
                "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [ {l} {l} {l} ]\n\
                 Shape \"trianglemesh\" \"point3 P\" [ {} {} 1  {} {} 1  {} {} 1  {} {} 1 ] \"integer indices\" [ 0 2 1 0 3 2 ]\nAttributeEnd\n",
                x - h, y - h, x + h, y - h, x + h, y + h, x - h, y + h
            );
        }
    }
    s + "Material \"diffuse\"\nShape \"trianglemesh\" \"point3 P\" [ -4 -4 0  4 -4 0  4 4 0  -4 4 0 ] \"integer indices\" [ 0 1 2 0 2 3 ]\n"
}

#[test]
fn bvh_and_power_sampling_give_the_same_irradiance_and_the_bvh_less_noise() {
    let (bvh, power) = (pbrt_scene(&scene("bvh"), AccelKind::Obvhs), pbrt_scene(&scene("power"), AccelKind::Obvhs));
    let integ = Integrator { max_depth: 1, strategy: DirectStrategy::LightOnly, ..Default::default() };
    for p in [Vec3::new(0.0, 0.0, 0.001), Vec3::new(-2.2, 1.7, 0.001), Vec3::new(2.5, -2.5, 0.001)] {
        let a = irradiance(&bvh, &integ, p, Vec3::Z, 40_000, 4).illuminance;
        let b = irradiance(&power, &integ, p, Vec3::Z, 40_000, 5).illuminance;
        assert!(a.mean > 0.0 && b.mean > 0.0);
        let sigma = (a.std_err.powi(2) + b.std_err.powi(2)).sqrt();
        assert!(
            (a.mean - b.mean).abs() <= 4.0 * sigma,
            "at {p}: bvh {} ± {}, power {} ± {}",
            a.mean,
            a.std_err,
            b.mean,
            b.std_err
        );
        assert!(a.std_err < 0.7 * b.std_err, "at {p}: bvh ± {} against power ± {}", a.std_err, b.std_err);
    }
}
