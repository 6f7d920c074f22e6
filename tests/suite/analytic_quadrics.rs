//! Analytic quadrics on every backend: ray hits against a closed form solved independently in
//! f64 (partial ranges, an annulus, grazing rays, rays from inside), every backend reporting the
//! same t; and an emissive annulus lighting a point with its closed-form irradiance (the disk
//! form factor) by light sampling, BSDF sampling and MIS.

use glam::{DVec3, Mat4, Quat, Vec3};
use prism::accel::{self, ExtraShapes};
use prism::geometry::{Mesh, PlacedQuadric, Quadric, Ray};
use prism::integrator::{DirectStrategy, Integrator};
use prism::light::Light;
use prism::measure::irradiance;
use prism::sampling::Rng;

use crate::common::{backends, pbrt_scene};

/// The nearest t > 0 at which o + t d meets `q` (object space, f64), and how close the roots
/// up to it come to an edge of the shape's ranges or to tangency (relative: below ~10⁻⁴ an f32
/// test may decide either way).
fn closed_form(q: &Quadric, o: DVec3, d: DVec3) -> (Option<f64>, f64) {
    let two_pi = std::f64::consts::TAU;
    let phi_of = |p: DVec3| p.y.atan2(p.x).rem_euclid(two_pi);
    let (roots, tangency): (Vec<f64>, f64) = match *q {
        Quadric::Sphere { radius, .. } | Quadric::Cylinder { radius, .. } => {
            let r = radius as f64;
            let (oo, dd) = match q {
                Quadric::Sphere { .. } => (o, d),
                _ => (DVec3::new(o.x, o.y, 0.0), DVec3::new(d.x, d.y, 0.0)),
            };
            let (a, b, c) = (dd.dot(dd), 2.0 * oo.dot(dd), oo.dot(oo) - r * r);
            let disc = b * b - 4.0 * a * c;
            let tangency = disc.abs() / (b * b + (4.0 * a * c).abs() + 4.0 * a * r * r);
            if a == 0.0 || disc < 0.0 {
                return (None, tangency);
            }
            let s = disc.sqrt();
            (vec![(-b - s) / (2.0 * a), (-b + s) / (2.0 * a)], tangency)
        }
        Quadric::Disk { height, .. } => (vec![(height as f64 - o.z) / d.z], 1.0),
    };
    // A root near t = 0 (an origin on the surface) may take either sign in f32.
    let size = match *q {
        Quadric::Sphere { radius, .. } | Quadric::Cylinder { radius, .. } | Quadric::Disk { radius, .. } => {
            radius as f64
        }
    };
    let mut margin = roots.iter().fold(tangency, |m, t| m.min(t.abs() * d.length() / size));
    for t in roots.into_iter().filter(|&t| t > 0.0) {
        let p = o + t * d;
        let phi = phi_of(p);
        let phi_margin = |pm: f64| if pm >= two_pi { 1.0 } else { phi.min((phi - pm).abs()).min(two_pi - phi) };
        let inside = match *q {
            Quadric::Sphere { radius, z_min, z_max, phi_max } | Quadric::Cylinder { radius, z_min, z_max, phi_max } => {
                let (r, lo, hi, pm) = (radius as f64, z_min as f64, z_max as f64, (phi_max as f64).to_radians());
                let full_z = matches!(q, Quadric::Sphere { .. }) && lo <= -r && hi >= r;
                let z_margin = if full_z { 1.0 } else { (p.z - lo).abs().min((p.z - hi).abs()) / r };
                margin = margin.min(z_margin).min(phi_margin(pm));
                p.z >= lo && p.z <= hi && phi <= pm
            }
            Quadric::Disk { radius, inner_radius, phi_max, .. } => {
                let (r, ri, pm) = (radius as f64, inner_radius as f64, (phi_max as f64).to_radians());
                let rho = (p.x * p.x + p.y * p.y).sqrt();
                let ri_margin = if ri > 0.0 { (rho - ri).abs() / r } else { 1.0 };
                margin = margin.min((rho - r).abs() / r).min(ri_margin).min(phi_margin(pm));
                rho <= r && rho >= ri && phi <= pm
            }
        };
        if inside {
            return (Some(t), margin);
        }
    }
    (None, margin)
}

/// The shapes of the test, each with its object-to-world transform.
fn shapes() -> Vec<(Quadric, Mat4)> {
    let placed = |scale: Vec3, axis: Vec3, angle: f32, at: Vec3| {
        Mat4::from_scale_rotation_translation(scale, Quat::from_axis_angle(axis.normalize(), angle), at)
    };
    vec![
        (
            Quadric::Sphere { radius: 1.3, z_min: -1.3, z_max: 1.3, phi_max: 360.0 },
            placed(Vec3::ONE, Vec3::X, 0.4, Vec3::new(0.5, -1.0, 2.0)),
        ),
        (
            Quadric::Sphere { radius: 0.9, z_min: -0.55, z_max: 0.65, phi_max: 290.0 },
            placed(Vec3::splat(2.5), Vec3::new(1.0, 1.0, 0.0), 1.1, Vec3::new(30.0, 4.0, -7.0)),
        ),
        (
            Quadric::Cylinder { radius: 0.7, z_min: -0.4, z_max: 1.3, phi_max: 240.0 },
            placed(Vec3::new(1.0, 2.0, 0.5), Vec3::new(0.3, 1.0, 0.2), 0.7, Vec3::new(-1.0, 0.2, 0.3)),
        ),
        (
            Quadric::Cylinder { radius: 0.5, z_min: 0.0, z_max: 2.0, phi_max: 360.0 },
            placed(Vec3::ONE, Vec3::Y, 1.5, Vec3::ZERO),
        ),
        (
            Quadric::Disk { height: 0.1, radius: 1.0, inner_radius: 0.45, phi_max: 270.0 },
            placed(Vec3::splat(0.01), Vec3::new(1.0, 0.2, 0.0), 2.1, Vec3::new(0.0, 0.0, 0.05)),
        ),
        (
            Quadric::Disk { height: -0.3, radius: 2.0, inner_radius: 0.0, phi_max: 360.0 },
            placed(Vec3::ONE, Vec3::Z, 0.3, Vec3::new(1.0, 1.0, 1.0)),
        ),
    ]
}

/// Rays at `q`: from outside toward points of its box, from inside its box, and grazing
/// (through a surface point, within 0.6° of the surface; flagged true).
fn rays(q: &PlacedQuadric, rng: &mut Rng, n: usize) -> Vec<(Ray, bool)> {
    let b = q.bounds();
    let (c, size) = (b.center(), (b.max - b.min).length());
    let mut u3 = || Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
    (0..n)
        .map(|i| {
            let target = b.min + (b.max - b.min) * u3();
            match i % 3 {
                0 => {
                    let o = c + (u3() - 0.5).normalize() * 3.0 * size;
                    (Ray::new(o, (target - o).normalize()), false)
                }
                1 => (Ray::new(b.min + (b.max - b.min) * u3(), (u3() - 0.5).normalize()), false),
                _ => {
                    let uv = u3();
                    let (p, n, _) = q.point(uv.x, uv.y);
                    let along = n.any_orthonormal_vector();
                    let d = (along + n * (u3().x - 0.5) * 0.02).normalize();
                    (Ray::new(p - d * size, d), true)
                }
            }
        })
        .collect()
}

#[test]
fn quadric_hits_match_the_closed_form_and_every_backend_reports_the_same_t() {
    let mut rng = Rng::new(41, 3);
    for (shape, m) in shapes() {
        let q = PlacedQuadric::new(shape, m, false).unwrap();
        let meshes = vec![Mesh::default()];
        let extra = ExtraShapes { curves: &[], quadrics: &[(0, &q)] };
        let accels: Vec<_> =
            backends().into_iter().map(|k| (k, accel::build_with_extra(k, &meshes, extra).unwrap())).collect();
        let inverse = m.as_dmat4().inverse();
        let (mut hits, mut edge, mut grazing_edge) = (0, 0, 0);
        for (ray, grazing) in rays(&q, &mut rng, 6000) {
            let o = inverse.transform_point3(ray.o.as_dvec3());
            let d = inverse.transform_vector3(ray.d.as_dvec3());
            let exact = closed_form(&shape, o, d);
            let found: Vec<_> = accels.iter().map(|(_, a)| a.intersect(&ray).map(|h| h.t)).collect();
            for ((k, a), t) in accels.iter().zip(&found) {
                assert_eq!(*t, found[0], "{shape:?}: {k:?} and {:?} differ on {ray:?}", accels[0].0);
                assert_eq!(a.occluded(&ray), t.is_some(), "{k:?}: occluded disagrees with intersect");
            }
            // f32 rounding of the ray's transform and of the roots: relative to t and to the
            // distances involved.
            let close = |t: f32, te: f64| (t as f64 - te).abs() < 1e-5 * (te + o.length() + 10.0 * d.length());
            match (exact, found[0]) {
                ((Some(te), _), Some(t)) if close(t, te) => hits += 1,
                ((None, _), None) => {}
                ((_, margin), _) if margin < 1e-4 && grazing => grazing_edge += 1,
                ((_, margin), _) if margin < 1e-4 => edge += 1,
                (exact, t) => panic!("{shape:?}: closed form {exact:?}, backends {t:?} on {ray:?}"),
            }
        }
        eprintln!(
            "{shape:?}: {hits} hits agree; within 1e-4 of an edge or tangency, decided otherwise: \
             {edge} rays, {grazing_edge} grazing ones"
        );
        assert!(hits > 1000, "{shape:?}: only {hits} hits");
        // Grazing rays are that close to tangency by construction (and far from the origin f32
        // cannot tell the two roots apart): only the others are counted.
        assert!(edge * 200 < hits, "{shape:?}: {edge} edge cases");
    }
}

#[test]
fn an_emissive_annulus_gives_its_closed_form_irradiance_by_every_strategy_and_backend() {
    // An annulus r ∈ [0.3, 1] of radiance L facing down from height h = 2 above the point, on
    // its axis: E = π L (r²/(h² + r²) − rᵢ²/(h² + rᵢ²)) (the disk form factor, differenced).
    // Tilted and moved by its transform; the point and its normal follow.
    let text = r#"
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  Translate 0.5 -0.2 1
  Rotate 35 1 0.5 0
  ReverseOrientation
  AreaLightSource "diffuse" "spectrum L" [ 300 3 900 3 ]
  Shape "disk" "float radius" [ 1 ] "float innerradius" [ 0.3 ] "float height" [ 2 ]
AttributeEnd
"#;
    let m = Mat4::from_translation(Vec3::new(0.5, -0.2, 1.0))
        * Mat4::from_axis_angle(Vec3::new(1.0, 0.5, 0.0).normalize(), 35f32.to_radians());
    let (at, normal) = (m.transform_point3(Vec3::ZERO), m.transform_vector3(Vec3::Z).normalize());
    let form = |r: f64| r * r / (4.0 + r * r);
    for accel in backends() {
        let s = pbrt_scene(text, accel);
        assert_eq!(s.lights().len(), 1);
        let Light::Quadric(light) = &s.lights()[0] else { panic!("the annulus is one quadric light") };
        // π L from the flux Φ = π L A.
        let pi_l = (light.radiant_flux() / light.area) as f64;
        let expected = pi_l * (form(1.0) - form(0.3));
        for strategy in [DirectStrategy::LightOnly, DirectStrategy::BsdfOnly, DirectStrategy::Mis] {
            let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
            let e = irradiance(&s, &integ, at, normal, 40_000, 3).irradiance;
            let tol = 3.5 * e.std_err;
            eprintln!("{accel:?} {strategy:?}: {} ± {} vs {expected}", e.mean, e.std_err);
            assert!(
                (e.mean - expected).abs() <= tol,
                "{accel:?} {strategy:?}: {} ± {} vs {expected}",
                e.mean,
                e.std_err
            );
        }
    }
}

#[test]
fn the_closest_of_many_quadrics_is_the_same_on_every_backend() {
    // All the shapes in one scene: each backend's closest hit is the nearest of the shapes'
    // own tests (the BVHs and Embree's traversal cull nothing they should not).
    let mut rng = Rng::new(5, 5);
    let placed: Vec<_> = shapes().into_iter().map(|(s, m)| PlacedQuadric::new(s, m, false).unwrap()).collect();
    let ids: Vec<(u32, &PlacedQuadric)> = placed.iter().enumerate().map(|(i, q)| (i as u32, q)).collect();
    let meshes = vec![Mesh::default(); placed.len()];
    let extra = ExtraShapes { curves: &[], quadrics: &ids };
    let accels: Vec<_> = backends().into_iter().map(|k| accel::build_with_extra(k, &meshes, extra).unwrap()).collect();
    let mut hits = 0;
    for i in 0..5000 {
        // From anywhere around toward a point of one shape's box.
        let b = placed[i % placed.len()].bounds();
        let target = b.min + (b.max - b.min) * Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
        let o = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 60.0;
        let ray = Ray::new(o, (target - o).normalize());
        let nearest = placed
            .iter()
            .enumerate()
            .filter_map(|(i, q)| q.intersect(&ray, f32::INFINITY).map(|t| (t, i as u32)))
            .min_by(|a, b| a.partial_cmp(b).unwrap());
        for a in &accels {
            let h = a.intersect(&ray).map(|h| (h.t, h.geom_id));
            assert_eq!(h, nearest, "{}: {ray:?}", a.name());
        }
        hits += nearest.is_some() as usize;
    }
    assert!(hits > 1500, "{hits} hits");
}
