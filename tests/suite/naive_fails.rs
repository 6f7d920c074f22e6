//! Robustness proofs: each test runs prism's routine and a naive textbook variant (written out
//! here) through the same assertion, and checks that ours passes where the naive one fails, so
//! the test would catch a regression to the naive form.

use glam::{Vec2, Vec3};
use prism::accel::watertight::ShearedRay;
use prism::bsdf::fresnel::fr_dielectric;
use prism::bsdf::TrowbridgeReitz;
use prism::math::offset::{offset_ray_origin, triangle_point};
use prism::math::PI;
use prism::sampling::Rng;

// ---------------------------------------------------------------- self-intersection ----

/// A fixed global epsilon along the normal: the classic spawn offset.
fn naive_offset(p: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    const EPSILON: f32 = 1e-4;
    p + if w.dot(n) < 0.0 { -n } else { n } * EPSILON
}

struct SpawnCounts {
    self_hits: usize,
    missed_occluder: usize,
}

/// Rays hit a large triangle (scaled by `scale`, moved by `shift`) at random points; from each
/// hit a ray is spawned on the front side, toward random directions down to grazing. Counts
/// spawned rays that hit the triangle they leave (acne), and spawned rays aimed straight at a
/// parallel triangle `1e-3 · scale` (or 64 ulps) above that do not hit it (a leak: the origin jumped over it).
fn spawn(scale: f32, shift: Vec3, offset: impl Fn(Vec3, Vec3, Vec3, Vec3) -> Vec3) -> SpawnCounts {
    let tri =
        [Vec3::new(-1.0, -1.0, 0.1), Vec3::new(1.3, -0.8, -0.2), Vec3::new(-0.2, 1.1, 0.05)].map(|p| p * scale + shift);
    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
    // The gap must be representable: at least 64 ulps of the largest coordinate (far from the
    // origin a 1e-3 gap would round away, like the Cornell box test's 0.1 mm light gap).
    let extent = tri.iter().map(|p| p.abs().max_element()).fold(0.0, f32::max);
    let gap = (1e-3 * scale).max(64.0 * extent * f32::EPSILON);
    // The lid is twice the triangle's size (about its centroid), so rays from near an edge
    // still meet it after rounding.
    let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
    let lid = tri.map(|p| centroid + (p - centroid) * 2.0 + n * gap);
    let mut rng = Rng::new(17, 3);
    let mut counts = SpawnCounts { self_hits: 0, missed_occluder: 0 };
    for _ in 0..20_000 {
        // A camera ray from above toward a random point of the triangle.
        let b = {
            let (u, v) = (rng.uniform(), rng.uniform());
            let su = u.sqrt();
            [1.0 - su, su * (1.0 - v), su * v]
        };
        let target = tri[0] * b[0] + tri[1] * b[1] + tri[2] * b[2];
        let o = target + (n + Vec3::new(0.3, -0.2, 0.1)) * scale;
        let Some(ray) = ShearedRay::new(o, target - o) else { continue };
        let Some(hit) = ray.intersect(tri[0], tri[1], tri[2], f32::INFINITY) else { continue };
        let bary = [1.0 - hit.u - hit.v, hit.u, hit.v];
        let (p, p_err) = triangle_point(tri, bary);
        // Spawn toward the front hemisphere, cos θ from 1 down to 1e-4 (grazing).
        let cos: f32 = [1.0, 0.5, 1e-2, 1e-4][rng.next_u32() as usize % 4];
        let phi = 2.0 * PI * rng.uniform();
        let (t1, t2) = n.any_orthonormal_pair();
        let sin = (1.0 - cos * cos).sqrt();
        let w = n * cos + (t1 * phi.cos() + t2 * phi.sin()) * sin;
        let po = offset(p, p_err, n, w);
        if let Some(r) = ShearedRay::new(po, w) {
            counts.self_hits += r.intersect(tri[0], tri[1], tri[2], f32::INFINITY).is_some() as usize;
        }
        let po = offset(p, p_err, n, n);
        if let Some(r) = ShearedRay::new(po, n) {
            counts.missed_occluder += r.intersect(lid[0], lid[1], lid[2], f32::INFINITY).is_none() as usize;
        }
    }
    counts
}

#[test]
fn error_bound_offset_has_no_acne_or_leaks_where_a_global_epsilon_fails() {
    let cases = [
        ("1e-4", 1e-4, Vec3::ZERO),
        ("1", 1.0, Vec3::ZERO),
        ("1e5", 1e5, Vec3::ZERO),
        ("1 at +1e5", 1.0, Vec3::splat(1e5)),
        ("1e3 at +1e5", 1e3, Vec3::new(1e5, -1e5, 1e5)),
    ];
    let (mut naive_acne, mut naive_leaks) = (0, 0);
    for (name, scale, shift) in cases {
        let ours = spawn(scale, shift, offset_ray_origin);
        assert_eq!(ours.self_hits, 0, "scale {name}: {} self-intersections", ours.self_hits);
        assert_eq!(ours.missed_occluder, 0, "scale {name}: {} rays skipped a surface just above", ours.missed_occluder);
        let naive = spawn(scale, shift, |p, _, n, w| naive_offset(p, n, w));
        naive_acne += naive.self_hits;
        naive_leaks += naive.missed_occluder;
        eprintln!("scale {name}: naive ε = 1e-4 gives {} self-hits, {} leaks", naive.self_hits, naive.missed_occluder);
    }
    // The same assertions fail for the fixed epsilon: it is below an ulp far from the origin and
    // at large scales (acne), and larger than the gap at small scales (leaks).
    assert!(naive_acne > 0, "the naive offset never self-intersected: the test lost its teeth");
    assert!(naive_leaks > 0, "the naive offset never leaked: the test lost its teeth");
}

// ---------------------------------------------------------------------- watertightness ----

/// Möller & Trumbore 1997 as usually written, with its barycentric range tests.
fn moller_trumbore(o: Vec3, d: Vec3, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<f32> {
    let (e1, e2) = (p1 - p0, p2 - p0);
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let tv = o - p0;
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    (t > 0.0).then_some(t)
}

/// A closed, convex triangle mesh: a UV sphere with `n` segments (shared poles, edges, vertices),
/// rotated and moved off the origin so no coordinate is "nice".
fn closed_sphere(n: usize) -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let rot = glam::Mat3::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.4);
    let centre = Vec3::new(3.7, -1.3, 2.9);
    let mut p = vec![rot * Vec3::Z + centre, rot * -Vec3::Z + centre];
    let rings = n / 2;
    for i in 1..rings {
        let th = PI * i as f32 / rings as f32;
        for j in 0..n {
            let ph = 2.0 * PI * j as f32 / n as f32;
            p.push(rot * Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()) * 1.7 + centre);
        }
    }
    let id = |i: usize, j: usize| 2 + (i - 1) * n + j % n;
    let mut t = Vec::new();
    for j in 0..n {
        t.push([0, id(1, j), id(1, j + 1)]);
        t.push([1, id(rings - 1, j + 1), id(rings - 1, j)]);
        for i in 1..rings - 1 {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (p, t)
}

#[test]
fn watertight_test_never_leaks_at_shared_edges_and_vertices_where_moller_trumbore_does() {
    let (p, tris) = closed_sphere(24);
    let centre = Vec3::new(3.7, -1.3, 2.9);
    let mut rng = Rng::new(9, 1);
    let (mut ours_leaks, mut naive_leaks, mut rays) = (0, 0, 0);
    for _ in 0..60 {
        // Origins inside the closed mesh; every ray from there must hit it.
        let o = centre + Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 0.8;
        for t in &tris {
            // Aim at each vertex and at points along each edge (shared with a neighbour).
            for k in 0..3 {
                let (a, b) = (p[t[k]], p[t[(k + 1) % 3]]);
                for s in [0.0, 0.5, rng.uniform()] {
                    let d = a.lerp(b, s) - o;
                    rays += 1;
                    let hit_ours = ShearedRay::new(o, d).is_some_and(|r| {
                        tris.iter().any(|q| r.intersect(p[q[0]], p[q[1]], p[q[2]], f32::INFINITY).is_some())
                    });
                    let hit_naive = tris.iter().any(|q| moller_trumbore(o, d, p[q[0]], p[q[1]], p[q[2]]).is_some());
                    ours_leaks += !hit_ours as usize;
                    naive_leaks += !hit_naive as usize;
                }
            }
        }
    }
    eprintln!("{rays} rays at shared edges/vertices: watertight {ours_leaks} leaks, Möller–Trumbore {naive_leaks}");
    assert_eq!(ours_leaks, 0, "{ours_leaks} of {rays} rays passed through the closed mesh");
    assert!(naive_leaks > 0, "Möller–Trumbore never leaked: the test lost its teeth");
}

// ---------------------------------------------------------------------- grazing angles ----

/// The textbook unpolarised Fresnel reflectance, without the total-internal-reflection and
/// cos θ = 0 guards.
fn naive_fresnel(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 { (-cos_i, 1.0 / eta) } else { (cos_i, eta) };
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

fn grazing_cosines() -> Vec<f32> {
    let mut c = vec![1.0, 0.5, 1e-2, 1e-4, 1e-6, 1e-8, 1e-20, 0.0];
    c.extend(c.clone().iter().map(|v| -v));
    c
}

fn reflectance_ok(f: impl Fn(f32, f32) -> f32) -> usize {
    let mut bad = 0;
    for eta in [1.0f32, 1.0 + 1e-7, 1.33, 1.5, 2.4] {
        for c in grazing_cosines() {
            let r = f(c, eta);
            bad += !(r.is_finite() && (0.0..=1.0).contains(&r)) as usize;
        }
    }
    bad
}

#[test]
fn fresnel_is_a_reflectance_at_grazing_angles_where_the_textbook_formula_is_not() {
    assert_eq!(reflectance_ok(fr_dielectric), 0);
    assert!(reflectance_ok(naive_fresnel) > 0, "the naive Fresnel never failed");
}

/// GGX D(ωm) = 1/(π α² cos⁴θm (1 + tan²θm/α²)²) and the visible-normal density
/// G1(ω) D(ωm) (ω·ωm) / cos θ, written directly.
fn naive_ggx_d(alpha: f32, wm: Vec3) -> f32 {
    let cos2 = wm.z * wm.z;
    let tan2 = (1.0 - cos2) / cos2;
    let e = 1.0 + tan2 / (alpha * alpha);
    1.0 / (PI * alpha * alpha * cos2 * cos2 * e * e)
}

fn naive_vndf_pdf(alpha: f32, w: Vec3, wm: Vec3) -> f32 {
    let tan2 = (1.0 - w.z * w.z) / (w.z * w.z);
    let g1 = 2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt());
    g1 / w.z.abs() * naive_ggx_d(alpha, wm) * w.dot(wm).max(0.0)
}

/// Counts non-finite or negative D and visible-normal densities over directions down to
/// grazing (cos θ → 0, ωm in the tangent plane) and roughness down to 0.
fn microfacet_failures(d: impl Fn(f32, Vec3) -> f32, pdf: impl Fn(f32, Vec3, Vec3) -> f32) -> usize {
    let dirs: Vec<Vec3> = [1.0f32, 0.3, 1e-4, 1e-8, 0.0]
        .iter()
        .flat_map(|&z| {
            let r = (1.0 - z * z).max(0.0).sqrt();
            [Vec3::new(r, 0.0, z), Vec3::new(-0.6 * r, 0.8 * r, z)]
        })
        .collect();
    let mut bad = 0;
    for alpha in [1.0f32, 0.3, 1e-3, 1e-8, 0.0] {
        for &w in &dirs {
            for &wm in &dirs {
                let (dv, pv) = (d(alpha, wm), pdf(alpha, w, wm));
                bad += !(dv.is_finite() && dv >= 0.0) as usize + !(pv.is_finite() && pv >= 0.0) as usize;
            }
        }
    }
    bad
}

/// prism's BxDFs switch to a delta lobe below `SMOOTH_ALPHA` and never evaluate D there.
fn smooth_or(alpha: f32, f: impl Fn(&TrowbridgeReitz) -> f32) -> f32 {
    let g = TrowbridgeReitz::new(alpha, alpha);
    if g.effectively_smooth() {
        0.0
    } else {
        f(&g)
    }
}

#[test]
fn ggx_density_and_masking_stay_finite_at_grazing_and_zero_roughness_where_naive_ggx_does_not() {
    let ours = microfacet_failures(|a, wm| smooth_or(a, |g| g.d(wm)), |a, w, wm| smooth_or(a, |g| g.pdf(w, wm)));
    assert_eq!(ours, 0, "prism's GGX produced {ours} non-finite values");
    assert!(microfacet_failures(naive_ggx_d, naive_vndf_pdf) > 0, "naive GGX never failed");
    // Masking is a probability at every angle, also for ours without the smooth switch.
    for alpha in [1.0f32, 0.3, 1e-3, 1e-8] {
        let g = TrowbridgeReitz::new(alpha, alpha);
        for z in [1.0f32, 1e-4, 1e-8, 0.0] {
            let w = Vec3::new((1.0 - z * z).sqrt(), 0.0, z);
            let g1 = g.g1(w);
            assert!((0.0..=1.0).contains(&g1), "G1({z}) = {g1} at α = {alpha}");
        }
    }
}

#[test]
fn visible_normal_samples_at_grazing_incidence_have_finite_positive_density() {
    let mut rng = Rng::new(4, 4);
    for alpha in [1.0f32, 0.2, 2e-3] {
        let g = TrowbridgeReitz::new(alpha, alpha * 0.5);
        for z in [1e-2f32, 1e-4, 1e-6, 1e-8] {
            let w = Vec3::new(-(1.0 - z * z).sqrt(), 0.0, z);
            for i in 0..2_000 {
                // Include the corners of the unit square.
                let u = match i {
                    0 => Vec2::ZERO,
                    1 => Vec2::splat(1.0 - f32::EPSILON / 2.0),
                    _ => Vec2::new(rng.uniform(), rng.uniform()),
                };
                let wm = g.sample_wm(w, u);
                let pdf = g.pdf(w, wm);
                assert!(wm.is_finite() && wm.z > 0.0, "α={alpha} z={z} u={u}: ωm = {wm}");
                assert!(pdf.is_finite() && pdf >= 0.0, "α={alpha} z={z} u={u}: pdf {pdf}");
            }
        }
        // Exactly tangent ω: the naive density divides 0 by 0.
        let w = Vec3::new(1.0, 0.0, 0.0);
        assert_eq!(g.pdf(w, Vec3::Z), 0.0);
        assert!(naive_vndf_pdf(alpha, w, Vec3::Z).is_nan());
    }
}
