//! pbrt-v4's square equal-area environment maps: χ² of their importance sampling on the sphere
//! and over the square, the sampled pdf against `pdf_li` and its normalisation, pbrt-v4's
//! "illuminance" (twice the requested irradiance, the figure pbrt-v4 renders) next to the
//! uniform sky's, and the compat scene `envmap.pbrt` against pbrt-v4's own render. (E = πL from
//! a constant map, both layouts: `envmap.rs`.)

use crate::common::tmpdir;
use glam::{Mat3, Vec2, Vec3};
use prism::accel::AccelKind;
use prism::image::Image;
use prism::integrator::Integrator;
use prism::light::photometry::lumens_per_unit_y;
use prism::light::{EnvMapLight, MapLayout};
use prism::math::equal_area::{sphere_to_square, square_to_sphere};
use prism::math::PI;
use prism::measure::irradiance;
use prism::pbrt::parse_str;
use prism::sampling::chi2::{Chi2Test, Domain};
use prism::sampling::Rng;
use prism::spectrum::ColorSpace;
use std::path::Path;

/// An n × n equal-area map whose texel (x, y) holds `f` of the direction of its centre.
pub fn equal_area_map(n: u32, f: impl Fn(u32, u32, Vec3) -> [f32; 3]) -> Image {
    let mut img = Image::new(n, n, 3);
    for y in 0..n {
        for x in 0..n {
            let d = square_to_sphere(Vec2::new((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32));
            let o = ((y * n + x) * 3) as usize;
            img.data[o..o + 3].copy_from_slice(&f(x, y, d));
        }
    }
    img
}

/// A sky: blue-white gradient above the horizon, brown ground, a warm sun of 2 × 2 texels
/// 300 times the sky.
fn sky(n: u32) -> Image {
    equal_area_map(n, |x, y, d| {
        if (n / 2 + 3..n / 2 + 5).contains(&x) && (n / 2 - 6..n / 2 - 4).contains(&y) {
            [300.0, 270.0, 200.0]
        } else if d.z > 0.0 {
            [0.25 + 0.6 * (1.0 - d.z), 0.45 + 0.45 * (1.0 - d.z), 1.0]
        } else {
            [0.12, 0.09, 0.06]
        }
    })
}

fn light(img: &Image, rot: Mat3) -> EnvMapLight {
    let l = EnvMapLight::new(img, rot, 1.0, ColorSpace::srgb());
    assert_eq!(l.layout(), MapLayout::EqualArea);
    l
}

#[test]
fn equal_area_sampling_matches_its_density_chi2_on_the_sphere() {
    // Smooth maps only: the cells' expected counts come from quadrature of the pdf over
    // (θ, φ) cells, which a 10³ step between texels would defeat (sharp maps: the next test).
    let gradient = equal_area_map(32, |_, _, d| [1.0 + 0.8 * d.x, 0.5 + d.z * d.z, 0.3 + 0.2 * d.y]);
    let rot = Mat3::from_rotation_x(0.7) * Mat3::from_rotation_z(0.3);
    let cases = [("gradient", light(&gradient, Mat3::IDENTITY)), ("gradient rotated", light(&gradient, rot))];
    for (what, l) in &cases {
        let t =
            Chi2Test { sample_count: 300_000, test_count: cases.len(), domain: Domain::SPHERE, ..Chi2Test::default() };
        let r = t.run(|_, u| l.sample_direction(u).map(|(d, _)| d), |d| l.pdf_li(d));
        assert!(r.passed, "{what}: {r}");
    }
}

/// Pearson's χ² of sampled directions, mapped back to the square, against each texel's
/// probability pdf_li(centre) · 4π/n² (the density is constant over a texel, so no
/// quadrature), cells expected below 5 pooled; the p-value.
fn texel_chi2(l: &EnvMapLight, n: u32, samples: usize) -> f64 {
    let cells = (n * n) as usize;
    let mut observed = vec![0.0f64; cells];
    let mut rng = Rng::new(23, 1);
    for _ in 0..samples {
        let (d, _) = l.sample_direction(Vec2::new(rng.uniform(), rng.uniform())).unwrap();
        let p = sphere_to_square(d);
        let (x, y) = (((p.x * n as f32) as u32).min(n - 1), ((p.y * n as f32) as u32).min(n - 1));
        observed[(y * n + x) as usize] += 1.0;
    }
    let expected: Vec<f64> = (0..cells)
        .map(|i| {
            let centre = Vec2::new(((i as u32 % n) as f32 + 0.5) / n as f32, ((i as u32 / n) as f32 + 0.5) / n as f32);
            (l.pdf_li(square_to_sphere(centre)) * 4.0 * PI) as f64 / cells as f64 * samples as f64
        })
        .collect();
    let total: f64 = expected.iter().sum();
    assert!((total / samples as f64 - 1.0).abs() < 1e-4, "texel probabilities sum to {}", total / samples as f64);
    let (mut stat, mut dof, mut pooled_e, mut pooled_o) = (0.0, 0usize, 0.0, 0.0);
    for (e, o) in expected.iter().zip(&observed) {
        if *e < 5.0 {
            pooled_e += e;
            pooled_o += o;
        } else {
            stat += (o - e).powi(2) / e;
            dof += 1;
        }
    }
    if pooled_e > 0.0 {
        stat += (pooled_o - pooled_e).powi(2) / pooled_e;
        dof += 1;
    }
    prism::sampling::chi2::chi2_survival(stat, (dof - 1) as f64)
}

#[test]
fn equal_area_sampling_matches_its_density_chi2_per_texel() {
    let n = 40;
    let spots =
        equal_area_map(n, |x, y, _| if (x, y) == (9, 30) || (x, y) == (20, 20) { [300.0; 3] } else { [0.3; 3] });
    let rot = Mat3::from_rotation_y(2.2);
    let cases = [("bright spots", light(&spots, Mat3::IDENTITY)), ("sky", light(&sky(n), Mat3::IDENTITY))];
    // Šidák-corrected α = 0.01 over the two cases.
    let significance = 1.0 - 0.99f64.powf(1.0 / cases.len() as f64);
    for (what, l) in &cases {
        let p = texel_chi2(l, n, 300_000);
        assert!(p >= significance, "{what}: p = {p:.3e}");
    }
    // The test can fail: samples rotated away from the texels whose probabilities it expects.
    assert!(texel_chi2(&light(&spots, rot), n, 20_000) < 1e-6, "a rotated map must not pass in light space");
}

#[test]
fn sampled_pdf_is_pdf_li_and_integrates_to_one() {
    let rot = Mat3::from_rotation_y(-1.1) * Mat3::from_rotation_z(2.0);
    let l = light(&sky(64), rot);
    let mut rng = Rng::new(17, 0);
    for _ in 0..20_000 {
        let (d, pdf) = l.sample_direction(Vec2::new(rng.uniform(), rng.uniform())).unwrap();
        let again = l.pdf_li(d);
        assert!((again - pdf).abs() <= 1e-3 * pdf, "{d}: sampled pdf {pdf}, pdf_li {again}");
    }
    // ∫ pdf_li dω = 1: the mean of 4π pdf_li over uniform directions, within 4σ.
    let n = 200_000;
    let values: Vec<f64> = (0..n)
        .map(|_| {
            let d = prism::sampling::warp::sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            (4.0 * PI * l.pdf_li(d)) as f64
        })
        .collect();
    let mean = values.iter().sum::<f64>() / n as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let se = (var / n as f64).sqrt();
    assert!((mean - 1.0).abs() < 4.0 * se, "∫ pdf dω = {mean} ± {se}");
}

/// Irradiance, in film units Y, of a patch facing +z under the lights of `world` (files
/// relative to `dir`), with its standard error.
fn upward_y(world: &str, dir: &Path) -> (f64, f64) {
    let (e, se, warnings) = upward_y_warned(world, dir);
    assert!(warnings.is_empty(), "{warnings:?}");
    (e, se)
}

/// [`upward_y`] and the scene's warnings.
fn upward_y_warned(world: &str, dir: &Path) -> (f64, f64, Vec<String>) {
    let opts = prism::pbrt::ParseOptions { base_dir: Some(dir.to_path_buf()), ..Default::default() };
    let (desc, mut warnings) = parse_str(&format!("Camera \"perspective\" WorldBegin\n{world}"), &opts).unwrap();
    let (b, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    let scene = b.build(AccelKind::Obvhs).unwrap();
    let integ = Integrator { max_depth: 1, ..Default::default() };
    let e = irradiance(&scene, &integ, Vec3::ZERO, Vec3::Z, 40_000, 9).illuminance;
    let k = lumens_per_unit_y() as f64;
    (e.mean / k, e.std_err / k, warnings.iter().map(|w| format!("{w:?}")).collect())
}

#[test]
fn illuminance_is_pbrt_v4s_twice_on_equal_area_maps_and_right_for_a_uniform_sky() {
    // pbrt-v4 at 5f7a606 renders "float illuminance" [π] on a diffuse 0.5 quad as 1.016 under a
    // constant 16 × 16 map and 0.500 under a uniform "L": the quad's radiance is 0.5 E/π, so
    // E = 2π · 1.016 and π. The 1.016 is π/2 over pbrt-v4's midpoint sum
    // (2π/256) Σ cos θ of the texel centres above the horizon, 1.5463 (16² texels), recomputed
    // here from the mapping's z = 1 − r² at each centre.
    let d = tmpdir("equal-area-illuminance");
    prism::image::write(&d.join("grey.exr"), &equal_area_map(16, |_, _, _| [0.3, 0.3, 0.3])).unwrap();
    let n = 16;
    let mut sum_cos = 0.0f64;
    for y in 0..n {
        for x in 0..n {
            let (u, v) = (2.0 * (x as f64 + 0.5) / n as f64 - 1.0, 2.0 * (y as f64 + 0.5) / n as f64 - 1.0);
            let inside = 1.0 - (u.abs() + v.abs());
            if inside > 0.0 {
                sum_cos += 1.0 - (1.0 - inside).powi(2);
            }
        }
    }
    let pbrt_k_e = 2.0 * std::f64::consts::PI / (n * n) as f64 * sum_cos;
    let quad = |e: f64| 0.5 * e / std::f64::consts::PI;
    let (e, se) = upward_y(r#"LightSource "infinite" "string filename" "grey.exr" "float illuminance" 3.14159265"#, &d);
    let expected = 0.5 * std::f64::consts::PI / pbrt_k_e;
    assert!((expected - 1.016).abs() < 5e-4, "pbrt-v4's figure {expected}");
    assert!((quad(e) - expected).abs() < 4.0 * quad(se), "map: quad {} ± {} vs {expected}", quad(e), quad(se));
    let (e, se) = upward_y(r#"LightSource "infinite" "float illuminance" 3.14159265"#, &d);
    assert!((quad(e) - 0.5).abs() < 4.0 * quad(se), "uniform: quad {} ± {} vs 0.5", quad(e), quad(se));
    // prism's "lux" is the true illuminance.
    let (e, se) = upward_y(r#"LightSource "infinite" "string filename" "grey.exr" "float lux" 1000"#, &d);
    let (lux, lux_se) = (e * lumens_per_unit_y() as f64, se * lumens_per_unit_y() as f64);
    assert!((lux - 1000.0).abs() < 4.0 * lux_se, "lux: {lux} ± {lux_se}");
}

#[test]
fn illuminance_takes_an_openexr_maps_channels_in_the_files_order_as_pbrt_v4() {
    // pbrt-v4 sums lum[c] · value[c] over the first three channels in the order the file lists
    // them, and OpenEXR lists channels by name: B, G, R, or A, B, G with alpha. So a pure red
    // EXR map is normalised by blue's luminance weight and comes out Y_r / Y_b times as bright
    // as the same map in a PNG (R, G, B). sRGB's luminance row (IEC 61966-2-1): 0.2126,
    // 0.7152, 0.0722. The same directions are sampled for both maps, so the ratio is exact.
    let d = tmpdir("equal-area-channel-order");
    let (y_r, y_g, y_b) = (0.2126, 0.7152, 0.0722);
    let red = equal_area_map(16, |_, _, _| [1.0, 0.0, 0.0]);
    prism::image::write(&d.join("red.exr"), &red).unwrap();
    prism::image::write(&d.join("red.png"), &red).unwrap();
    let world = |f: &str| format!(r#"LightSource "infinite" "string filename" "{f}" "float illuminance" 3.14159265"#);
    let (exr, _, warned) = upward_y_warned(&world("red.exr"), &d);
    let (png, _) = upward_y(&world("red.png"), &d);
    assert!(exr > 0.0 && png > 0.0);
    let want = y_r / y_b;
    assert!((exr / png / want - 1.0).abs() < 2e-3, "EXR / PNG {} vs {want}", exr / png);
    assert!(warned.iter().any(|w| w.contains("file's order (B, G, R)")), "{warned:?}");
    // With alpha: (R, G, B, A) = (1, ½, 0, 1) is weighed as (A, B, G), against (B, G, R) for the
    // same colour without alpha.
    let mut rgba = prism::image::Image::new(16, 16, 4);
    rgba.data.chunks_mut(4).for_each(|t| t.copy_from_slice(&[1.0, 0.5, 0.0, 1.0]));
    prism::image::write(&d.join("rgba.exr"), &rgba).unwrap();
    prism::image::write(&d.join("orange.exr"), &equal_area_map(16, |_, _, _| [1.0, 0.5, 0.0])).unwrap();
    let (with_alpha, _, warned) = upward_y_warned(&world("rgba.exr"), &d);
    let (without, _, _) = upward_y_warned(&world("orange.exr"), &d);
    let want = (0.5 * y_g + y_b) / (y_r + 0.5 * y_b);
    assert!((with_alpha / without / want - 1.0).abs() < 2e-3, "RGBA / RGB {} vs {want}", with_alpha / without);
    assert!(warned.iter().any(|w| w.contains("(A, B, G)")), "{warned:?}");
}

/// pbrt-v4's "illuminance" sum over an equal-area map, written from its definition: each
/// texel centre above the horizon, rows outer, its three channels weighed by sRGB's luminance
/// row (IEC 61966-2-1) and cos θ = z = 1 − r², added one term at a time to an f32 (or, for
/// comparison, an f64) accumulator, times 2π / texels.
fn pbrt_v4_sum<T: Copy + Into<f64> + std::ops::AddAssign + From<f32>>(img: &Image) -> f64 {
    let n = img.width as usize;
    let weights = [0.2126f32, 0.7152, 0.0722];
    let mut sum = T::from(0.0);
    for y in 0..n {
        for x in 0..n {
            let (u, v) = (2.0 * (x as f32 + 0.5) / n as f32 - 1.0, 2.0 * (y as f32 + 0.5) / n as f32 - 1.0);
            let inside = 1.0 - (u.abs() + v.abs());
            if inside > 0.0 {
                let z = 1.0 - (1.0 - inside) * (1.0 - inside);
                for (value, weight) in img.data[(y * n + x) * 3..][..3].iter().zip(weights) {
                    sum += T::from(value * weight * z);
                }
            }
        }
    }
    sum.into() * 2.0 * std::f64::consts::PI / (n * n) as f64
}

#[test]
fn pbrt_v4_illuminance_sum_is_half_the_midpoint_rule() {
    // A constant white 16² map: (2π/256) Σ (1 − r²) over the centres inside the diamond,
    // 1.54625 (π/2 less the midpoint rule's error), where the true integral is π.
    let white = equal_area_map(16, |_, _, _| [1.0; 3]);
    let k_e = prism::light::image_upper_hemisphere_y(&white, ColorSpace::srgb(), Some([0, 1, 2]));
    assert!((k_e - 1.546_253).abs() < 1e-5, "{k_e}");
    assert!((k_e - pbrt_v4_sum::<f64>(&white)).abs() < 1e-5);
}

#[test]
fn pbrt_v4_illuminance_sum_rounds_as_its_single_precision_accumulator() {
    // A 2048² sky with a sun of 3 × 3 texels: once the accumulator is 2²⁴ times a term, the
    // term is lost, so pbrt-v4's f32 sum falls over 1 % below the exact sum of the same terms
    // and its images are that much brighter. prism's k_e is pbrt-v4's.
    let n = 2048;
    let img = equal_area_map(n, |x, y, d| {
        let (dx, dy) = (x as i64 - (n as i64) * 3 / 10, y as i64 - (n as i64) * 4 / 10);
        let sun = if dx * dx + dy * dy < 9 { 2e4 } else { 0.0 };
        [0.1, 0.3, 1.0].map(|c| c * (0.5 + d.z.max(0.0)) + sun)
    });
    let (single, exact) = (pbrt_v4_sum::<f32>(&img), pbrt_v4_sum::<f64>(&img));
    assert!(single < 0.99 * exact, "rounding loss {}", single / exact);
    let k_e = prism::light::image_upper_hemisphere_y(&img, ColorSpace::srgb(), Some([0, 1, 2]));
    assert!((k_e / single - 1.0).abs() < 1e-3, "prism {k_e}, pbrt-v4 {single}, exact {exact}");
}
