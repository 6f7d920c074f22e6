//! The NanoVDB medium in the volumetric path tracer, against what the fixture script wrote
//! (`tests/data/nanovdb/density.nvdb`, by OpenVDB and `nanovdb_convert`): transmittance
//! against the optical depth integrated from the script's closed form, and renders against the
//! same values given as a `uniformgrid`, whose trilinear interpolation between sample centres is
//! NanoVDB's between voxels.

use super::transmittance::transmittance;
use super::volpath_tests::{assert_close, bounded_medium, chromatic, per_wavelength, uniform_sky};
use crate::geometry::shapes::axis_box;
use crate::geometry::Ray;
use crate::media::nanovdb::tests::{fixture, script_density, script_temperature};
use crate::media::nanovdb::NanoVdbFile;
use crate::media::{Homogeneous, Medium, NanoVdbMedium};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{DVec3, Mat4, Vec3};

/// The fixture's map: world = 0.05 · index + (0.3, −0.2, 0.1).
const VOXEL: f64 = 0.05;
const ORIGIN: DVec3 = DVec3::new(0.3, -0.2, 0.1);

/// World point of index coordinate `i` on every axis.
fn world(i: f64) -> DVec3 {
    ORIGIN + DVec3::splat(VOXEL * i)
}

/// The medium's bounds: index −8 to 31 + 1.
fn bounds() -> (Vec3, Vec3) {
    (world(-8.0).as_vec3(), world(32.0).as_vec3())
}

/// The script's density at world `p`, trilinear between voxels (in double precision).
fn script_trilinear(p: DVec3) -> f64 {
    let x = (p - ORIGIN) / VOXEL;
    let (b, f) = (x.floor(), x - x.floor());
    let c = b.as_ivec3();
    let mut sum = 0.0;
    for k in 0..8 {
        let d = glam::IVec3::new(k >> 2, (k >> 1) & 1, k & 1);
        let w = |a: usize, on: i32| if on == 1 { f[a] } else { 1.0 - f[a] };
        sum += w(0, d.x) * w(1, d.y) * w(2, d.z) * script_density(c.x + d.x, c.y + d.y, c.z + d.z) as f64;
    }
    sum
}

#[test]
fn ratio_tracking_through_the_fixture_matches_the_optical_depth_by_quadrature() {
    let (sigma_a, sigma_s) = ([0.3f32, 0.5, 0.2, 0.6], [0.6f32, 0.3, 0.9, 0.2]);
    let density = NanoVdbFile::open(&fixture("density.nvdb")).unwrap().float_grid("density").unwrap();
    let unit = Homogeneous {
        sigma_a: chromatic(sigma_a),
        sigma_s: chromatic(sigma_s),
        scale: 1.0,
        le: Spectrum::constant(0.0),
        g: 0.0,
    };
    let medium = NanoVdbMedium::new(Mat4::IDENTITY, density, unit, None).unwrap();
    assert_eq!(medium.bounds, bounds());
    let (lo, hi) = bounds();
    let scene = bounded_medium(axis_box(lo, hi), Medium::NanoVdb(Box::new(medium)), uniform_sky(1.0));
    // Along x through the smooth part, a diagonal, and along z through the 0.625 tile.
    let rays = [
        (Vec3::new(-0.5, 0.4, 0.7), Vec3::new(2.3, 0.45, 0.65)),
        (Vec3::new(-0.5, -1.0, -0.7), Vec3::new(2.3, 1.8, 2.1)),
        (Vec3::new(1.2, 0.7, -0.6), Vec3::new(1.25, 0.72, 2.0)),
    ];
    for (r, (from, to)) in rays.into_iter().enumerate() {
        // ∫ d along the segment by the midpoint rule (10⁵ steps; the trilinear pieces are
        // smooth between voxel planes, so the error is far below the estimate's).
        let (a, b) = (from.as_dvec3(), to.as_dvec3());
        let steps = 100_000;
        let inside = |p: DVec3| p.cmpge(lo.as_dvec3()).all() && p.cmple(hi.as_dvec3()).all();
        let depth: f64 = (0..steps)
            .map(|s| a + (b - a) * ((s as f64 + 0.5) / steps as f64))
            .filter(|&p| inside(p))
            .map(script_trilinear)
            .sum::<f64>()
            * (b - a).length()
            / steps as f64;
        assert!(depth > 0.3, "ray {r} must cross real density: {depth}");
        let got = per_wavelength(20_000, 40 + r as u64, |w, s, st| {
            match transmittance(&scene, Ray::segment(from, to - from, 1.0), None, w, s, st) {
                Some((t, r_l, _)) => t / r_l.average(),
                None => SampledSpectrum::zero(),
            }
        });
        let expect = std::array::from_fn(|c| (-((sigma_a[c] + sigma_s[c]) as f64) * depth).exp());
        assert_close(got, expect, &format!("ray {r}: T = exp(-σ_t ∫d), ∫d = {depth:.4}"));
    }
}

/// A pbrt-v4 scene of `medium` (a MakeNamedMedium "m" line) inside a box over the fixture's
/// bounds, lit by a distant light and a dim sky.
fn scene_text(medium: &str) -> String {
    let (lo, hi) = bounds();
    let p: Vec<String> = (0..8)
        .map(|k| {
            let c = |bit: usize, a: f32, b: f32| if k & bit == 0 { a } else { b };
            format!("{} {} {}", c(1, lo.x, hi.x), c(2, lo.y, hi.y), c(4, lo.z, hi.z))
        })
        .collect();
    let faces = "0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5";
    format!(
        "LookAt 0.9 0.4 -4.5  0.9 0.4 0.7  0 1 0\nCamera \"perspective\" \"float fov\" 32\n\
         Integrator \"volpath\" \"integer maxdepth\" 6\nWorldBegin\n\
         LightSource \"distant\" \"point3 from\" [ 1 4 -2 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 3 3 3 ]\n\
         LightSource \"infinite\" \"rgb L\" [ 0.2 0.2 0.2 ]\n{medium}\n\
         Material \"interface\"\nMediumInterface \"m\" \"\"\n\
         Shape \"trianglemesh\" \"point3 P\" [ {} ] \"integer indices\" [ {faces} ]\n",
        p.join(" ")
    )
}

/// The coefficients and the emission, as both media take them.
const COMMON: &str = "\"rgb sigma_a\" [ 1 1 1 ] \"rgb sigma_s\" [ 3 3 3 ] \"float g\" 0.3 \
    \"float temperatureoffset\" 400 \"float temperaturescale\" 1.5";

/// The fixture as a pbrt-v4 "nanovdb" medium, emitting with `Lescale` 2.
fn nanovdb_medium() -> String {
    let path = fixture("density.nvdb");
    format!(
        "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"{}\" {COMMON} \"float Lescale\" 2",
        path.display()
    )
}

/// The fixture's voxels −8..=32 per axis (32 is past the last: background 0) as a uniformgrid
/// whose sample centres are the voxels: its box runs from index −8.5 to 32.5.
fn uniformgrid_medium() -> String {
    let n = 41;
    let (mut density, mut temperature) = (Vec::new(), Vec::new());
    for k in -8..=32 {
        for j in -8..=32 {
            for i in -8..=32 {
                density.push(script_density(i, j, k).to_string());
                temperature.push(script_temperature(i, j, k).to_string());
            }
        }
    }
    let (p0, p1) = (world(-8.5), world(32.5));
    format!(
        "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"integer nx\" {n} \"integer ny\" {n} \"integer nz\" {n} \
         \"point3 p0\" [ {} {} {} ] \"point3 p1\" [ {} {} {} ] \"float density\" [ {} ] \"float temperature\" [ {} ] \
         \"float Lescale\" [ {} ] {COMMON}",
        p0.x,
        p0.y,
        p0.z,
        p1.x,
        p1.y,
        p1.z,
        density.join(" "),
        temperature.join(" "),
        vec!["2"; n * n * n].join(" ")
    )
}

fn build(text: &str) -> crate::scene::Scene {
    let (desc, mut warnings) = crate::pbrt::parse_str(text, &Default::default()).unwrap();
    let (b, _) = crate::pbrt::build(&desc, &mut warnings).unwrap();
    warnings.extend(desc.report_unused());
    assert!(warnings.is_empty(), "{warnings:?}");
    b.build(crate::accel::AccelKind::Obvhs).unwrap()
}

#[test]
fn the_nanovdb_medium_has_the_uniformgrids_coefficients_and_emission_at_every_point() {
    // Inside the box, trilinear between the same values, with the temperature's blackbody
    // at (T − 400) · 1.5 K times Lescale 2 (the uniformgrid's per-voxel Lescale is 2 at every
    // sample centre, so exactly 2 inside their hull).
    let (nano, grid) = (build(&scene_text(&nanovdb_medium())), build(&scene_text(&uniformgrid_medium())));
    let (a, b) = (&nano.media()[0], &grid.media()[0]);
    assert!(matches!(a, Medium::NanoVdb(_)) && matches!(b, Medium::Grid(_)));
    let (lo, hi) = bounds();
    let mut rng = crate::sampling::Rng::new(5, 0);
    let mut emitting = 0;
    for s in 0..20_000 {
        let w = SampledWavelengths::sample_uniform(rng.uniform());
        let (ua, ub) = (a.uniform_point(&w), b.uniform_point(&w));
        let p = lo + (hi - lo) * Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
        let (pa, pb) = (a.point_at(p, &ua, &w), b.point_at(p, &ub, &w));
        // Index coordinates near 32 carry ~4·10⁻⁶ of float rounding in their fraction: times a
        // jump of up to 1.5 per voxel and σ_s = 3, up to 2·10⁻⁵ in σ.
        let close =
            |x: SampledSpectrum, y: SampledSpectrum| (x - y).map(f32::abs).max_value() <= 2e-4 * y.max_value() + 5e-5;
        assert!(close(pa.sigma_a, pb.sigma_a) && close(pa.sigma_s, pb.sigma_s), "sample {s} at {p}: {pa:?} vs {pb:?}");
        assert!(close(pa.le, pb.le), "sample {s} at {p}: L_e {:?} vs {:?}", pa.le, pb.le);
        emitting += !pa.le.is_black() as u32;
    }
    assert!(emitting > 2000, "the temperature grid covers a fifth of the box: {emitting} emitting points");
}

/// Mean of the per-pixel differences of Y, its standard error, and the mean Y of `a`.
fn difference(a: &crate::film::Film, b: &crate::film::Film) -> (f64, f64, f64) {
    let y = |p: &crate::film::Pixel| p.xyz_sum.y / p.weight_sum;
    let d: Vec<f64> = a.pixels.iter().zip(&b.pixels).map(|(p, q)| y(p) - y(q)).collect();
    let n = d.len() as f64;
    let m = d.iter().sum::<f64>() / n;
    let se = (d.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0) / n).sqrt();
    (m, se, a.pixels.iter().map(y).sum::<f64>() / n)
}

#[test]
fn a_nanovdb_render_equals_the_uniformgrid_render_within_noise() {
    let settings = |seed| crate::render::RenderSettings {
        resolution: (32, 32),
        spp: 64,
        seed,
        sampler: crate::render::SamplerKind::Independent,
        filter: crate::filter::Filter::by_name("box").unwrap(),
        integrator: super::Integrator { max_depth: 6, ..Default::default() },
        ..Default::default()
    };
    let (nano, grid) = (build(&scene_text(&nanovdb_medium())), build(&scene_text(&uniformgrid_medium())));
    let (a, _) = crate::render::render(&nano, &settings(1), |_| {}).unwrap();
    let (b, _) = crate::render::render(&grid, &settings(2), |_| {}).unwrap();
    let (d, se, mean) = difference(&a, &b);
    eprintln!("nanovdb − uniformgrid: {d:.5} ± {se:.5} (mean Y {mean:.4})");
    assert!(mean > 0.05, "the medium must be lit: {mean}");
    assert!(d.abs() < 4.0 * se, "means differ by {d} ± {se}");
}
