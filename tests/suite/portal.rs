//! pbrt-v4's portal infinite light: a room lit only through a hole in its ceiling, with the
//! portal over the hole. Illuminance under a constant sky against the rectangle's closed-form
//! form factor, for light sampling, BSDF sampling and MIS; the same under a sky with a sun,
//! against the plain environment map (the same physics), with far less noise; χ² of the
//! portal's direction sampling; radiance only through the portal; scene errors.

use crate::common::tmpdir;
use crate::equal_area_envmap::equal_area_map;
use glam::{Vec2, Vec3};
use prism::accel::AccelKind;
use prism::integrator::{DirectStrategy, Integrator};
use prism::light::photometry::lumens_per_unit_y;
use prism::light::{Light, LightSampleContext};
use prism::math::PI;
use prism::measure::irradiance;
use prism::pbrt::parse_str;
use prism::sampling::chi2::{Chi2Test, Domain};
use prism::scene::Scene;
use prism::spectrum::SampledWavelengths;
use std::path::Path;

/// Half-sizes of the ceiling's hole (x, y) and the ceiling's height [m].
const HOLE: (f32, f32) = (0.4, 0.25);
const CEILING: f32 = 2.0;

/// A closed 2 × 2 × 2 room with a hole in the ceiling, under the equal-area map in `map`,
/// with the portal over the hole when `portal` is set.
fn room(map: &Path, portal: bool, rotate: &str) -> Scene {
    room_lit_by(&format!("\"string filename\" \"{}\"", map.display()), portal, rotate)
}

/// [`room`] under an infinite light with parameters `light`.
fn room_lit_by(light: &str, portal: bool, rotate: &str) -> Scene {
    let (a, b, c) = (HOLE.0, HOLE.1, CEILING);
    let quad = |p: [[f32; 3]; 4]| {
        let pts: Vec<String> = p.iter().map(|v| format!("{} {} {}", v[0], v[1], v[2])).collect();
        format!("Shape \"trianglemesh\" \"point3 P\" [ {} ] \"integer indices\" [ 0 1 2 0 2 3 ]\n", pts.join(" "))
    };
    let mut walls = String::new();
    for q in [
        [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
        [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, -1.0, c], [-1.0, -1.0, c]],
        [[-1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, c], [-1.0, 1.0, c]],
        [[-1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, 1.0, c], [-1.0, -1.0, c]],
        [[1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, c], [1.0, -1.0, c]],
        // The ceiling around the hole: two strips along x, two along y between them.
        [[-1.0, -1.0, c], [1.0, -1.0, c], [1.0, -b, c], [-1.0, -b, c]],
        [[-1.0, b, c], [1.0, b, c], [1.0, 1.0, c], [-1.0, 1.0, c]],
        [[-1.0, -b, c], [-a, -b, c], [-a, b, c], [-1.0, b, c]],
        [[a, -b, c], [1.0, -b, c], [1.0, b, c], [a, b, c]],
    ] {
        walls += &quad(q);
    }
    // Corners p0..p3 with p3 − p0 along +x and p1 − p0 along +y: the portal's z = x × y points
    // up, out through the hole.
    let portal = if portal {
        format!("\"point3 portal\" [ {} {} {c}  {} {} {c}  {} {} {c}  {} {} {c} ]", -a, -b, -a, b, a, b, a, -b)
    } else {
        String::new()
    };
    let text = format!(
        "Camera \"perspective\" WorldBegin\n\
         AttributeBegin {rotate} LightSource \"infinite\" {light} {portal} AttributeEnd\n\
         Material \"diffuse\"\n{walls}"
    );
    let (desc, mut warnings) = parse_str(&text, &Default::default()).unwrap();
    let (builder, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    builder.build(AccelKind::Obvhs).unwrap()
}

fn write_map(name: &str, n: u32, f: impl Fn(u32, u32, Vec3) -> [f32; 3]) -> std::path::PathBuf {
    let path = tmpdir(name).join("sky.exr");
    prism::image::write(&path, &equal_area_map(n, f)).unwrap();
    path
}

/// Form factor from a patch to a parallel rectangle a × b at height c with one corner straight
/// above it (Howell's catalogue, configuration C-11).
fn corner_form_factor(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI as f64)
}

fn portal_of(scene: &Scene) -> &Light {
    scene.lights().iter().find(|l| matches!(l, Light::Portal(_))).expect("a portal light")
}

#[test]
fn a_constant_sky_through_the_portal_gives_the_rectangles_form_factor() {
    // RGB 0.5 is luminance 0.5: E_v = π L_v F with F the hole's form factor from the floor's
    // centre (four corner rectangles of HOLE at height c).
    let map = write_map("portal-constant", 32, |_, _, _| [0.5; 3]);
    let scene = room(&map, true, "");
    let p = Vec3::new(0.0, 0.0, 0.01);
    let c = (CEILING - p.z) as f64;
    let f = 4.0 * corner_form_factor(HOLE.0 as f64, HOLE.1 as f64, c);
    let expected = PI as f64 * f * 0.5 * lumens_per_unit_y() as f64;
    for strategy in [DirectStrategy::Mis, DirectStrategy::LightOnly, DirectStrategy::BsdfOnly] {
        let integ = Integrator { max_depth: 1, strategy, ..Default::default() };
        let e = irradiance(&scene, &integ, p, Vec3::Z, 40_000, 5).illuminance;
        assert!(e.mean > 0.0);
        // The map is a constant sampled at texel centres: exact.
        assert!((e.mean - expected).abs() <= 3.5 * e.std_err, "{strategy:?}: {} ± {} vs {expected}", e.mean, e.std_err);
    }
}

#[test]
fn a_sky_with_a_sun_gives_the_plain_maps_light_with_less_noise() {
    // The sun (40°) is hidden by the ceiling; the plain map spends most light samples on it.
    let map = write_map("portal-sun", 64, |x, y, d| {
        if (40..43).contains(&x) && (20..23).contains(&y) {
            [500.0, 450.0, 300.0]
        } else if d.z > 0.0 {
            [0.3 + 0.5 * (1.0 - d.z) + 0.2 * d.x, 0.5 + 0.4 * (1.0 - d.z), 1.0]
        } else {
            [0.1, 0.08, 0.05]
        }
    });
    let rotate = "Rotate 20 0 0 1";
    let (plain, portal) = (room(&map, false, rotate), room(&map, true, rotate));
    let integ = Integrator { max_depth: 1, ..Default::default() };
    for p in [Vec3::new(0.0, 0.0, 0.01), Vec3::new(0.6, -0.3, 0.01)] {
        let a = irradiance(&plain, &integ, p, Vec3::Z, 40_000, 9).illuminance;
        let b = irradiance(&portal, &integ, p, Vec3::Z, 40_000, 9).illuminance;
        assert!(a.mean > 0.0 && b.mean > 0.0);
        let sigma = (a.std_err.powi(2) + b.std_err.powi(2)).sqrt();
        assert!(
            (a.mean - b.mean).abs() <= 3.5 * sigma,
            "at {p}: plain {} ± {}, portal {} ± {}",
            a.mean,
            a.std_err,
            b.mean,
            b.std_err
        );
        assert!(b.std_err < 0.5 * a.std_err, "at {p}: portal ± {} against plain ± {}", b.std_err, a.std_err);
    }
}

#[test]
fn portal_direction_sampling_matches_its_density_chi2() {
    let map = write_map("portal-chi2", 32, |_, _, d| [1.0 + 0.8 * d.x, 0.5 + d.z * d.z, 0.3 + 0.2 * d.y]);
    let scene = room(&map, true, "Rotate 30 1 0 0");
    let light = portal_of(&scene);
    let w = SampledWavelengths::sample_uniform(0.5);
    let points = [Vec3::new(0.0, 0.0, 0.5), Vec3::new(0.7, -0.6, 1.2)];
    for p in points {
        let t = Chi2Test {
            sample_count: 300_000,
            test_count: points.len(),
            domain: Domain::Cap { axis: Vec3::Z, theta_max: 1.2 },
            ..Chi2Test::default()
        };
        let ctx = LightSampleContext::medium(p);
        let r = t.run(|_, u| light.sample_li(&ctx, u, &w).map(|s| s.wi), |d| light.pdf_li(&ctx, d));
        assert!(r.passed, "at {p}: {r}");
        assert!((r.pdf_integral - 1.0).abs() < 1e-2, "at {p}: ∫ pdf = {}", r.pdf_integral);
    }
}

#[test]
fn radiance_arrives_only_through_the_portal() {
    let map = write_map("portal-mask", 16, |_, _, _| [1.0; 3]);
    let scene = room(&map, true, "");
    let light = portal_of(&scene);
    let w = SampledWavelengths::sample_uniform(0.5);
    let inside = Vec3::new(0.1, 0.0, 1.0);
    let through = Vec3::new(0.2, 0.1, CEILING) - inside;
    let beside = Vec3::new(0.6, 0.1, CEILING) - inside;
    assert!(!light.escaped_radiance(inside, through.normalize(), &w).is_black());
    assert!(light.escaped_radiance(inside, beside.normalize(), &w).is_black());
    // Above the portal nothing is lit, and light sampling finds nothing.
    let above = Vec3::new(0.0, 0.0, CEILING + 1.0);
    assert!(light.escaped_radiance(above, Vec3::Z, &w).is_black());
    let above = LightSampleContext::medium(above);
    assert!(light.sample_li(&above, Vec2::splat(0.5), &w).is_none());
    assert_eq!(light.pdf_li(&above, Vec3::Z), 0.0);
}

#[test]
fn a_uniform_l_with_a_portal_is_the_portal_light_of_a_constant_map() {
    // pbrt-v4 turns "L" beside a portal into a 1 × 1 image of L's sRGB colour and keeps the
    // portal: the same light as a constant map of that colour.
    let rgb = [0.5, 0.4, 0.3];
    let map = write_map("portal-uniform", 2, |_, _, _| rgb);
    let by_map = room(&map, true, "Rotate 20 0 0 1");
    let by_l = room_lit_by(&format!("\"rgb L\" [ {} {} {} ] \"float scale\" 2", rgb[0], rgb[1], rgb[2]), true, "");
    let (a, b) = (portal_of(&by_map), portal_of(&by_l));
    let w = SampledWavelengths::sample_uniform(0.3);
    let (inside, through) = (Vec3::new(0.1, 0.0, 1.0), Vec3::new(0.3, 0.2, 1.0).normalize());
    let (la, lb) = (a.escaped_radiance(inside, through, &w), b.escaped_radiance(inside, through, &w));
    for i in 0..4 {
        // (The map file stores half floats.)
        assert!((2.0 * la[i] - lb[i]).abs() <= 2e-3 * lb[i].abs().max(1.0), "{la:?} {lb:?}");
    }
    let integ = Integrator { max_depth: 1, ..Default::default() };
    let p = Vec3::new(0.3, -0.2, 0.01);
    let (ea, eb) = (
        irradiance(&by_map, &integ, p, Vec3::Z, 20_000, 7).illuminance,
        irradiance(&by_l, &integ, p, Vec3::Z, 20_000, 7).illuminance,
    );
    assert!((2.0 * ea.mean - eb.mean).abs() <= 4.0 * (2.0 * ea.std_err + eb.std_err), "{ea:?} {eb:?}");
    // A blackbody "L" gives a portal light too (pbrt-v4 notes the conversion to RGB).
    let text = "WorldBegin\nLightSource \"infinite\" \"blackbody L\" 5500\n  \
                \"point3 portal\" [ 0 0 1  0 1 1  1 1 1  1 0 1 ]\n";
    let (desc, mut warnings) = parse_str(text, &Default::default()).unwrap();
    let (builder, _) = prism::pbrt::build(&desc, &mut warnings).unwrap();
    assert!(warnings.iter().all(|w| matches!(w.kind, prism::pbrt::error::WarningKind::Note)), "{warnings:?}");
    let scene = builder.build(AccelKind::Obvhs).unwrap();
    let l = portal_of(&scene).escaped_radiance(Vec3::new(0.5, 0.5, 0.0), Vec3::Z, &w);
    assert!(!l.is_black());
}

#[test]
fn a_bad_portal_is_an_error_at_its_parameter() {
    let square = write_map("portal-errors", 8, |_, _, _| [1.0; 3]);
    let cases = [(
        format!("\"string filename\" \"{}\" \"point3 portal\" [ 0 0 1  0 1 1  1 1 1 ]", square.display()),
        "4 corners",
    )];
    for (params, message) in cases {
        let text = format!("WorldBegin\nLightSource \"infinite\"\n  {params}\n");
        let (desc, mut warnings) = parse_str(&text, &Default::default()).unwrap();
        let e = prism::pbrt::build(&desc, &mut warnings).err().expect("an error").to_string();
        assert!(e.contains(message) && e.contains(":3:"), "{e}");
    }
}
