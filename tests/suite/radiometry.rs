//! Radiometry in SI units, checked against closed forms (PBR 4th ed. §4.1–4.2) with the
//! measuring instrument (full integrator, mean ± standard error). Tolerances are 3 standard
//! errors; estimators with zero variance (flat spectra, one delta light) get a 1e-4 relative
//! allowance for f32 rounding instead.

use crate::common::test_settings;
use glam::{Mat4, Vec3};
use prism::accel::AccelKind;
use prism::camera::Camera;
use prism::geometry::shapes::{icosphere, quad};
use prism::geometry::Mesh;
use prism::integrator::{DirectStrategy, Integrator, Stats, UNBOUNDED_DEPTH};
use prism::light::photometry::{lumens_per_unit_y, radiant_flux_from_lumens};
use prism::light::{AreaLight, DistantLight, Light, PointLight, SpotFalloff, SpotLight, UniformInfiniteLight};
use prism::material::Material;
use prism::math::PI;
use prism::measure::{irradiance, Estimate};
use prism::sampling::Sampler;
use prism::scene::{Emission, Scene, SceneBuilder};
use prism::spectrum::{ColorSpace, SampledWavelengths, Spectrum};
use std::sync::Arc;

fn builder() -> SceneBuilder {
    let mut b = SceneBuilder::new();
    b.set_camera(Camera::look_at(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y), 45.0);
    b
}

fn build(b: SceneBuilder) -> Scene {
    b.build(AccelKind::Obvhs).unwrap()
}

fn assert_close(what: &str, e: Estimate, expected: f64) {
    let tol = 3.0 * e.std_err + 1e-4 * expected.abs();
    assert!((e.mean - expected).abs() <= tol, "{what}: measured {} ± {} vs closed form {expected}", e.mean, e.std_err);
}

fn direct() -> Integrator {
    Integrator { max_depth: 1, ..Default::default() }
}

#[test]
fn point_light_inverse_square_and_lambert_cosine() {
    let flux = 100.0; // W over 360–830 nm
    for spectrum in [Spectrum::constant(1.0), Spectrum::blackbody(3000.0)] {
        let mut b = builder();
        b.add_light(Light::Point(PointLight::with_flux(Vec3::ZERO, Arc::new(spectrum.clone()), flux)));
        let scene = build(b);
        for (r, theta_deg) in [(1.0f32, 0.0f32), (2.5, 0.0), (2.0, 60.0), (3.0, 80.0)] {
            let p = Vec3::new(0.0, 0.0, r);
            let t = theta_deg.to_radians();
            let n = Vec3::new(t.sin(), 0.0, -t.cos()); // tilted away from the light by θ
            let m = irradiance(&scene, &direct(), p, n, 20_000, 1);
            let expected = flux as f64 / (4.0 * std::f64::consts::PI * (r * r) as f64) * (t.cos() as f64);
            assert_close(&format!("point r={r} θ={theta_deg}"), m.irradiance, expected);
        }
    }
}

/// Flux through a sphere of radius `r` around `centre`: Φ = ∫ E dA, by measuring E (normal toward
/// the centre) at uniformly distributed points, one estimate each; `weight(E, λ)` turns a spectral
/// estimate into the quantity integrated (W/m², or lux for luminous flux).
fn sphere_integral(
    scene: &Scene,
    centre: Vec3,
    r: f32,
    n: u64,
    pixel: (u32, u32),
    seed: u64,
    weight: impl Fn(&prism::spectrum::SampledSpectrum, &SampledWavelengths) -> f64,
) -> Estimate {
    let integ = direct();
    let mut sampler = Sampler::independent();
    let mut stats = Stats::default();
    let (mut s, mut s2) = (0.0f64, 0.0f64);
    for i in 0..n {
        sampler.start_pixel_sample(pixel, i, seed);
        let u = sampler.get_2d();
        let z = 1.0 - 2.0 * u.x;
        let rr = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let dir = Vec3::new(rr * phi.cos(), rr * phi.sin(), z);
        let mut w = SampledWavelengths::sample_uniform(sampler.get_1d());
        let e = integ.irradiance(scene, centre + dir * r, -dir, &mut w, &mut sampler, &mut stats);
        let v = 4.0 * std::f64::consts::PI * (r * r) as f64 * weight(&e, &w);
        s += v;
        s2 += v * v;
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean) * n as f64 / (n - 1) as f64;
    Estimate { mean, std_err: (var / n as f64).sqrt() }
}

/// Radiant flux [W] through a sphere (∫ over 360–830 nm).
fn flux_through_sphere(scene: &Scene, centre: Vec3, r: f32, n: u64) -> Estimate {
    sphere_integral(scene, centre, r, n, (1, 2), 7, |e, w| e.safe_div(w.pdf()).average() as f64)
}

#[test]
fn warn_spotlight_flux_is_two_pi_i0_over_s_plus_one() {
    let i0 = 5.0f32;
    for s in [0.0f32, 1.0, 10.0, 100.0] {
        let mut b = builder();
        let spot = SpotLight::new(
            Vec3::ZERO,
            Vec3::new(0.3, 1.0, 0.2),
            Arc::new(Spectrum::constant(1.0)),
            i0,
            SpotFalloff::Warn { exponent: s },
        );
        b.add_light(Light::Spot(spot));
        let scene = build(b);
        let phi = flux_through_sphere(&scene, Vec3::ZERO, 3.0, 200_000);
        // Warn's lobe: Φ = 2π I₀/(s+1) per nm, × 470 nm of flat spectrum.
        let expected = 2.0 * std::f64::consts::PI * i0 as f64 / (s as f64 + 1.0) * 470.0;
        assert_close(&format!("Warn s={s}"), phi, expected);
    }
}

#[test]
fn pbrt_spotlight_and_area_light_given_power_emit_that_flux() {
    let power = 42.0f32;
    let bb = Spectrum::blackbody(4000.0);
    // pbrt-v4 cone spotlight with `power`.
    let mut b = builder();
    let falloff = SpotFalloff::Cone { cos_start: 20f32.to_radians().cos(), cos_end: 35f32.to_radians().cos() };
    b.add_light(Light::Spot(SpotLight::with_flux(Vec3::ZERO, Vec3::X, Arc::new(bb.clone()), power, falloff)));
    let phi = flux_through_sphere(&build(b), Vec3::ZERO, 2.0, 100_000);
    assert_close("pbrt spot power", phi, power as f64);

    // An area light with `power` on a scaled, rotated, translated mesh (one-sided).
    let xf = Mat4::from_translation(Vec3::new(0.3, -0.2, 0.1))
        * Mat4::from_rotation_x(0.6)
        * Mat4::from_scale(Vec3::new(0.7, 1.0, 0.3));
    let mesh = quad(Vec3::new(-0.5, -0.5, 0.0), Vec3::X, Vec3::Y).transformed(&xf);
    let scale = AreaLight::scale_for_flux(power, &bb, mesh.area(), false);
    let mut b = builder();
    let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));
    b.add_mesh(mesh, black, Some(Emission { spectrum: bb, scale, two_sided: false }));
    let phi = flux_through_sphere(&build(b), Vec3::new(0.3, -0.2, 0.1), 2.0, 100_000);
    assert_close("area power", phi, power as f64);
}

/// Irradiance at a point on the axis of a parallel a×b rectangle at distance c of radiance L:
/// E = π L F, with F four times the corner view factor
/// F_c = 1/(2π) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/2c, Y = b/2c.
fn rectangle_irradiance(l: f64, a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / 2.0 / c, b / 2.0 / c);
    let fc = (x / (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
        + y / (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan())
        / (2.0 * std::f64::consts::PI);
    std::f64::consts::PI * l * 4.0 * fc
}

#[test]
fn lambertian_emitter_irradiance_matches_view_factor() {
    let (a, bb, c, l) = (2.0f32, 1.0f32, 1.5f32, 3.0f32);
    for strategy in [DirectStrategy::Mis, DirectStrategy::LightOnly, DirectStrategy::BsdfOnly] {
        let mut b = builder();
        let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));
        // Emitter in the plane z = c facing −z (toward the sensor at the origin).
        let mesh = quad(Vec3::new(-a / 2.0, -bb / 2.0, c), Vec3::new(0.0, bb, 0.0), Vec3::new(a, 0.0, 0.0));
        b.add_mesh(mesh, black, Some(Emission { spectrum: Spectrum::constant(1.0), scale: l, two_sided: false }));
        let scene = build(b);
        let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
        let m = irradiance(&scene, &integ, Vec3::ZERO, Vec3::Z, 100_000, 3);
        let expected = rectangle_irradiance(l as f64, a as f64, bb as f64, c as f64) * 470.0;
        assert_close(&format!("view factor ({strategy:?})"), m.irradiance, expected);
    }
}

/// The same emitter as one face of two triangles (a rectangular bilinear patch): one rectangle
/// light, sampled by solid angle with the cosine warp. It meets the view factor with every
/// strategy, and sampled from the light its estimate is far less noisy than the two triangles'
/// sampled by area (the warp leaves only the cosine's departure from bilinear).
#[test]
fn a_rectangular_face_is_one_rectangle_light_that_meets_the_view_factor_with_less_noise() {
    let (a, bb, c, l) = (2.0f32, 1.0f32, 1.5f32, 3.0f32);
    let expected = rectangle_irradiance(l as f64, a as f64, bb as f64, c as f64) * 470.0;
    for strategy in [DirectStrategy::Mis, DirectStrategy::LightOnly, DirectStrategy::BsdfOnly] {
        let mut std_errs = Vec::new();
        for one_face in [false, true] {
            let mut b = builder();
            let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));
            let mut mesh = quad(Vec3::new(-a / 2.0, -bb / 2.0, c), Vec3::new(0.0, bb, 0.0), Vec3::new(a, 0.0, 0.0));
            mesh.faces = one_face.then(|| vec![0, 0]);
            b.add_mesh(mesh, black, Some(Emission { spectrum: Spectrum::constant(1.0), scale: l, two_sided: false }));
            let scene = build(b);
            let rectangles = scene.lights().iter().filter(|l| matches!(l, Light::Rectangle(_))).count();
            assert_eq!((scene.lights().len(), rectangles), if one_face { (1, 1) } else { (2, 0) });
            let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
            let m = irradiance(&scene, &integ, Vec3::ZERO, Vec3::Z, 100_000, 3);
            assert_close(&format!("view factor ({strategy:?}, one face: {one_face})"), m.irradiance, expected);
            std_errs.push(m.irradiance.std_err);
        }
        eprintln!("{strategy:?}: standard error, two triangles {:.3e}, one rectangle {:.3e}", std_errs[0], std_errs[1]);
        if strategy == DirectStrategy::LightOnly {
            assert!(std_errs[1] < 0.5 * std_errs[0], "{strategy:?}: {std_errs:?}");
        }
    }
}

#[test]
fn distant_light_irradiance_follows_lambert() {
    let e0 = 2.0f32;
    let mut b = builder();
    let to_light = Vec3::new(0.0, 0.0, 1.0);
    b.add_light(Light::Distant(DistantLight { to_light, spectrum: Arc::new(Spectrum::constant(1.0)), scale: e0 }));
    let scene = build(b);
    for deg in [0.0f32, 30.0, 75.0] {
        let t = deg.to_radians();
        let m = irradiance(&scene, &direct(), Vec3::ZERO, Vec3::new(t.sin(), 0.0, t.cos()), 2_000, 4);
        assert_close(&format!("distant θ={deg}"), m.irradiance, (e0 * t.cos()) as f64 * 470.0);
    }
}

#[test]
fn uniform_environment_gives_pi_l() {
    let l = 0.5f32;
    for strategy in [DirectStrategy::Mis, DirectStrategy::LightOnly, DirectStrategy::BsdfOnly] {
        let mut b = builder();
        b.add_light(Light::UniformInfinite(UniformInfiniteLight {
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: l,
        }));
        let scene = build(b);
        let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
        let m = irradiance(&scene, &integ, Vec3::ZERO, Vec3::Y, 50_000, 5);
        assert_close(&format!("environment ({strategy:?})"), m.irradiance, (PI * l) as f64 * 470.0);
    }
}

#[test]
fn lambertian_reflector_radiance_is_rho_e_over_pi() {
    // A large diffuse plane of albedo ρ lit by a distant light of perpendicular irradiance E at
    // incidence θ; the camera sees radiance ρ E cos θ / π (flat spectra → Y is the radiance).
    let (rho, e0, theta) = (0.6f32, 3.0f32, 40f32.to_radians());
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::diffuse(Spectrum::constant(rho)));
    b.add_mesh(quad(Vec3::new(-50.0, 0.0, -50.0), Vec3::new(0.0, 0.0, 100.0), Vec3::new(100.0, 0.0, 0.0)), m, None);
    let to_light = Vec3::new(theta.sin(), theta.cos(), 0.0);
    b.add_light(Light::Distant(DistantLight { to_light, spectrum: Arc::new(Spectrum::constant(1.0)), scale: e0 }));
    b.set_camera(Camera::look_at(Vec3::new(0.0, 2.0, -2.0), Vec3::ZERO, Vec3::Y), 20.0);
    let scene = build(b);
    let s = test_settings((16, 16), 4, 0, 1);
    let (film, stats) = prism::render::render(&scene, &s, |_| {}).unwrap();
    assert_eq!(stats.nonfinite, 0);
    let expected = (rho * e0 * theta.cos() / PI) as f64;
    // Every pixel estimates the same radiance; the spread comes from wavelength sampling.
    let ys: Vec<f64> =
        (0..16).flat_map(|y| (0..16).map(move |x| (x, y))).map(|(x, y)| film.xyz(x, y).y as f64).collect();
    let n = ys.len() as f64;
    let mean = ys.iter().sum::<f64>() / n;
    let se = (ys.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0) / n).sqrt();
    assert_close("ρE/π", Estimate { mean, std_err: se }, expected);
    // The instrument reads the same radiance (∫ over 360–830 nm of a flat spectrum: × 470 nm)
    // leaving the plane toward any direction above it.
    for dir in [Vec3::Y, Vec3::new(0.5, 0.5, -0.7), Vec3::new(-0.9, 0.1, 0.3)] {
        let m = prism::measure::radiance(&scene, &direct(), Vec3::new(0.3, 0.0, 0.2), dir, 2_000, 6);
        assert_close(&format!("L toward {dir}"), m.radiance, expected * 470.0);
    }
}

#[test]
fn closed_glowing_room_sends_le_over_one_minus_rho_with_no_depth_limit() {
    // Inside a closed shape whose walls all emit L_e and reflect ρ (Lambertian), every ray sees
    // L = L_e Σ ρ^k: L_e (1 − ρ^(d+1)) / (1 − ρ) with at most d scattering events, and
    // L_e / (1 − ρ) with no limit. Russian roulette renormalises the throughput to 1, so with
    // ρ = 0.97 the paths survive with min(0.97, 0.95): no limit is estimated through the cap.
    let (le, rho) = (2.0f32, 0.97f64);
    let mut b = builder();
    let m = b.add_material(Material::diffuse(Spectrum::constant(rho as f32)));
    let glow = Emission { spectrum: Spectrum::constant(1.0), scale: le, two_sided: true };
    // Flat faces: with the interpolated normals a few sampled directions would cross the walls.
    b.add_mesh(Mesh { normals: None, ..icosphere(Vec3::ZERO, 1.0, 2) }, m, Some(glow));
    let scene = build(b);
    let truncated = |d: i32| (1.0 - rho.powi(d + 1)) / (1.0 - rho);
    for (max_depth, sum) in [(1, truncated(1)), (8, truncated(8)), (UNBOUNDED_DEPTH, 1.0 / (1.0 - rho))] {
        let integ = Integrator { max_depth, ..Default::default() };
        let m = prism::measure::radiance(&scene, &integ, Vec3::ZERO, Vec3::X, 20_000, 8);
        // Flat spectra: the measured radiance is integrated over 360–830 nm.
        assert_close(&format!("max depth {max_depth}"), m.radiance, le as f64 * sum * 470.0);
    }
}

#[test]
fn with_no_depth_limit_paths_in_a_closed_white_room_still_end() {
    // ρ = 1 keeps the throughput at 1 forever, so only the 0.95 survival cap ends a path: from
    // the Russian-roulette depth 3 on, each bounce continues with probability 0.95, and a path
    // casts 1 + 2 + Σ_{k≥1} 0.95^k = 22 rays on average (no lights: no shadow rays).
    let mut b = builder();
    let white = b.add_material(Material::diffuse(Spectrum::constant(1.0)));
    b.add_mesh(Mesh { normals: None, ..icosphere(Vec3::ZERO, 1.0, 1) }, white, None);
    let scene = build(b);
    let integ = Integrator { max_depth: UNBOUNDED_DEPTH, ..Default::default() };
    let (mut sampler, n) = (Sampler::independent(), 4000u64);
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for i in 0..n {
        let mut stats = Stats::default();
        sampler.start_pixel_sample((0, 0), i, 17);
        let mut w = SampledWavelengths::sample_visible(sampler.get_1d());
        let ray = prism::geometry::Ray::new(Vec3::ZERO, Vec3::new(0.3, 0.5, 0.8));
        assert!(integ.li(&scene, ray, &mut w, &mut sampler, &mut stats).is_black());
        sum += stats.rays as f64;
        sum2 += (stats.rays * stats.rays) as f64;
    }
    let mean = sum / n as f64;
    let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    assert!((mean - 22.0).abs() < 4.0 * se, "{mean} ± {se} rays per path, expected 22");
}

// ---- Photometric targets: pbrt-v4's `power`/`illuminance`, prism's `lumens`/`lux` ----
//
// pbrt-v4's film reads Y = ∫ȳ L dλ where prism's reads ∫ȳ L dλ / ∫ȳ dλ, and pbrt-v4 scales a
// light so that `power` q gives its film a flux of Y = q: in prism's ∫ȳ normalisation
// that is the same Y = q, i.e. K_m ∫ȳ dλ · q lumens. `lumens`/`lux` are SI.

fn load_pbrt(text: &str) -> Scene {
    let (desc, mut warnings) = prism::pbrt::parse_str(text, &Default::default()).unwrap();
    let (b, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    build(b)
}

/// An illuminance estimate [lux] as the film's Y (lux / K_m ∫ȳ dλ).
fn film_y(lux: Estimate) -> Estimate {
    let k = lumens_per_unit_y() as f64;
    Estimate { mean: lux.mean / k, std_err: lux.std_err / k }
}

/// Luminous flux [lm] through a sphere: each estimate weighted by K_m ȳ instead of integrated
/// over λ uniformly.
fn luminous_flux_through_sphere(scene: &Scene, centre: Vec3, r: f32, n: u64) -> Estimate {
    sphere_integral(scene, centre, r, n, (3, 4), 9, |e, w| lumens_per_unit_y() as f64 * e.to_xyz(w).y as f64)
}

#[test]
fn point_light_power_is_pbrt_v4s_and_lumens_and_watts_are_si() {
    let bulb = |param: &str| {
        load_pbrt(&format!(
            r#"WorldBegin LightSource "point" "blackbody I" 2700 "float {param}" 800 "point3 from" [0 0 0]"#
        ))
    };
    let (pbrt, si, radiometric) = (bulb("power"), bulb("lumens"), bulb("watts"));
    for (r, deg) in [(1.0f32, 0.0f32), (2.0, 60.0)] {
        let t = deg.to_radians();
        let n = Vec3::new(t.sin(), 0.0, -t.cos());
        let at = Vec3::new(0.0, 0.0, r);
        let lambert = 800.0 / (4.0 * std::f64::consts::PI * (r * r) as f64) * t.cos() as f64;
        // pbrt-v4 `power` 800: the film reads E = 800 cos θ / (4π r²).
        let m = irradiance(&pbrt, &direct(), at, n, 20_000, 3);
        assert_close(&format!("power 800 at r={r} θ={deg}, film Y"), film_y(m.illuminance), lambert);
        // An 800 lm incandescent bulb: E_v = Φ_v cos θ / (4π r²) [lux] ...
        let m = irradiance(&si, &direct(), at, n, 20_000, 3);
        assert_close(&format!("800 lm at r={r} θ={deg}"), m.illuminance, lambert);
        // ... and Φ_e = Φ_v / K watts behind it, K the blackbody's luminous efficacy.
        let watts = radiant_flux_from_lumens(800.0, &Spectrum::blackbody(2700.0)) as f64;
        let e = watts / (4.0 * std::f64::consts::PI * (r * r) as f64) * t.cos() as f64;
        assert_close(&format!("800 lm → {watts} W"), m.irradiance, e);
        // prism's `watts` 800: radiant flux over 360–830 nm, E = Φ cos θ / (4π r²) [W/m²].
        let m = irradiance(&radiometric, &direct(), at, n, 20_000, 3);
        assert_close(&format!("800 W at r={r} θ={deg}"), m.irradiance, lambert);
    }
}

/// A two-sided square area light with `param` 300 and `scale` 2 on a transformed mesh (pbrt-v4
/// multiplies `scale` in as well; the area is the transformed, world-space area).
fn area_light(param: &str) -> Scene {
    load_pbrt(&format!(
        r#"WorldBegin AttributeBegin Translate 0.2 0 0.1 Rotate 30 1 1 0 Scale 0.5 2 1
           Material "diffuse" "rgb reflectance" [0 0 0]
           AreaLightSource "diffuse" "blackbody L" 5500 "float {param}" 300 "float scale" 2 "bool twosided" true
           Shape "trianglemesh" "point3 P" [-0.5 -0.5 0  0.5 -0.5 0  0.5 0.5 0  -0.5 0.5 0] "integer indices" [0 1 2 0 2 3]
           AttributeEnd"#
    ))
}

#[test]
fn pbrt_spot_and_area_light_emit_their_power_and_lumens_through_a_sphere() {
    // pbrt-v4's "power" is each triangle's (one light per shape it creates, and a triangle mesh
    // is a shape per triangle); prism's "lumens" is the whole mesh's.
    for (param, to_lumens, triangles) in [("power", lumens_per_unit_y() as f64, 2.0), ("lumens", 1.0, 1.0)] {
        let spot = load_pbrt(&format!(
            r#"WorldBegin LightSource "spot" "blackbody I" 4000 "float {param}" 500 "float coneangle" 30
               "float conedeltaangle" 10 "point3 from" [0 0 0] "point3 to" [1 1 0]"#
        ));
        let m = luminous_flux_through_sphere(&spot, Vec3::ZERO, 2.0, 40_000);
        assert_close(&format!("spot {param} 500"), m, 500.0 * to_lumens);
        let area = area_light(param);
        let m = luminous_flux_through_sphere(&area, Vec3::new(0.2, 0.0, 0.1), 2.5, 40_000);
        assert_close(&format!("area 2 × {param} 300 × {triangles}"), m, 600.0 * triangles * to_lumens);
    }
}

#[test]
fn illuminance_of_distant_and_uniform_lights_is_pbrt_v4s_and_lux_is_si() {
    for (param, to_lux) in [("illuminance", lumens_per_unit_y() as f64), ("lux", 1.0)] {
        let distant = load_pbrt(&format!(
            r#"WorldBegin LightSource "distant" "blackbody L" 5800 "float {param}" 1000 "point3 from" [0 0 1] "point3 to" [0 0 0]"#
        ));
        for deg in [0.0f32, 60.0] {
            let t = deg.to_radians();
            let m = irradiance(&distant, &direct(), Vec3::ZERO, Vec3::new(t.sin(), 0.0, t.cos()), 4_000, 4);
            assert_close(&format!("distant {param} 1000 θ={deg}"), m.illuminance, 1000.0 * t.cos() as f64 * to_lux);
        }
        let sky = load_pbrt(&format!(r#"WorldBegin LightSource "infinite" "rgb L" [0.3 0.5 1] "float {param}" 2000"#));
        let m = irradiance(&sky, &direct(), Vec3::ZERO, Vec3::new(0.2, 0.9, -0.3), 20_000, 5);
        // For an RGB illuminant, pbrt-v4 normalises by the white alone; the RGB's luminance stays.
        let y_rgb = ColorSpace::srgb().rgb_to_xyz(Vec3::new(0.3, 0.5, 1.0)).y as f64;
        assert_close(&format!("sky {param} 2000 × Y(rgb)"), m.illuminance, 2000.0 * y_rgb * to_lux);
    }
}

#[test]
fn watts_and_irradiance_are_radiometric_si() {
    let area = area_light("watts");
    assert_close("area 2 × 300 W", flux_through_sphere(&area, Vec3::new(0.2, 0.0, 0.1), 2.5, 40_000), 600.0);
    let distant = load_pbrt(
        r#"WorldBegin LightSource "distant" "blackbody L" 5800 "float irradiance" 10 "point3 from" [0 0 1] "point3 to" [0 0 0]"#,
    );
    let m = irradiance(&distant, &direct(), Vec3::ZERO, Vec3::new(0.5, 0.0, 0.75f32.sqrt()), 4_000, 4);
    assert_close("distant 10 W/m² at 30°", m.irradiance, 10.0 * 0.75f64.sqrt());
    let sky = load_pbrt(r#"WorldBegin LightSource "infinite" "rgb L" [0.3 0.5 1] "float irradiance" 5"#);
    let m = irradiance(&sky, &direct(), Vec3::ZERO, Vec3::new(0.2, 0.9, -0.3), 20_000, 5);
    assert_close("sky 5 W/m²", m.irradiance, 5.0);
}

#[test]
fn a_light_given_two_brightness_targets_is_an_error() {
    let text = r#"WorldBegin LightSource "point" "float power" 1 "float lumens" 683"#;
    let (desc, mut warnings) = prism::pbrt::parse_str(text, &Default::default()).unwrap();
    let err = prism::pbrt::build(&desc, &mut warnings).err().expect("must fail").to_string();
    assert!(err.contains("give one of \"power\" and \"lumens\", not both"), "{err}");
    assert!(err.contains("1:"), "no location: {err}");
}

/// pbrt-v4 makes one area light per shape it creates: a triangle mesh is one shape per triangle,
/// so "power" is each triangle's flux whatever its area; a bilinear patch is one shape.
#[test]
fn pbrt_area_power_is_per_triangle_of_a_triangle_mesh_and_per_patch_of_a_bilinear_mesh() {
    let powers = |shape: &str| -> Vec<f32> {
        let text = format!(
            "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n\
             AreaLightSource \"diffuse\" \"blackbody L\" 4000 \"float power\" 5\n{shape}\n"
        );
        let scene = crate::common::pbrt_scene(&text, AccelKind::Obvhs);
        scene.lights().iter().map(|l| l.power(1.0)).collect()
    };
    let one = powers(r#"Shape "trianglemesh" "point3 P" [0 0 0  1 0 0  0 2 0] "integer indices" [0 1 2]"#);
    // Two triangles of areas 1 and 4.5.
    let two =
        powers(r#"Shape "trianglemesh" "point3 P" [0 0 0  1 0 0  0 2 0  4 3 0] "integer indices" [0 1 2  1 3 2]"#);
    let patch = powers(r#"Shape "bilinearmesh" "point3 P" [0 0 0  2 0 0  0 3 0  2 3 0]"#);
    // The rectangular patch is one rectangle light.
    assert_eq!((one.len(), two.len(), patch.len()), (1, 2, 1));
    assert!(one[0] > 0.0);
    for (what, p) in [("first triangle", two[0]), ("second triangle", two[1]), ("patch", patch[0])] {
        assert!((p - one[0]).abs() <= 1e-4 * one[0], "{what}: power {p} vs one triangle's {}", one[0]);
    }
}
