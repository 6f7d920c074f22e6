//! pbrt-v4's quadrics through the whole renderer: an emissive sphere read from a scene file
//! lights a point with the closed-form irradiance E = π L sin²θmax (sin θmax = r/d, PBR 4th ed.
//! §4.2) by light sampling, BSDF sampling and MIS on every backend; from inside a reversed one
//! (a sky sphere) E = π L; and disks, cylinders and partial spheres render on every backend
//! with the same image.

use crate::common::{backends, pbrt_scene as scene, test_settings};
use glam::Vec3;
use prism::integrator::{DirectStrategy, Integrator};
use prism::light::{Light, SphereLight};
use prism::math::PI;
use prism::measure::{irradiance, Estimate};
use prism::render::render;

/// Within 3.5 standard errors plus the tessellation's share: BSDF-sampled directions see the
/// inscribed mesh, whose solid angle is smaller than the sphere's by less than 2·1.1·10⁻³
/// (twice its relative sag, geometry::quadric).
fn assert_close(what: &str, e: Estimate, expected: f64) {
    let tol = 3.5 * e.std_err + 2.2e-3 * expected;
    assert!(e.mean > 0.0, "{what}: black");
    assert!((e.mean - expected).abs() <= tol, "{what}: {} ± {} vs closed form {expected}", e.mean, e.std_err);
}

/// The scene `text` has one emissive sphere, which must become one sphere light; on every
/// backend and by each of `strategies`, the irradiance at `at` = (point, normal) from `samples`
/// estimates is `expected(light)`.
fn assert_sphere_irradiance(
    text: &str,
    at: (Vec3, Vec3),
    strategies: &[DirectStrategy],
    samples: u64,
    expected: impl Fn(&SphereLight) -> f64,
) {
    for accel in backends() {
        let s = scene(text, accel);
        let Light::Sphere(light) = &s.lights()[0] else { panic!("the sphere is one light sampled by solid angle") };
        assert_eq!(s.lights().len(), 1);
        for &strategy in strategies {
            let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
            let m = irradiance(&s, &integ, at.0, at.1, samples, 3);
            assert_close(&format!("{accel:?} {strategy:?}"), m.irradiance, expected(light));
        }
    }
}

#[test]
fn an_emissive_sphere_gives_pi_l_sin2_theta_max_by_every_strategy_and_backend() {
    // r = 1 at distance 3 above the point: sin²θmax = 1/9 (L, which pbrt-v4 normalises from the
    // spectrum, is read back from the light).
    let text = r#"
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "spectrum L" [ 300 2 900 2 ]
  Translate 0 3 0
  Rotate 30 1 1 0
  Shape "sphere" "float radius" [ 1 ]
AttributeEnd
"#;
    // E = π L sin²θmax = Φ / (4π r²) · sin²θmax, with L (integrated over the measured
    // wavelengths) from the light's flux Φ = π L · 4π r².
    let expected = |l: &SphereLight| (l.radiant_flux() / (4.0 * PI * l.radius * l.radius)) as f64 / 9.0;
    let strategies = [DirectStrategy::LightOnly, DirectStrategy::BsdfOnly, DirectStrategy::Mis];
    assert_sphere_irradiance(text, (Vec3::ZERO, Vec3::Y), &strategies, 40_000, expected);
}

#[test]
fn inside_a_reversed_emissive_sphere_the_irradiance_is_pi_l() {
    // A point off the centre of a sphere emitting inward (ReverseOrientation) with L = 1 sees
    // L in every direction of its hemisphere: E = π L, sampled by area from inside.
    let text = r#"
LookAt 0 0 -1  0 0 0  0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  ReverseOrientation
  AreaLightSource "diffuse" "spectrum L" [ 300 1 900 1 ]
  Shape "sphere" "float radius" [ 10 ]
AttributeEnd
"#;
    // E = π L = Φ / (4π r²), with L from the flux Φ = π L · 4π r².
    let expected = |l: &SphereLight| (l.radiant_flux() / (4.0 * PI * l.radius * l.radius)) as f64;
    let at = (Vec3::new(2.0, -3.0, 1.0), Vec3::new(0.3, 1.0, 0.2));
    assert_sphere_irradiance(text, at, &[DirectStrategy::LightOnly, DirectStrategy::Mis], 20_000, expected);
}

#[test]
fn disks_cylinders_and_partial_spheres_render_alike_on_every_backend() {
    let text = r#"
LookAt 0 4 -6  0 0.3 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
WorldBegin
LightSource "infinite" "rgb L" [ 0.5 0.5 0.5 ]
AttributeBegin
  AreaLightSource "diffuse" "spectrum L" [ 300 8 900 8 ]
  Translate 0 3 0
  Shape "disk" "float radius" [ 0.5 ] "float innerradius" [ 0.2 ] "float phimax" [ 300 ]
AttributeEnd
AttributeBegin
  Rotate -90 1 0 0
  Shape "disk" "float radius" [ 3 ]
  Translate -1.5 0 0
  Shape "cylinder" "float radius" [ 0.6 ] "float zmin" [ 0 ] "float zmax" [ 1.2 ] "float phimax" [ 250 ]
  Translate 3 0 0.7
  Shape "sphere" "float radius" [ 0.7 ] "float zmin" [ -0.4 ] "float zmax" [ 0.6 ] "float phimax" [ 280 ]
AttributeEnd
"#;
    let settings = test_settings((48, 32), 32, 7, 4);
    let films: Vec<_> = backends().into_iter().map(|a| render(&scene(text, a), &settings, |_| {}).unwrap().0).collect();
    let y = |f: &prism::film::Film| -> Vec<f64> { f.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect() };
    let a = y(&films[0]);
    let mean = a.iter().sum::<f64>() / a.len() as f64;
    assert!(mean > 0.05, "image is black ({mean})");
    // Not one flat value: the shapes are there (pixels differ from each other).
    let spread = a.iter().fold(0.0f64, |m, &v| m.max((v - mean).abs()));
    assert!(spread > 0.2 * mean, "the image is uniform: no shapes");
    for f in &films[1..] {
        let b = y(f);
        // Same samples on the same triangles: most pixels are equal to rounding; a path that
        // meets an edge on one backend and its neighbour on the other diverges, so the images'
        // means agree within 4 standard errors of their pixel-by-pixel difference.
        let differ = a.iter().zip(&b).filter(|(x, y)| (*x - *y).abs() > 1e-3 * x.abs().max(1e-3)).count();
        assert!(differ * 20 < a.len(), "{differ} of {} pixels differ between backends", a.len());
        let n = a.len() as f64;
        let d: f64 = a.iter().zip(&b).map(|(x, y)| x - y).sum::<f64>() / n;
        let se = (a.iter().zip(&b).map(|(x, y)| (x - y).powi(2)).sum::<f64>()).sqrt() / n;
        assert!(d.abs() <= 4.0 * se + 1e-6 * mean, "image means differ by {d} ± {se}");
    }
}

/// Rays spawned from hit points on a sphere and an annulus (offset by the points' error bounds)
/// never meet their own surface at the point again. The tessellated sphere is a convex
/// polyhedron and the annulus planar, so exactly: a ray leaving the sphere outward, or leaving
/// the annulus, meets nothing of its own shape; a ray entering the sphere meets it once more, on
/// another triangle.
#[test]
fn rays_spawned_from_quadric_surfaces_do_not_hit_them_again() {
    let text = r#"
LookAt 0 0 -10  0 0 0  0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  Translate 0.3 -0.2 0.1
  Rotate 37 1 2 3
  Shape "sphere" "float radius" [ 1.3 ]
AttributeEnd
AttributeBegin
  Translate 40 0 0
  Rotate 20 0 1 1
  Shape "disk" "float radius" [ 2 ] "float innerradius" [ 0.3 ]
AttributeEnd
"#;
    let mut rng = prism::sampling::Rng::new(17, 3);
    let mut dir = || {
        let z = 1.0 - 2.0 * rng.uniform();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * rng.uniform();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    for accel in backends() {
        let s = scene(text, accel);
        let (mut leaving, mut entering) = (0, 0);
        for (centre, size) in [(Vec3::new(0.3, -0.2, 0.1), 1.2), (Vec3::new(40.0, 0.0, 0.0), 1.9)] {
            for _ in 0..20_000 {
                // From far away toward a random point of the shape's bounds.
                let o = centre + dir() * 30.0;
                let aim = centre + dir() * size;
                let Some(si) = s.intersect(&prism::geometry::Ray::new(o, (aim - o).normalize())) else { continue };
                let d = dir();
                let ng = si.shading.ng;
                let again = s.intersect(&si.spawn_ray(d)).filter(|h| h.mesh == si.mesh);
                // (A ray aimed at the annulus may pass it and meet the sphere.)
                let on_disk = si.p.x > 20.0;
                let sphere_centre = Vec3::new(0.3, -0.2, 0.1);
                if on_disk || d.dot(ng) * ng.dot(si.p - sphere_centre) > 0.0 {
                    leaving += 1;
                    assert!(again.is_none(), "{accel:?}: a ray leaving {} along {d} met its shape again", si.p);
                } else {
                    entering += 1;
                    let far = again.unwrap_or_else(|| panic!("{accel:?}: a ray into the sphere at {} left it", si.p));
                    // The far side, not the point it left (the sphere is 2.6 across).
                    assert!((far.p - si.p).length() > 1e-3, "{accel:?}: re-hit the sphere at {} from {}", far.p, si.p);
                }
            }
        }
        assert!(leaving > 10_000 && entering > 5_000, "{leaving} leaving, {entering} entering rays");
    }
}
