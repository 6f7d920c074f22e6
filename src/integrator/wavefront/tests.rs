use super::*;
use crate::accel::AccelKind;
use crate::render::{render, RenderSettings, SamplerKind};
use crate::scene::SceneBuilder;

/// Luminance Y of every pixel of the built-in Cornell box, 32² at 16 spp.
fn cornell(kind: AccelKind, wavefront: bool, sampler: SamplerKind, seed: u64) -> Vec<f64> {
    let scene = SceneBuilder::cornell_box().build(kind).unwrap();
    // 33 columns: the last batch of a band is not a whole number of 16-lane vectors.
    let settings = RenderSettings { resolution: (33, 32), spp: 16, sampler, seed, wavefront, ..Default::default() };
    let (film, _) = render(&scene, &settings, |_| {}).unwrap();
    film.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect()
}

fn kinds() -> Vec<AccelKind> {
    let mut kinds = vec![AccelKind::Obvhs];
    if cfg!(embree) {
        kinds.push(AccelKind::Embree);
    }
    kinds
}

/// Each path draws its sampler's dimensions in the scalar loop's order and runs the same
/// physics, so the image equals the scalar one pixel by pixel up to rounding (a lane computes
/// as the scalar code; only a path that a differently rounded direction sent elsewhere could
/// differ, and at these 16,896 paths none does). A loop that lost NEE, MIS, roulette or a
/// path, or mixed up paths, would differ by whole path contributions.
#[test]
fn the_wavefront_loop_renders_the_scalar_image() {
    for kind in kinds() {
        for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
            let scalar = cornell(kind, false, sampler, 0);
            let mean = scalar.iter().sum::<f64>() / scalar.len() as f64;
            assert!(mean > 0.01, "black image: {mean}");
            let wavefront = cornell(kind, true, sampler, 0);
            for (i, (a, b)) in scalar.iter().zip(&wavefront).enumerate() {
                assert!((a - b).abs() <= 1e-5 * mean, "{kind:?} {sampler:?} pixel {i}: {a} vs {b}");
            }
        }
    }
}

/// Against independent noise: the wavefront image of one seed differs from the scalar image of
/// another as two scalar images of different seeds differ. The RMS difference of P pixels is
/// known to a relative standard error of 1/√(2P) (2.2% for 1056 pixels; 4σ allowed), and the
/// mean difference must be within 4 standard errors of zero (σ of a pixel difference over √P).
#[test]
fn the_wavefront_image_is_within_noise_of_the_scalar_one() {
    let kind = *kinds().last().expect("a backend");
    let sampler = SamplerKind::Independent;
    let (a, b, c) =
        (cornell(kind, false, sampler, 1), cornell(kind, false, sampler, 2), cornell(kind, true, sampler, 3));
    let p = a.len() as f64;
    let rms = |x: &[f64], y: &[f64]| (x.iter().zip(y).map(|(u, v)| (u - v).powi(2)).sum::<f64>() / p).sqrt();
    let (noise, against) = (rms(&a, &b), rms(&c, &b));
    assert!((against / noise - 1.0).abs() < 4.0 / (2.0 * p).sqrt(), "RMS {against} vs scalar noise {noise}");
    let mean_diff = c.iter().zip(&b).map(|(u, v)| u - v).sum::<f64>() / p;
    assert!(mean_diff.abs() < 4.0 * noise / p.sqrt(), "mean difference {mean_diff}, noise {noise}");
}

#[test]
fn scenes_outside_the_prototype_are_refused() {
    let scene = SceneBuilder::cornell_box().build(AccelKind::Obvhs).unwrap();
    let path = Integrator::default().for_scene(&scene);
    assert!(check(&scene, &path).is_ok());
    let bdpt = Integrator { kind: IntegratorKind::SimplePath, ..path };
    let e = check(&scene, &bdpt).expect_err("refused");
    assert!(e.to_string().contains("simplepath"), "{e}");
    let light_only = Integrator { strategy: DirectStrategy::LightOnly, ..path };
    assert!(check(&scene, &light_only).is_err());
}
