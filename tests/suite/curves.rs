//! Curves on both backends: Embree (user geometry) and obvhs's curve BVH, both with pbrt-v4's
//! recursive intersector, find the same hits on a hair bundle, and the compat scene's curves
//! render alike on both; and a curve's normal follows pbrt-v4's orientation rule.

use glam::Vec3;
use prism::accel::AccelKind;
use prism::geometry::Ray;

use crate::common::{backends, pbrt_scene};

#[test]
fn reverse_orientation_and_a_mirror_reverse_a_curves_normal() {
    // A flat curve along x seen from −z faces the ray; its normal ∂p/∂u × ∂p/∂v points along
    // the ray (pbrt-v4's convention), and is reversed by ReverseOrientation or by a mirroring
    // transform, not by both.
    let scene = |prefix: &str, kind: AccelKind| {
        pbrt_scene(
            &format!(
                "WorldBegin\n{prefix}\nShape \"curve\" \"point3 P\" [-1 0 0 -0.3 0 0 0.3 0 0 1 0 0] \"float width\" 0.2"
            ),
            kind,
        )
    };
    let ray = Ray::new(Vec3::new(0.2, 0.0, -3.0), Vec3::Z);
    for kind in backends() {
        let normal = |prefix: &str| {
            let s = scene(prefix, kind);
            let hit = s.intersect(&ray).expect("hit");
            assert!((hit.p - Vec3::new(0.2, 0.0, 0.0)).length() < 1e-4, "{kind:?} {prefix}: p = {}", hit.p);
            assert_eq!(hit.shading.ns, hit.shading.ng);
            hit.shading.ns
        };
        assert!((normal("") - Vec3::Z).length() < 1e-4, "{kind:?}: {}", normal(""));
        assert!((normal("ReverseOrientation") + Vec3::Z).length() < 1e-4);
        assert!((normal("Scale 1 -1 1") + Vec3::Z).length() < 1e-4);
        assert!((normal("ReverseOrientation\nScale 1 -1 1") - Vec3::Z).length() < 1e-4);
    }
}

#[cfg(embree)]
mod embree_and_obvhs {
    use glam::Vec3;
    use prism::accel::{self, AccelKind};
    use prism::geometry::curve::bezier_point;
    use prism::geometry::shapes::hair_bundle;
    use prism::geometry::{CurveKind, Hit, Mesh, Ray};
    use prism::image::metrics::channel_means;
    use prism::sampling::Rng;

    use crate::common::{prism, stderr, tmpdir};

    /// A ray from a random point 4 units from the bundle's centre toward a random point inside it;
    /// with `level`, a horizontal one (across the strands).
    fn ray_at_bundle(rng: &mut Rng, level: bool) -> Ray {
        let centre = Vec3::new(0.0, 0.6, 0.0);
        let z = if level { 0.0 } else { 1.0 - 2.0 * rng.uniform() };
        let s = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * rng.uniform();
        let target = Vec3::new(rng.uniform() - 0.5, 1.2 * rng.uniform(), rng.uniform() - 0.5);
        let mut o = centre + 4.0 * Vec3::new(s * phi.cos(), z, s * phi.sin());
        if level {
            o.y = target.y;
        }
        Ray::new(o, (target - o).normalize())
    }

    /// For the rays: how many hit at all; how many hit on one backend only; how many hit
    /// different segments at different depths (relative 1e-2: overlapping strands, or a segment's
    /// end shared with the next, may give either at one depth); and where both hit the same
    /// segment, the largest relative difference in t and, for rays more than 25° off the strand's
    /// tangent (along it, u is ill-conditioned), the largest difference in u.
    struct Agreement {
        hits: usize,
        one_sided: usize,
        other_segment: usize,
        max_dt: f32,
        max_du: f32,
    }

    fn compare(kind: CurveKind, rays: usize) -> Agreement {
        let mut rng = Rng::new(29, 2);
        let curves = hair_bundle(1000, kind, 23);
        let meshes = vec![Mesh::default()];
        let build = |k| accel::build_with_curves(k, &meshes, &[(0, &curves)]).unwrap();
        let (embree, obvhs) = (build(AccelKind::Embree), build(AccelKind::Obvhs));
        let mut a = Agreement { hits: 0, one_sided: 0, other_segment: 0, max_dt: 0.0, max_du: 0.0 };
        for _ in 0..rays {
            let ray = ray_at_bundle(&mut rng, kind == CurveKind::Ribbon);
            let (e, o): (Option<Hit>, Option<Hit>) = (embree.intersect(&ray), obvhs.intersect(&ray));
            assert_eq!(embree.occluded(&ray), e.is_some());
            assert_eq!(obvhs.occluded(&ray), o.is_some());
            match (e, o) {
                (Some(e), Some(o)) => {
                    a.hits += 1;
                    let dt = (e.t - o.t).abs() / o.t;
                    if e.prim_id != o.prim_id {
                        a.other_segment += usize::from(dt > 1e-2);
                        continue;
                    }
                    a.max_dt = a.max_dt.max(dt);
                    let seg = &curves.segments[o.prim_id as usize];
                    let tangent = bezier_point(&seg.cp, o.u).1.normalize();
                    if tangent.dot(ray.d).abs() < 0.9 {
                        a.max_du = a.max_du.max((e.u - o.u).abs());
                    }
                }
                (None, None) => {}
                _ => a.one_sided += 1,
            }
        }
        a
    }

    #[test]
    fn embree_and_obvhs_find_the_same_hits_on_a_hair_bundle() {
        // Both backends run pbrt-v4's curve test (Embree as user geometry), so every hit is the
        // same, to the bit. (Embree's own flat curves, four ray-facing quads per segment, missed
        // or gained a strand on about 1% of these rays.)
        for kind in [CurveKind::Cylinder, CurveKind::Flat, CurveKind::Ribbon] {
            let rays = 20_000;
            let a = compare(kind, rays);
            eprintln!(
                "{kind:?}: {} hits of {rays}; {} one-sided, {} on another segment; max |Δt|/t {:.2e}, max |Δu| {:.2e}",
                a.hits, a.one_sided, a.other_segment, a.max_dt, a.max_du
            );
            assert!(a.hits > rays / 10, "{kind:?}: {} hits", a.hits);
            assert_eq!((a.one_sided, a.other_segment), (0, 0), "{kind:?}");
            assert_eq!((a.max_dt, a.max_du), (0.0, 0.0), "{kind:?}");
        }
    }

    /// The image of `scene` (tests/data/compat) on `accel` at `spp` with `seed`.
    fn render(scene: &str, accel: &str, spp: u32, seed: u32) -> prism::image::Image {
        let d = tmpdir(&format!("curves-{accel}-{seed}"));
        let out = d.join("c.exr");
        let o = prism()
            .arg("render")
            .arg(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compat").join(scene))
            .args(["--spp", &spp.to_string(), "--sampler", "independent", "--seed", &seed.to_string()])
            .args(["--accel", accel, "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        let img = prism::image::read(&out).unwrap();
        std::fs::remove_dir_all(&d).ok();
        img
    }

    #[test]
    fn the_compat_curves_render_alike_on_embree_and_obvhs() {
        // Two seeds per backend: the pixel differences of a backend's seeds give its standard error.
        let spp = 16;
        let [e1, e2, o1, o2] =
            [("embree", 1), ("embree", 2), ("obvhs", 1), ("obvhs", 2)].map(|(a, s)| render("curves.pbrt", a, spp, s));
        let se = |a: &prism::image::Image, b: &prism::image::Image| -> [f64; 3] {
            let c = a.channels as usize;
            let n = (a.data.len() / c) as f64;
            let mut d2 = [0.0; 3];
            for (p, q) in a.data.chunks_exact(c).zip(b.data.chunks_exact(c)) {
                for k in 0..3 {
                    d2[k] += (f64::from(p[k]) - f64::from(q[k])).powi(2);
                }
            }
            d2.map(|s| s.sqrt() / (2.0 * n))
        };
        let (se_e, se_o) = (se(&e1, &e2), se(&o1, &o2));
        let (me, mo) = ([&e1, &e2].map(channel_means), [&o1, &o2].map(channel_means));
        for k in 0..3 {
            let (e, o) = (0.5 * (me[0][k] + me[1][k]), 0.5 * (mo[0][k] + mo[1][k]));
            assert!(e > 0.02 && o > 0.02, "channel {k} is black: {e} {o}");
            let tol = 4.0 * (se_e[k] * se_e[k] + se_o[k] * se_o[k]).sqrt();
            assert!((e - o).abs() < tol, "channel {k}: embree {e}, obvhs {o}, 4σ = {tol}");
        }
    }
}
