//! Ribbon curves whose normal turns along them (n0 ⟂ n1): pbrt-v4 orients a ribbon at u by the
//! spherical interpolation of its end normals and intersects the ray-facing strip of width
//! w·|n(u)·d̂| (PBR 4th ed. §6.7.2); every backend must find the same hits on it, hit for hit,
//! and render it alike.

use glam::Vec3;
use prism::accel::{self, Accel, AccelKind};
use prism::geometry::curve_hit::curve_surface;
use prism::geometry::shapes::{level_ray_into_ribbon_grid, ribbon_grid};
use prism::geometry::{Curves, Hit, Mesh};
use prism::sampling::Rng;

use crate::common::{backends, pbrt_scene, test_settings};

/// Strand width [scene units].
const WIDTH: f32 = 0.05;

/// How two backends' closest hits on the same rays compare.
#[derive(Debug, Default)]
struct Agreement {
    /// Rays both hit.
    hits: usize,
    /// Rays one backend hit and the other missed.
    one_sided: usize,
    /// Rays both hit, on different strands.
    other_strand: usize,
    /// Where both hit one strand: the largest distance between the hit points, in widths.
    max_dp: f32,
    /// ... the largest difference in u.
    max_du: f32,
    /// ... the largest angle [degrees] between the normal a backend reports (when it reports
    /// one: Embree's own curves do) and prism's surface normal at the other's hit.
    max_normal_deg: f32,
}

fn compare(a: &dyn Accel, b: &dyn Accel, curves: &Curves, rays: usize) -> Agreement {
    let mut rng = Rng::new(31, 4);
    let mut g = Agreement::default();
    for _ in 0..rays {
        let ray = level_ray_into_ribbon_grid(&mut rng);
        let (x, y): (Option<Hit>, Option<Hit>) = (a.intersect(&ray), b.intersect(&ray));
        assert_eq!(a.occluded(&ray), x.is_some());
        assert_eq!(b.occluded(&ray), y.is_some());
        match (x, y) {
            (Some(x), Some(y)) if x.prim_id != y.prim_id => {
                g.hits += 1;
                g.other_strand += 1;
            }
            (Some(x), Some(y)) => {
                g.hits += 1;
                g.max_dp = g.max_dp.max((ray.at(x.t) - ray.at(y.t)).length() / WIDTH);
                g.max_du = g.max_du.max((x.u - y.u).abs());
                let seg = &curves.segments[y.prim_id as usize];
                let n = curve_surface(seg, &ray, y.t, y.u).expect("a surface at the hit").n;
                if x.ng != Vec3::ZERO {
                    let cos = x.ng.normalize().dot(n).abs().min(1.0);
                    g.max_normal_deg = g.max_normal_deg.max(cos.acos().to_degrees());
                }
            }
            (None, None) => {}
            _ => g.one_sided += 1,
        }
    }
    g
}

#[test]
fn every_backend_finds_the_same_hits_on_twisted_ribbons() {
    const RAYS: usize = 20_000;
    let meshes = vec![Mesh::default()];
    for twist in [0.0, std::f32::consts::FRAC_PI_2] {
        let curves = ribbon_grid(twist, WIDTH);
        let obvhs = accel::build_with_curves(AccelKind::Obvhs, &meshes, &[(0, &curves)]).unwrap();
        for kind in backends().into_iter().filter(|&k| k != AccelKind::Obvhs) {
            let other = accel::build_with_curves(kind, &meshes, &[(0, &curves)]).unwrap();
            let g = compare(&*other, &*obvhs, &curves, RAYS);
            eprintln!("twist {:.0}°, {kind:?} vs Obvhs: {g:?}", twist.to_degrees());
            assert!(g.hits > RAYS / 10, "{kind:?}: {} hits", g.hits);
            assert_eq!((g.one_sided, g.other_strand), (0, 0), "twist {twist}, {kind:?}: {g:?}");
            assert!(g.max_dp < 1e-3 && g.max_du < 1e-5, "twist {twist}, {kind:?}: {g:?}");
        }
    }
}

/// A tuft of twisted ribbons over a grey floor under a uniform sky.
const TUFT: &str = r#"
LookAt 0 0.6 -2.2  0 0.45 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
WorldBegin
LightSource "infinite" "rgb L" [ 1 1 1 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "trianglemesh" "integer indices" [ 0 1 2  0 2 3 ] "point3 P" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ]
Material "diffuse" "rgb reflectance" [ 0.8 0.4 0.1 ]
"#;

#[test]
fn twisted_ribbons_render_alike_on_every_backend() {
    // Eight ribbons turning their normals by 90° from root to tip, wide enough to fill pixels.
    let mut text = TUFT.to_string();
    for i in 0..8 {
        let x = -0.7 + 0.2 * i as f32;
        let a = 0.4 * i as f32;
        text += &format!(
            "Shape \"curve\" \"string type\" \"ribbon\" \"point3 P\" [ {x} 0 0  {x1} 0.3 0  {x} 0.6 0.1  {x1} 0.9 0 ] \
             \"normal N\" [ {n0x} 0 {n0z}  {n1x} 0 {n1z} ] \"float width0\" 0.12 \"float width1\" 0.06\n",
            x1 = x + 0.05,
            n0x = a.cos(),
            n0z = a.sin(),
            n1x = -a.sin(),
            n1z = a.cos(),
        );
    }
    const N: u32 = 48;
    let luminance = |kind, seed| {
        let s = pbrt_scene(&text, kind);
        let film = prism::render::render(&s, &test_settings((N, N), 16, seed, 3), |_| {}).unwrap().0;
        film.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).collect::<Vec<f64>>()
    };
    let obvhs = luminance(AccelKind::Obvhs, 7);
    let noise = {
        let other = luminance(AccelKind::Obvhs, 8);
        (obvhs.iter().zip(&other).map(|(a, b)| (a - b) * (a - b)).sum::<f64>() / obvhs.len() as f64).sqrt()
    };
    let mean = obvhs.iter().sum::<f64>() / obvhs.len() as f64;
    assert!(mean > 0.05, "the image is black ({mean})");
    for kind in backends().into_iter().filter(|&k| k != AccelKind::Obvhs) {
        let y = luminance(kind, 7);
        let d: Vec<f64> = y.iter().zip(&obvhs).map(|(a, b)| a - b).collect();
        let n = d.len() as f64;
        let md = d.iter().sum::<f64>() / n;
        let rms = (d.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
        let se = (d.iter().map(|v| (v - md) * (v - md)).sum::<f64>() / (n - 1.0) / n).sqrt();
        eprintln!("{kind:?} vs Obvhs, same samples: rms {rms:.2e} (noise {noise:.2e}), mean {md:.2e} ± {se:.2e}");
        assert!(md.abs() <= 4.0 * se.max(1e-9), "{kind:?}: mean difference {md} ± {se}");
        assert!(rms < 0.1 * noise, "{kind:?}: rms difference {rms}, noise {noise}");
    }
}
