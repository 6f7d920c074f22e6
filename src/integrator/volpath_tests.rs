//! The volumetric path tracer against closed forms. Media are chromatic, with values given at
//! four fixed wavelengths; each sample rotates which of them is the hero (as the renderer's
//! wavelength sampling does), so the spectral-MIS estimate of every wavelength is checked
//! separately. Tolerances are 4 standard errors of the mean.

use super::transmittance::transmittance;
use super::{Integrator, IntegratorKind, Stats};
use crate::accel::AccelKind;
use crate::geometry::shapes::{axis_box, uv_sphere};
use crate::geometry::Ray;
use crate::light::{DistantLight, Light, UniformInfiniteLight};
use crate::material::Material;
use crate::media::{DensityGrid, GridMedium, Homogeneous, Medium};
use crate::sampling::Sampler;
use crate::scene::{Emission, MediumInterface, Scene, SceneBuilder};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Mat4, UVec3, Vec3};
use std::sync::Arc;

/// The wavelengths [nm] the chromatic coefficients are given at.
pub(super) const LAMBDAS: [f32; 4] = [450.0, 520.0, 590.0, 660.0];

/// A spectrum taking `v[c]` at `LAMBDAS[c]` (linear between, constant beyond).
pub(super) fn chromatic(v: [f32; 4]) -> Spectrum {
    Spectrum::piecewise_linear(&[360.0, 450.0, 520.0, 590.0, 660.0, 830.0], &[v[0], v[0], v[1], v[2], v[3], v[3]])
        .unwrap()
}

pub(super) fn homogeneous(sigma_a: [f32; 4], sigma_s: [f32; 4], g: f32, le: Spectrum) -> Medium {
    Medium::Homogeneous(Homogeneous { sigma_a: chromatic(sigma_a), sigma_s: chromatic(sigma_s), scale: 1.0, le, g })
}

/// Mean and standard error per wavelength of `LAMBDAS` of `n` estimates; sample `i` makes
/// wavelength `i mod 4` the hero.
pub(super) fn per_wavelength(
    n: u64,
    seed: u64,
    mut estimate: impl FnMut(&mut SampledWavelengths, &mut Sampler, &mut Stats) -> SampledSpectrum,
) -> [(f64, f64); 4] {
    let mut sampler = Sampler::independent();
    let mut stats = Stats::default();
    let (mut s, mut s2) = ([0f64; 4], [0f64; 4]);
    for i in 0..n {
        sampler.start_pixel_sample((0, 0), i, seed);
        let k = (i % 4) as usize;
        let mut w = SampledWavelengths::sample_uniform(0.0);
        w.lambda = std::array::from_fn(|j| LAMBDAS[(j + k) % 4]);
        let x = estimate(&mut w, &mut sampler, &mut stats);
        for c in 0..4 {
            let v = x[(c + 4 - k) % 4] as f64;
            assert!(v.is_finite(), "sample {i}: {x:?}");
            s[c] += v;
            s2[c] += v * v;
        }
    }
    std::array::from_fn(|c| {
        let mean = s[c] / n as f64;
        (mean, ((s2[c] / n as f64 - mean * mean).max(0.0) / n as f64).sqrt())
    })
}

pub(super) fn assert_close(got: [(f64, f64); 4], expect: [f64; 4], what: &str) {
    for c in 0..4 {
        let (mean, se) = got[c];
        assert!(expect[c] > 1e-4, "{what}: the expected value must not be negligible");
        assert!(
            (mean - expect[c]).abs() <= 4.0 * se + 1e-6 * expect[c],
            "{what} λ = {} nm: {mean} ± {se}, expected {}",
            LAMBDAS[c],
            expect[c]
        );
    }
}

/// A scene of `mesh` as an interface with `medium` inside and vacuum outside, lit by `light`.
pub(super) fn bounded_medium(mesh: crate::geometry::Mesh, medium: Medium, light: Light) -> Scene {
    let mut b = SceneBuilder::new();
    let interface = b.add_material(Material::Interface);
    let m = b.add_medium(medium);
    let id = b.add_mesh(mesh, interface, None);
    b.set_medium_interface(id, MediumInterface { inside: Some(m), outside: None });
    b.add_light(light);
    b.set_camera(Mat4::IDENTITY, 40.0);
    b.build(AccelKind::Obvhs).unwrap()
}

pub(super) fn uniform_sky(l: f32) -> Light {
    Light::UniformInfinite(UniformInfiniteLight { spectrum: Arc::new(Spectrum::constant(l)), scale: 1.0 })
}

#[test]
fn beer_lambert_through_an_absorbing_slab() {
    let d = 1.3f32;
    let sigma_a = [0.3, 0.8, 1.5, 0.05];
    let scene = bounded_medium(
        axis_box(Vec3::new(-50.0, -50.0, 0.0), Vec3::new(50.0, 50.0, d)),
        homogeneous(sigma_a, [0.0; 4], 0.0, Spectrum::constant(0.0)),
        uniform_sky(2.0),
    );
    let dir = Vec3::new(0.3, 0.0, 1.0).normalize();
    let ray = Ray::new(Vec3::new(0.1, 0.2, -1.0), dir);
    let integ = Integrator { kind: IntegratorKind::VolPath, max_depth: 5, ..Default::default() };
    let got = per_wavelength(40_000, 1, |w, s, st| integ.li(&scene, ray, w, s, st));
    let path = d as f64 / dir.z as f64;
    assert_close(got, sigma_a.map(|a| 2.0 * (-(a as f64) * path).exp()), "L = L_sky exp(-σ_a ℓ)");
}

#[test]
fn ratio_tracking_through_a_scattering_slab_is_beer_lambert() {
    let d = 0.9f32;
    let (sigma_a, sigma_s) = ([0.2, 0.1, 0.5, 0.0], [0.5, 1.5, 0.2, 2.0]);
    let scene = bounded_medium(
        axis_box(Vec3::new(-50.0, -50.0, 0.0), Vec3::new(50.0, 50.0, d)),
        homogeneous(sigma_a, sigma_s, 0.4, Spectrum::constant(0.0)),
        uniform_sky(1.0),
    );
    let (from, to) = (Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.5, 0.0, 2.0));
    let got = per_wavelength(40_000, 2, |w, s, st| {
        match transmittance(&scene, Ray::segment(from, to - from, 1.0), None, w, s, st) {
            Some((t, r_l, _)) => t / r_l.average(),
            None => SampledSpectrum::zero(),
        }
    });
    // The segment from z = -1 to z = 2 spends d/3 of its parameter range in the slab.
    let inside = (to - from).length() as f64 * d as f64 / 3.0;
    assert_close(got, std::array::from_fn(|c| (-((sigma_a[c] + sigma_s[c]) as f64) * inside).exp()), "T = exp(-σ_t ℓ)");
}

/// Henyey–Greenstein density [1/sr] for the cosine between propagation directions.
fn hg(cos: f64, g: f64) -> f64 {
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * cos).powf(1.5))
}

#[test]
fn single_scattering_of_a_collimated_beam_in_a_thin_slab() {
    // Slab z ∈ [0, d] lit by a distant light of irradiance E from the camera's side at angle θ
    // to the normal; the camera looks along +z. With one scattering event allowed the radiance
    // is L = σ_s p(ω_l → −z) E ∫_0^d exp(−σ_t z (1 + 1/μ)) dz, μ = cos θ.
    let (d, theta, g, e) = (0.1f64, 60f64.to_radians(), 0.3f64, 3.0f32);
    let (sigma_a, sigma_s) = ([0.2, 0.4, 0.1, 0.3], [0.5, 1.0, 1.5, 0.8]);
    let to_light = Vec3::new(theta.sin() as f32, 0.0, -(theta.cos() as f32));
    let light = Light::Distant(DistantLight { to_light, spectrum: Arc::new(Spectrum::constant(1.0)), scale: e });
    let scene = bounded_medium(
        axis_box(Vec3::new(-50.0, -50.0, 0.0), Vec3::new(50.0, 50.0, d as f32)),
        homogeneous(sigma_a, sigma_s, g as f32, Spectrum::constant(0.0)),
        light,
    );
    let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z);
    let integ = Integrator { kind: IntegratorKind::VolPath, max_depth: 1, ..Default::default() };
    let got = per_wavelength(40_000, 3, |w, s, st| integ.li(&scene, ray, w, s, st));
    let mu = theta.cos();
    // Light propagates along ω_l = −to_light, the scattered light toward the camera along −z:
    // cos = ω_l · (−z) = to_light.z.
    let p = hg(to_light.z as f64, g);
    let expect = std::array::from_fn(|c| {
        let st = (sigma_a[c] + sigma_s[c]) as f64;
        let k = st * (1.0 + 1.0 / mu);
        sigma_s[c] as f64 * p * e as f64 * (1.0 - (-k * d).exp()) / k
    });
    assert_close(got, expect, "single scattering");
}

#[test]
fn furnace_a_closed_emitter_filled_with_a_scattering_medium_gives_its_radiance() {
    // Inside an enclosure emitting L_e inward, a non-absorbing medium (any g, any σ_s) changes
    // nothing: L = L_e in every direction (the transport equation with σ_a = 0 and L = L_e
    // everywhere is stationary).
    let le = 0.7f32;
    let mut b = SceneBuilder::new();
    let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));
    let m = b.add_medium(homogeneous([0.0; 4], [0.4, 1.0, 2.0, 0.1], 0.6, Spectrum::constant(0.0)));
    let emission = Emission { spectrum: Spectrum::constant(le), scale: 1.0, two_sided: true };
    let id = b.add_mesh(uv_sphere(Vec3::ZERO, 1.0, 24, 48), black, Some(emission));
    b.set_medium_interface(id, MediumInterface { inside: Some(m), outside: None });
    b.set_camera(Mat4::IDENTITY, 40.0);
    b.set_camera_medium(Some(m));
    let scene = b.build(AccelKind::Obvhs).unwrap();
    let integ = Integrator { kind: IntegratorKind::VolPath, max_depth: 1000, ..Default::default() };
    let ray = Ray::new(Vec3::new(0.2, -0.1, 0.3), Vec3::new(0.3, 0.5, -0.2).normalize());
    let got = per_wavelength(20_000, 4, |w, s, st| integ.li(&scene, ray, w, s, st));
    // A furnace has zero variance per path only up to MIS and the hero's choices; still, the
    // mean must be L_e.
    let got = got.map(|(m, se)| (m, se.max(1e-4)));
    assert_close(got, [le as f64; 4], "furnace");
}

#[test]
fn an_emissive_absorbing_sphere_seen_from_outside() {
    // Along a chord of length ℓ through an emitting, absorbing medium, L = L_e (1 − exp(−σ_a ℓ)).
    let (r, le) = (1.0f32, 1.5f32);
    let sigma_a = [0.3, 1.0, 2.5, 0.6];
    let scene = bounded_medium(
        uv_sphere(Vec3::ZERO, r, 64, 128),
        homogeneous(sigma_a, [0.0; 4], 0.0, Spectrum::constant(le)),
        uniform_sky(0.0),
    );
    let integ = Integrator { kind: IntegratorKind::VolPath, max_depth: 5, ..Default::default() };
    // Near the pole, where the tessellation's chord is within 10⁻⁴ of the sphere's.
    let b = 1e-3f64;
    let ray = Ray::new(Vec3::new(b as f32, 0.0, -3.0), Vec3::Z);
    let got = per_wavelength(40_000, 5, |w, s, st| integ.li(&scene, ray, w, s, st));
    let chord = 2.0 * ((r as f64).powi(2) - b * b).sqrt();
    assert_close(got, sigma_a.map(|a| le as f64 * (1.0 - (-(a as f64) * chord).exp())), "emissive sphere");
}

/// The grid of the ratio-tracking test: density varying along x as `profile`, the same in y
/// and z, over the unit cube.
fn profile_grid(profile: [f32; 4]) -> DensityGrid {
    let values = (0..64).map(|i| profile[i % 4]).collect();
    DensityGrid::new(UVec3::splat(4), values).unwrap()
}

#[test]
fn ratio_tracking_on_a_grid_matches_the_known_optical_depth() {
    // Samples at cell centres x = (i + ½)/4, trilinear between, falling to half the edge sample
    // at the faces (outside samples are 0): ∫_0^1 d(x) dx by the trapezoid rule on the pieces.
    let profile = [1.0f32, 3.0, 2.0, 4.0];
    let v = profile.map(|x| x as f64);
    let edges = 0.125 * (0.75 * v[0]) + 0.125 * (0.75 * v[3]);
    let interior: f64 = (0..3).map(|i| 0.25 * 0.5 * (v[i] + v[i + 1])).sum();
    let depth = edges + interior;
    let (sigma_a, sigma_s) = ([0.1, 0.3, 0.05, 0.2], [0.3, 0.2, 0.6, 0.1]);
    let Medium::Homogeneous(coefficients) = homogeneous(sigma_a, sigma_s, 0.0, Spectrum::constant(0.0)) else {
        unreachable!()
    };
    let grid = GridMedium::new(Mat4::IDENTITY, Vec3::ZERO, Vec3::ONE, profile_grid(profile), coefficients).unwrap();
    let scene = bounded_medium(axis_box(Vec3::ZERO, Vec3::ONE), Medium::Grid(Box::new(grid)), uniform_sky(1.0));
    // Along x through the middle, where y and z sit between sample centres.
    let (from, to) = (Vec3::new(-1.0, 0.5, 0.45), Vec3::new(2.0, 0.5, 0.45));
    let got = per_wavelength(40_000, 6, |w, s, st| {
        match transmittance(&scene, Ray::segment(from, to - from, 1.0), None, w, s, st) {
            Some((t, r_l, _)) => t / r_l.average(),
            None => SampledSpectrum::zero(),
        }
    });
    assert_close(got, std::array::from_fn(|c| (-((sigma_a[c] + sigma_s[c]) as f64) * depth).exp()), "grid T");
}

#[test]
fn subsurface_random_walk_and_volpath_agree_on_the_same_medium() {
    // A smooth dielectric sphere (η = 1.33) filled with a chromatic scattering medium, under a uniform sky:
    // the subsurface material's random walk and the volumetric path tracer with the medium
    // behind a dielectric boundary solve the same transport, so their means agree within noise.
    use crate::geometry::shapes::icosphere;
    use crate::integrator::{Integrator, SubsurfaceMethod};
    use crate::material::{Ior, Roughness, ScatteringSpec, SubsurfaceMaterial};
    let (sigma_a, sigma_s, g, eta) = ([0.3, 0.1, 0.6, 0.2], [2.0, 1.0, 3.0, 0.5], 0.3f32, 1.33f32);
    let sphere = || icosphere(Vec3::ZERO, 1.0, 4);
    let build = |material: Material, medium: Option<Medium>| {
        let mut b = SceneBuilder::new();
        let id_m = b.add_material(material);
        let id = b.add_mesh(sphere(), id_m, None);
        if let Some(m) = medium {
            let m = b.add_medium(m);
            b.set_medium_interface(id, MediumInterface { inside: Some(m), outside: None });
        }
        b.add_light(uniform_sky(1.0));
        b.set_camera(Mat4::IDENTITY, 40.0);
        b.build(AccelKind::Obvhs).unwrap()
    };
    let medium = homogeneous(sigma_a, sigma_s, g, Spectrum::constant(0.0));
    let vol_scene =
        build(Material::Dielectric { eta: Ior::Constant(eta), roughness: Roughness::alpha(0.0) }, Some(medium));
    let spec = ScatteringSpec::Coefficients { sigma_a: chromatic(sigma_a), sigma_s: chromatic(sigma_s), scale: 1.0 };
    let sss = SubsurfaceMaterial::new(spec, eta, g, Roughness::alpha(0.0));
    let walk_scene = build(Material::Subsurface(Box::new(sss)), None);
    let volpath = Integrator { kind: IntegratorKind::VolPath, max_depth: 10_000, ..Default::default() };
    let walk = Integrator { max_depth: 10_000, sss: SubsurfaceMethod::RandomWalk, ..Default::default() }
        .for_scene(&walk_scene);
    for (k, x) in [0.0f32, 0.5, 0.85].into_iter().enumerate() {
        let ray = Ray::new(Vec3::new(x, 0.1, 3.0), -Vec3::Z);
        let a = per_wavelength(40_000, 10 + k as u64, |w, s, st| volpath.li(&vol_scene, ray, w, s, st));
        let b = per_wavelength(40_000, 20 + k as u64, |w, s, st| walk.li(&walk_scene, ray, w, s, st));
        for c in 0..4 {
            let ((ma, sa), (mb, sb)) = (a[c], b[c]);
            eprintln!("x = {x}, λ = {} nm: volpath {ma:.4} ± {sa:.4}, random walk {mb:.4} ± {sb:.4}", LAMBDAS[c]);
            assert!(ma > 0.05, "not black");
            let tol = 4.0 * (sa * sa + sb * sb).sqrt();
            assert!((ma - mb).abs() <= tol, "x = {x}: volpath {ma} ± {sa} vs walk {mb} ± {sb}");
        }
    }
}

#[test]
fn volpath_renders_subsurface_materials_as_the_path_tracer_does() {
    // An optically thick subsurface sphere with a rough boundary under a sky and a sun, no
    // media: the volumetric loop continues paths into it by diffusion as the surface loop does,
    // with its own light sampling and MIS. (A walk needs the volumetric loop's medium step; it
    // is checked against a medium behind a dielectric boundary above.)
    use crate::geometry::shapes::icosphere;
    use crate::integrator::{Integrator, SubsurfaceMethod};
    use crate::material::{Roughness, ScatteringSpec, SubsurfaceMaterial};
    let spec = ScatteringSpec::Coefficients {
        sigma_a: chromatic([0.2, 0.05, 0.4, 0.1]),
        sigma_s: chromatic([3.0, 1.5, 4.0, 0.8]),
        scale: 10.0,
    };
    let sss = SubsurfaceMaterial::new(spec, 1.4, 0.2, Roughness::alpha(0.3));
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::Subsurface(Box::new(sss)));
    b.add_mesh(icosphere(Vec3::ZERO, 1.0, 4), m, None);
    b.add_light(uniform_sky(0.3));
    let sun = Vec3::new(0.4, 0.5, 1.0).normalize();
    b.add_light(Light::Distant(DistantLight {
        to_light: sun,
        spectrum: Arc::new(Spectrum::constant(2.0)),
        scale: 1.0,
    }));
    b.set_camera(Mat4::IDENTITY, 40.0);
    let scene = b.build(AccelKind::Obvhs).unwrap();
    assert!(!scene.may_have_thin_subsurface(), "the sphere is optically thick");
    {
        let sss = SubsurfaceMethod::Diffusion;
        let path = Integrator { max_depth: 64, sss, ..Default::default() };
        assert_eq!(path.for_scene(&scene).kind, IntegratorKind::Path);
        let volpath = Integrator { kind: IntegratorKind::VolPath, ..path };
        for (k, x) in [0.0f32, 0.7].into_iter().enumerate() {
            let ray = Ray::new(Vec3::new(x, 0.1, 3.0), -Vec3::Z);
            let a = per_wavelength(40_000, 30 + k as u64, |w, s, st| volpath.li(&scene, ray, w, s, st));
            let b = per_wavelength(40_000, 40 + k as u64, |w, s, st| path.li(&scene, ray, w, s, st));
            for c in 0..4 {
                let ((ma, sa), (mb, sb)) = (a[c], b[c]);
                assert!(ma > 0.05, "{sss:?} x = {x}: not black ({ma})");
                let tol = 4.0 * (sa * sa + sb * sb).sqrt();
                assert!(
                    (ma - mb).abs() <= tol,
                    "{sss:?} x = {x}, λ = {}: volpath {ma} ± {sa} vs path {mb} ± {sb}",
                    LAMBDAS[c]
                );
            }
        }
    }
}

#[test]
fn an_emissive_rgb_grid_gives_the_quadrature_of_its_emission() {
    // An absorbing RGB grid over the unit cube, 2 × 1 × 1 voxels, emitting Lescale · trilinear(Le)
    // [pbrt-v4's RGBGridMedium]. Along z at x = 3/8 the x weights are ¾ and ¼; with one voxel in
    // z, the lattice's trilinear support falls to half at the faces z = 0 and z = 1, so
    // w(z) = ½ + min(z, 1 − z) for σ_a and L_e alike, and
    // L = ∫₀¹ σ_a(z) L_e(z) exp(−∫₀ᶻ σ_a) dz, by quadrature here.
    use crate::media::{RgbGridMedium, SpectrumGrid};
    let (a0, a1) = ([0.4f32, 1.0, 2.0, 3.0], [1.2f32, 0.6, 0.2, 3.0]);
    let (e0, e1, le_scale) = ([1.0f32, 2.0, 0.5, 4.0], [3.0f32, 0.5, 0.5, 0.0], 1.5f32);
    let grid = |v0, v1| SpectrumGrid::new(UVec3::new(2, 1, 1), vec![chromatic(v0), chromatic(v1)]).unwrap();
    let medium = RgbGridMedium::new(
        Mat4::IDENTITY,
        Vec3::ZERO,
        Vec3::ONE,
        Some(grid(a0, a1)),
        Some(grid([0.0; 4], [0.0; 4])),
        1.0,
        0.0,
    )
    .unwrap()
    .with_emission(grid(e0, e1), le_scale);
    let scene = bounded_medium(axis_box(Vec3::ZERO, Vec3::ONE), Medium::RgbGrid(Box::new(medium)), uniform_sky(0.0));
    let integ = Integrator { kind: IntegratorKind::VolPath, max_depth: 5, ..Default::default() };
    let ray = Ray::new(Vec3::new(0.375, 0.5, -2.0), Vec3::Z);
    let got = per_wavelength(40_000, 6, |w, s, st| integ.li(&scene, ray, w, s, st));
    let expect = std::array::from_fn(|c| {
        let support = |z: f64| 0.5 + z.min(1.0 - z);
        let x_mix = |v0: f32, v1: f32| 0.75 * v0 as f64 + 0.25 * v1 as f64;
        let (steps, mut tau, mut l) = (100_000, 0.0f64, 0.0f64);
        for i in 0..steps {
            let z = (i as f64 + 0.5) / steps as f64;
            let sa = x_mix(a0[c], a1[c]) * support(z);
            let le = le_scale as f64 * x_mix(e0[c], e1[c]) * support(z);
            let dz = 1.0 / steps as f64;
            l += (-(tau + 0.5 * sa * dz)).exp() * sa * le * dz;
            tau += sa * dz;
        }
        l
    });
    assert_close(got, expect, "emissive rgb grid");
}

/// Without media the volumetric loop and the surface loop estimate the same radiance, with each
/// direct-light strategy: they share every surface step and differ in how emission found by
/// BSDF sampling is weighted against light sampling (the balance heuristic on r_u, r_l against
/// the power heuristic) and in the sample dimensions a shadow ray's transmittance draws, so their
/// means agree within noise.
#[test]
fn the_volumetric_and_the_surface_loop_agree_on_a_scene_without_media() {
    use crate::integrator::DirectStrategy;
    let scene = SceneBuilder::cornell_box().build(AccelKind::Obvhs).unwrap();
    assert!(!scene.has_media());
    let base = Integrator { max_depth: 6, ..Default::default() };
    let as_volpath = Integrator { kind: IntegratorKind::VolPath, ..base };
    assert_eq!(as_volpath.for_scene(&scene).kind, IntegratorKind::Path, "a scene without media takes the surface loop");
    let origin = Vec3::new(278.0, 273.0, -800.0);
    for (k, target) in [Vec3::new(278.0, 273.0, 0.0), Vec3::new(100.0, 400.0, 300.0)].into_iter().enumerate() {
        let ray = Ray::new(origin, (target - origin).normalize());
        for (j, strategy) in
            [DirectStrategy::Mis, DirectStrategy::LightOnly, DirectStrategy::BsdfOnly].into_iter().enumerate()
        {
            let path = Integrator { strategy, ..base };
            let volpath = Integrator { kind: IntegratorKind::VolPath, ..path };
            let seed = 50 + 10 * k as u64 + 2 * j as u64;
            let a = per_wavelength(12_000, seed, |w, s, st| volpath.li(&scene, ray, w, s, st));
            let b = per_wavelength(12_000, seed + 1, |w, s, st| path.li(&scene, ray, w, s, st));
            for c in 0..4 {
                let ((ma, sa), (mb, sb)) = (a[c], b[c]);
                assert!(ma > 1e-3, "ray {k}: black ({ma})");
                let tol = 4.0 * (sa * sa + sb * sb).sqrt();
                let lambda = LAMBDAS[c];
                assert!(
                    (ma - mb).abs() < tol,
                    "{strategy:?} ray {k} λ = {lambda} nm: volpath {ma} ± {sa}, path {mb} ± {sb}"
                );
            }
        }
    }
}

/// A closed grey box (reflectance 0.5, flat faces, seen from inside) lit by a point light
/// inside: no path escapes and every diffuse bounce succeeds, so a path ends only by its depth
/// limit or roulette.
fn grey_room() -> Scene {
    use crate::light::PointLight;
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::diffuse(Spectrum::constant(0.5)));
    b.add_mesh(axis_box(Vec3::splat(-5.0), Vec3::splat(5.0)), m, None);
    b.add_light(Light::Point(PointLight::new(Vec3::new(0.0, 1.0, 0.0), Arc::new(Spectrum::constant(1.0)), 1.0)));
    b.set_camera(Mat4::IDENTITY, 40.0);
    b.build(AccelKind::Obvhs).unwrap()
}

/// Both loops honour `rr_depth`, `rr_threshold` and the direct-light strategy, the settings
/// they share: with roulette beyond the depth limit, or a threshold of 0, every path of the grey
/// room reaches the limit, and BSDF sampling alone never finds a point light.
#[test]
fn both_loops_take_the_shared_roulette_depth_and_strategy() {
    use crate::integrator::DirectStrategy;
    let scene = grey_room();
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.3, -0.2, 1.0).normalize());
    for kind in [IntegratorKind::Path, IntegratorKind::VolPath] {
        let no_roulette = Integrator { kind, max_depth: 12, rr_depth: 100, ..Default::default() };
        let early_roulette = Integrator { rr_depth: 1, ..no_roulette };
        let no_threshold = Integrator { rr_threshold: 0.0, ..early_roulette };
        let bsdf_only = Integrator { strategy: DirectStrategy::BsdfOnly, ..no_roulette };
        let mut sampler = Sampler::independent();
        let (mut stats, mut shallow, mut lit) = (Stats::default(), [0u32; 3], 0.0f32);
        for i in 0..400 {
            for (k, integ) in [no_roulette, early_roulette, no_threshold].into_iter().enumerate() {
                sampler.start_pixel_sample((0, 0), i, 3);
                let mut w = SampledWavelengths::sample_visible(sampler.get_1d());
                integ.li(&scene, ray, &mut w, &mut sampler, &mut stats);
                shallow[k] += (stats.last_depth < 12) as u32;
            }
            sampler.start_pixel_sample((0, 0), i, 4);
            let mut w = SampledWavelengths::sample_visible(sampler.get_1d());
            lit += bsdf_only.li(&scene, ray, &mut w, &mut sampler, &mut stats).average();
        }
        assert_eq!(shallow[0], 0, "{kind:?}: a path ended before depth 12 with roulette from depth 100");
        // Survival is at most 0.5 per bounce from depth 1: nearly every path ends early.
        assert!(shallow[1] > 350, "{kind:?}: roulette from depth 1 ended only {} of 400 paths early", shallow[1]);
        assert_eq!(shallow[2], 0, "{kind:?}: a path ended before depth 12 with a roulette threshold of 0");
        assert_eq!(lit, 0.0, "{kind:?}: BSDF sampling alone found the point light");
    }
}

/// A depth limit of 2³¹ − 1 in a closed white room (every bounce keeps the throughput at 1)
/// ends every path, as no limit does: from a limit of 1024 the survival probability is capped.
#[test]
fn a_huge_depth_limit_in_a_lossless_room_ends_like_no_limit() {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        use crate::light::PointLight;
        let mut b = SceneBuilder::new();
        let m = b.add_material(Material::diffuse(Spectrum::constant(1.0)));
        b.add_mesh(axis_box(Vec3::splat(-5.0), Vec3::splat(5.0)), m, None);
        b.add_light(Light::Point(PointLight::new(Vec3::Y, Arc::new(Spectrum::constant(1.0)), 1.0)));
        b.set_camera(Mat4::IDENTITY, 40.0);
        let scene = b.build(AccelKind::Obvhs).unwrap();
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.3, -0.2, 1.0).normalize());
        for kind in [IntegratorKind::Path, IntegratorKind::VolPath] {
            let integ = Integrator { kind, max_depth: i32::MAX as u32, ..Default::default() };
            let mut sampler = Sampler::independent();
            let mut stats = Stats::default();
            for i in 0..200 {
                sampler.start_pixel_sample((0, 0), i, 5);
                let mut w = SampledWavelengths::sample_visible(sampler.get_1d());
                integ.li(&scene, ray, &mut w, &mut sampler, &mut stats);
            }
        }
        tx.send(()).unwrap();
    });
    let ended = rx.recv_timeout(std::time::Duration::from_secs(60));
    assert!(ended.is_ok(), "200 paths with a depth limit of 2^31 - 1 did not end in 60 s");
}
