use super::super::{LightSampleContext, LightSampler, LightSamplerKind};
use super::BvhLightSampler;
use crate::light::{
    AreaLight, DistantLight, Light, PointLight, SphereLight, SpotFalloff, SpotLight, UniformInfiniteLight,
};
use crate::sampling::chi2::chi2_survival;
use crate::sampling::rng::Rng;
use crate::sampling::warp::sample_uniform_sphere;
use crate::spectrum::Spectrum;
use glam::{Vec2, Vec3};
use std::sync::Arc;

fn white() -> Arc<Spectrum> {
    Arc::new(Spectrum::constant(1.0))
}

fn unit(rng: &mut Rng) -> Vec3 {
    sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()))
}

fn in_box(rng: &mut Rng, half: f32) -> Vec3 {
    Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * (2.0 * half) - Vec3::splat(half)
}

fn triangle(p: [Vec3; 3], scale: f32, two_sided: bool) -> Light {
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    Light::Area(AreaLight {
        p,
        n: n.normalize(),
        area: 0.5 * n.length(),
        spectrum: white(),
        scale,
        two_sided,
        image: None,
    })
}

/// Triangles of random size, orientation and radiance (one-sided with probability
/// `one_sided`), spheres, point lights and (if `spots`) spotlights spread over a box of
/// half-side 5, one constant infinite light and one distant light.
fn many_lights(seed: u64, one_sided: f32, spots: bool) -> Vec<Light> {
    let mut rng = Rng::new(seed, 1);
    let mut lights = Vec::new();
    for _ in 0..120 {
        let c = in_box(&mut rng, 5.0);
        let s = 0.05 + 0.5 * rng.uniform();
        let p = [c, c + s * unit(&mut rng), c + s * unit(&mut rng)];
        lights.push(triangle(p, 0.1 + 10.0 * rng.uniform(), rng.uniform() >= one_sided));
    }
    for _ in 0..15 {
        lights.push(Light::Sphere(SphereLight {
            center: in_box(&mut rng, 5.0),
            radius: 0.05 + 0.3 * rng.uniform(),
            spectrum: white(),
            scale: 0.1 + 5.0 * rng.uniform(),
            two_sided: false,
            inward: false,
        }));
    }
    for _ in 0..10 {
        lights.push(Light::Point(PointLight::new(in_box(&mut rng, 5.0), white(), 0.1 + 3.0 * rng.uniform())));
    }
    for _ in 0..if spots { 5 } else { 0 } {
        let falloff = SpotFalloff::Cone { cos_start: 0.9, cos_end: 0.7 };
        lights.push(Light::Spot(SpotLight::new(in_box(&mut rng, 5.0), unit(&mut rng), white(), 2.0, falloff)));
    }
    lights.push(Light::UniformInfinite(UniformInfiniteLight { spectrum: white(), scale: 0.01 }));
    lights.push(Light::Distant(DistantLight { to_light: Vec3::Y, spectrum: white(), scale: 0.1 }));
    lights
}

/// A point inside the lights' box, on a surface with a random normal or (one in four) in a
/// medium.
fn random_context(rng: &mut Rng) -> LightSampleContext {
    let p = in_box(rng, 6.0);
    if rng.uniform() < 0.25 {
        LightSampleContext::medium(p)
    } else {
        LightSampleContext::surface(p, unit(rng))
    }
}

/// The probability that a walk from `node` down the tree ends at a node whose children both
/// have importance 0 (no light below can reach the point), found top-down.
fn dead_end_mass(s: &BvhLightSampler, ctx: &LightSampleContext, node: usize) -> f64 {
    let n = &s.nodes[node];
    if n.leaf {
        return 0.0;
    }
    let second = n.child_or_light as usize;
    let c0 = s.nodes[node + 1].bounds.importance(ctx.p, ctx.n) as f64;
    let c1 = s.nodes[second].bounds.importance(ctx.p, ctx.n) as f64;
    if c0 + c1 == 0.0 {
        return 1.0;
    }
    (c0 * dead_end_mass(s, ctx, node + 1) + c1 * dead_end_mass(s, ctx, second)) / (c0 + c1)
}

/// With lights that emit in every direction (two-sided triangles, spheres, points), Σ pmf = 1
/// at every context.
#[test]
fn the_pmfs_of_lights_emitting_everywhere_sum_to_one() {
    let lights = many_lights(3, 0.0, false);
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let mut rng = Rng::new(19, 4);
    for _ in 0..500 {
        let ctx = random_context(&mut rng);
        let sum: f64 = (0..lights.len()).map(|i| sampler.pmf(&ctx, i) as f64).sum();
        assert!((sum - 1.0).abs() < 1e-5, "Σ pmf = {sum} at {ctx:?}");
    }
}

/// With one-sided emitters and spotlights, Σ pmf = 1 less the share of `u` that reaches a
/// subtree none of whose lights can reach the point (where `sample` returns `None`, as
/// pbrt-v4's does); the sampled pmf is `pmf`'s.
#[test]
fn the_pmfs_over_all_lights_sum_to_one_and_match_what_sampling_reports() {
    let lights = many_lights(3, 0.7, true);
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let LightSampler::Bvh(tree) = &sampler else { unreachable!() };
    let mut rng = Rng::new(17, 4);
    let mut dead_total = 0.0;
    for _ in 0..500 {
        let ctx = random_context(&mut rng);
        let sum: f64 = (0..lights.len()).map(|i| sampler.pmf(&ctx, i) as f64).sum();
        // Two of the lights are at infinity: the tree has probability 1/3.
        let dead = dead_end_mass(tree, &ctx, 0) / 3.0;
        dead_total += dead;
        assert!((sum + dead - 1.0).abs() < 1e-5, "Σ pmf = {sum}, dead ends {dead} at {ctx:?}");
        for _ in 0..20 {
            let Some((i, pmf, rest)) = sampler.sample(&ctx, rng.uniform()) else { continue };
            let expected = sampler.pmf(&ctx, i);
            assert!((pmf - expected).abs() <= 1e-5 * expected, "light {i}: sampled pmf {pmf}, pmf() {expected}");
            assert!((0.0..1.0).contains(&rest), "remainder {rest}");
        }
    }
    // One-sided lights facing away lose some share, but most reaches a light.
    let dead_mean = dead_total / 500.0;
    assert!(dead_mean < 0.1, "mean share without a light {dead_mean}");
    eprintln!("mean share of u without a light: {dead_mean}");
}

/// Pearson's χ² of `counts` against `expected` (cells expected below 5 pooled): P(χ² ≥ X²).
/// A count in a cell of expected 0 is an outright failure.
fn chi2_p_value(counts: &[u64], expected: &[f64]) -> f64 {
    let (mut cells, mut stat) = (0usize, 0.0f64);
    let (mut pooled_o, mut pooled_e) = (0.0f64, 0.0f64);
    for (&o, &e) in counts.iter().zip(expected) {
        assert!(e > 0.0 || o == 0, "{o} samples in a cell of probability 0");
        if e < 5.0 {
            pooled_o += o as f64;
            pooled_e += e;
        } else {
            stat += (o as f64 - e).powi(2) / e;
            cells += 1;
        }
    }
    if pooled_e > 0.0 {
        stat += (pooled_o - pooled_e).powi(2) / pooled_e;
        cells += 1;
    }
    chi2_survival(stat, (cells - 1) as f64)
}

/// At four contexts, the frequency with which `sample` picks each light over 400 000 draws
/// agrees with `pmf` by Pearson's χ², and the remainder of `u` it returns is uniform over 20
/// bins: each test at α = 0.01 with Šidák's correction over the eight.
#[test]
fn the_pmf_is_the_frequency_with_which_sampling_picks_each_light() {
    let lights = many_lights(5, 0.7, true);
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let alpha = 1.0 - 0.99f64.powf(1.0 / 8.0);
    let mut rng = Rng::new(23, 9);
    let n = 400_000u64;
    for _ in 0..4 {
        let ctx = random_context(&mut rng);
        // The last cell counts the draws that find no light.
        let mut counts = vec![0u64; lights.len() + 1];
        let mut rest_bins = vec![0u64; 20];
        for _ in 0..n {
            let Some((i, _, rest)) = sampler.sample(&ctx, rng.uniform()) else {
                counts[lights.len()] += 1;
                continue;
            };
            counts[i] += 1;
            rest_bins[((rest * 20.0) as usize).min(19)] += 1;
        }
        let mut expected: Vec<f64> = (0..lights.len()).map(|i| sampler.pmf(&ctx, i) as f64 * n as f64).collect();
        expected.push((n as f64 - expected.iter().sum::<f64>()).max(0.0));
        let p = chi2_p_value(&counts, &expected);
        assert!(p > alpha, "light choice at {ctx:?}: p = {p}");
        let found = n - counts[lights.len()];
        let p_rest = chi2_p_value(&rest_bins, &[found as f64 / 20.0; 20]);
        assert!(p_rest > alpha, "remainder of u at {ctx:?}: p = {p_rest}");
    }
}

/// Two equal point lights seen from a point in a medium: the root's children are the two
/// leaves, each of importance Φ/d², so the nearer light is picked with probability
/// (1/d₁²) / (1/d₁² + 1/d₂²).
#[test]
fn the_nearer_of_two_equal_point_lights_is_picked_by_inverse_square_distance() {
    let lights = [
        Light::Point(PointLight::new(Vec3::new(0.0, 0.0, 0.0), white(), 1.0)),
        Light::Point(PointLight::new(Vec3::new(4.0, 0.0, 0.0), white(), 1.0)),
    ];
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let ctx = LightSampleContext::medium(Vec3::new(0.5, 0.0, 0.0));
    let (d1, d2) = (0.5f32, 3.5f32);
    let expected = (1.0 / (d1 * d1)) / (1.0 / (d1 * d1) + 1.0 / (d2 * d2));
    let got = sampler.pmf(&ctx, 0);
    assert!((got - expected).abs() < 1e-5, "{got} vs {expected}");
    assert!((sampler.pmf(&ctx, 1) - (1.0 - expected)).abs() < 1e-5);
}

/// A point behind a one-sided triangle (whose front faces +z, away from it) and in front of
/// another: the first is never picked and its pmf is 0; the other takes everything.
#[test]
fn a_light_facing_away_from_the_point_is_never_picked() {
    let away = [Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0)];
    let toward = [Vec3::new(3.0, 0.0, 1.0), Vec3::new(3.0, 1.0, 1.0), Vec3::new(4.0, 0.0, 1.0)];
    let lights = [triangle(away, 1.0, false), triangle(toward, 1.0, false)];
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let ctx = LightSampleContext::surface(Vec3::new(1.0, 0.3, -2.0), Vec3::Z);
    assert_eq!(sampler.pmf(&ctx, 0), 0.0);
    assert_eq!(sampler.pmf(&ctx, 1), 1.0);
    let mut rng = Rng::new(1, 1);
    for _ in 0..10_000 {
        assert_eq!(sampler.sample(&ctx, rng.uniform()).map(|s| s.0), Some(1));
    }
}

/// Lights at infinity are picked apart from the tree, each with probability 1/(n_∞ + 1); with
/// no bounded light, they share everything.
#[test]
fn lights_at_infinity_share_one_over_their_number_plus_one() {
    let lights = many_lights(7, 0.7, true);
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let ctx = LightSampleContext::medium(Vec3::ZERO);
    let n = lights.len();
    assert_eq!(sampler.pmf(&ctx, n - 1), 1.0 / 3.0);
    assert_eq!(sampler.pmf(&ctx, n - 2), 1.0 / 3.0);
    let only = [Light::UniformInfinite(UniformInfiniteLight { spectrum: white(), scale: 1.0 })];
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &only, 10.0);
    assert_eq!(sampler.pmf(&ctx, 0), 1.0);
    assert_eq!(sampler.sample(&ctx, 0.7).map(|s| (s.0, s.1)), Some((0, 1.0)));
    let none = LightSampler::new(LightSamplerKind::Bvh, &[], 10.0);
    assert!(none.sample(&ctx, 0.5).is_none());
}

/// Many lights on one spot (equal centroids) build a tree by halving, still exact.
#[test]
fn coincident_lights_still_sum_to_one() {
    let lights: Vec<Light> =
        (0..37).map(|k| Light::Point(PointLight::new(Vec3::ONE, white(), 1.0 + k as f32))).collect();
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let ctx = LightSampleContext::surface(Vec3::ZERO, Vec3::X);
    let sum: f32 = (0..lights.len()).map(|i| sampler.pmf(&ctx, i)).sum();
    assert!((sum - 1.0).abs() < 1e-5, "{sum}");
    // Importance is proportional to flux at a common position: light k has (1 + k)/Σ.
    let total: f32 = (1..=37).map(|k| k as f32).sum();
    for (k, _) in lights.iter().enumerate() {
        let expected = (1.0 + k as f32) / total;
        assert!((sampler.pmf(&ctx, k) - expected).abs() < 1e-5 * 37.0, "{k}");
    }
}

/// `many_lights` and 20 axis-aligned rectangles, each two triangles with the same box and
/// normal, so that the tree has nodes whose children differ only in flux.
fn lights_with_rectangles(seed: u64) -> Vec<Light> {
    let mut lights = many_lights(seed, 0.7, true);
    let mut rng = Rng::new(seed, 2);
    for k in 0..20 {
        let c = in_box(&mut rng, 5.0);
        let (a, b) = (0.1 + rng.uniform(), 0.1 + rng.uniform());
        let (e1, e2) = match k % 3 {
            0 => (Vec3::X * a, Vec3::Y * b),
            1 => (Vec3::Z * a, Vec3::X * b),
            _ => (Vec3::Y * a, Vec3::Z * b),
        };
        let two_sided = k % 4 == 0;
        let scale = 0.1 + 10.0 * rng.uniform();
        lights.insert(k, triangle([c, c + e1, c + e1 + e2], scale, two_sided));
        lights.insert(k + 1, triangle([c, c + e1 + e2, c + e2], scale, two_sided));
    }
    lights
}

/// The pmf by pbrt-v4's definition: the product, from the root to the light's leaf, of each
/// choice's importance over the sum of both children's, every importance evaluated (and a root
/// that is a leaf checked for positive importance).
fn pmf_by_importances(s: &BvhLightSampler, ctx: &LightSampleContext, light: usize) -> f64 {
    let n_inf = s.infinite.len();
    let mut pmf = 1.0 - n_inf as f64 / (n_inf + 1) as f64;
    let mut index = s.leaf_of[light] as usize;
    if index == 0 {
        return if s.nodes[0].bounds.importance(ctx.p, ctx.n) > 0.0 { pmf } else { 0.0 };
    }
    while index != 0 {
        let parent = s.nodes[index].parent as usize;
        let second = s.nodes[parent].child_or_light as usize;
        let c0 = s.nodes[parent + 1].bounds.importance(ctx.p, ctx.n) as f64;
        let c1 = s.nodes[second].bounds.importance(ctx.p, ctx.n) as f64;
        if c0 + c1 == 0.0 {
            return 0.0;
        }
        pmf *= if index == second { c1 } else { c0 } / (c0 + c1);
        index = parent;
    }
    pmf
}

/// Where two children differ only in flux the tree takes their flux ratio instead of evaluating
/// both importances: the pmfs are still those of evaluating every importance, and sampling
/// reports them, at points around, behind and inside the rectangles.
#[test]
fn children_that_differ_only_in_flux_are_chosen_by_their_flux_ratio() {
    let lights = lights_with_rectangles(11);
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let LightSampler::Bvh(tree) = &sampler else { unreachable!() };
    let split = tree.nodes.iter().filter(|n| n.flux_split.is_some()).count();
    assert!(split >= 20, "{split} nodes split by flux");
    let mut rng = Rng::new(29, 4);
    for _ in 0..500 {
        let ctx = random_context(&mut rng);
        for i in 0..lights.len() - 2 {
            let (got, expected) = (sampler.pmf(&ctx, i) as f64, pmf_by_importances(tree, &ctx, i));
            assert!(
                (got - expected).abs() <= 1e-5 * expected,
                "light {i} at {ctx:?}: pmf {got}, by importances {expected}"
            );
        }
        for _ in 0..20 {
            let Some((i, pmf, _)) = sampler.sample(&ctx, rng.uniform()) else { continue };
            let expected = sampler.pmf(&ctx, i);
            assert!((pmf - expected).abs() <= 1e-5 * expected, "light {i}: sampled pmf {pmf}, pmf() {expected}");
        }
    }
}

/// One rectangle of two triangles (the Cornell box's light): the root splits by flux, so
/// sampling evaluates one importance, the root's. Below the light, each triangle has 1/2; above
/// it (behind a one-sided light) none can be picked.
#[test]
fn one_rectangle_of_two_triangles_is_split_evenly_where_it_shines() {
    let (c, e1, e2) = (Vec3::new(-1.0, 2.0, -1.0), Vec3::Z * 2.0, Vec3::X * 1.5);
    let lights = [triangle([c, c + e1, c + e1 + e2], 3.0, false), triangle([c, c + e1 + e2, c + e2], 3.0, false)];
    let sampler = LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0);
    let LightSampler::Bvh(tree) = &sampler else { unreachable!() };
    assert_eq!(tree.nodes[0].flux_split, Some([0.5, 0.5]));
    // The triangles face −y: (e1 × (e1 + e2)) points along Z × X = Y... reversed by the order.
    let below = LightSampleContext::surface(Vec3::new(0.0, 0.0, 0.3), Vec3::Y);
    let above = LightSampleContext::surface(Vec3::new(0.0, 4.0, 0.3), -Vec3::Y);
    let (lit, dark) = if lights_face_down(&lights) { (below, above) } else { (above, below) };
    assert_eq!((sampler.pmf(&lit, 0), sampler.pmf(&lit, 1)), (0.5, 0.5));
    assert_eq!(sampler.sample(&lit, 0.3), Some((0, 0.5, 0.6)));
    assert_eq!((sampler.pmf(&dark, 0), sampler.pmf(&dark, 1)), (0.0, 0.0));
    assert_eq!(sampler.sample(&dark, 0.3), None);
}

fn lights_face_down(lights: &[Light]) -> bool {
    matches!(&lights[0], Light::Area(a) if a.n.y < 0.0)
}

/// pbrt-v4's `buildBVH` never cuts after the first of its 12 buckets. Three tiny lights with
/// centroids at x = 0, 0.1 and 1 fall in buckets 0, 1 and 11; the first carries 10⁴ times the
/// others' flux, which makes the cut after bucket 0 ({0} | {0.1, 1}) the cheapest by the cost
/// Φ M_Ω K_r A, but pbrt-v4 cuts after bucket 1 or later: {0, 0.1} | {1}. The probability of
/// the light at x = 1 at a point in a medium is then, the lights emitting over every direction
/// (cos θ' = 1), Φ₂/d₂² / (Φ₀₁/d₀₁² + Φ₂/d₂²), d the distance to each node's box centre;
/// the other tree would make it (2/d₁₂²)/(10⁴/d₀² + 2/d₁₂²) · (1/d₂²)/(1/d₁² + 1/d₂²).
#[test]
fn the_tree_is_never_cut_after_the_first_bucket() {
    let tiny = |x: f32, phi: f32| {
        let c = Vec3::new(x, 0.0, 0.0);
        let bounds = crate::geometry::Bounds3 { min: c - Vec3::splat(0.01), max: c + Vec3::splat(0.01) };
        let b = super::LightBounds { bounds, w: Vec3::Z, phi, cos_theta_o: -1.0, cos_theta_e: 0.0, two_sided: false };
        super::BoundedLight { bounds: Some(b), infinite: false }
    };
    let sampler = BvhLightSampler::new(&[tiny(0.0, 1.0e4), tiny(0.1, 1.0), tiny(1.0, 1.0)]);
    let p = Vec3::new(0.5, 0.0, 3.0);
    let inv_d2 = |x: f64| 1.0 / (p.as_dvec3() - glam::DVec3::new(x, 0.0, 0.0)).length_squared();
    let (near, far) = ((1.0e4 + 1.0) * inv_d2(0.05), inv_d2(1.0));
    let want = far / (near + far);
    let got = sampler.pmf(p, Vec3::ZERO, 2) as f64;
    assert!((got - want).abs() < 1e-4 * want, "light at x = 1: {got}, pbrt-v4's tree gives {want}");
}

/// `many_lights` with two emissive meshes of one shared spectrum each (6,400 triangles, past
/// the size from which subtrees are built in parallel): a curved patch (every
/// triangle's normal its own) and a flat, subdivided square (every normal the same).
fn lights_with_meshes(seed: u64) -> Vec<Light> {
    let mut lights = many_lights(seed, 0.5, true);
    let spectra = [white(), Arc::new(Spectrum::blackbody(4000.0))];
    let mesh = |corner: [Vec3; 4], scale: f32, spectrum: &Arc<Spectrum>| {
        let corner = corner.map(|c| c * scale);
        Light::Area(AreaLight {
            p: [corner[0], corner[1], corner[2]],
            n: (corner[1] - corner[0]).cross(corner[2] - corner[0]).normalize(),
            area: 0.5 * (corner[1] - corner[0]).cross(corner[2] - corner[0]).length(),
            spectrum: spectrum.clone(),
            scale: 2.0,
            two_sided: false,
            image: None,
        })
    };
    let k = 40;
    for i in 0..k {
        for j in 0..k {
            // A piece of the sphere of radius 4 about the origin, facing inward.
            let at = |a: usize, b: usize| {
                let (t, f) = (0.3 + 0.8 * a as f32 / k as f32, 0.2 + 1.0 * b as f32 / k as f32);
                Vec3::new(t.sin() * f.cos(), t.cos(), t.sin() * f.sin())
            };
            let q = [at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)];
            lights.push(mesh([q[0], q[1], q[2], q[3]], 4.0, &spectra[1]));
            lights.push(mesh([q[1], q[3], q[2], q[0]], 4.0, &spectra[1]));
            // A square of side 2 at y = 3, facing down.
            let at = |a: usize, b: usize| Vec3::new(a as f32 / k as f32 - 0.5, 1.5, b as f32 / k as f32 - 0.5);
            let q = [at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)];
            lights.push(mesh([q[0], q[1], q[2], q[3]], 2.0, &spectra[0]));
            lights.push(mesh([q[1], q[3], q[2], q[0]], 2.0, &spectra[0]));
        }
    }
    lights
}

/// The tree is the same however many threads build it: subtrees built in parallel fill the
/// slots a serial build would, so every light keeps its probability bit for bit.
#[test]
fn a_parallel_build_gives_the_serial_builds_probabilities() {
    let lights = lights_with_meshes(17);
    let build = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| LightSampler::new(LightSamplerKind::Bvh, &lights, 10.0))
    };
    let (serial, parallel) = (build(1), build(4));
    let points = [
        LightSampleContext::surface(Vec3::new(0.0, -1.0, 0.0), Vec3::Y),
        LightSampleContext::surface(Vec3::new(2.0, 0.5, 1.0), Vec3::new(-1.0, 0.2, 0.3).normalize()),
        LightSampleContext::medium(Vec3::new(-3.0, 2.0, 4.0)),
    ];
    for ctx in &points {
        for i in 0..lights.len() {
            assert_eq!(serial.pmf(ctx, i).to_bits(), parallel.pmf(ctx, i).to_bits(), "light {i}");
        }
    }
}
