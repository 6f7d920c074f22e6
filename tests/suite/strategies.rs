//! Every light × every BSDF: renders with next-event estimation only, BSDF sampling only and MIS
//! estimate the same image (per-pixel differences average to zero within 4 standard errors).
//! Delta lights cannot be reached by BSDF sampling, so for them MIS is checked against NEE only.

use crate::common::film_difference as diff;
use crate::common::test_settings;
use glam::Vec3;
use prism::accel::AccelKind;
use prism::camera::Camera;
use prism::film::Film;
use prism::geometry::shapes::quad;
use prism::integrator::{DirectStrategy, Integrator};
use prism::light::{Light, PointLight, SpotFalloff, SpotLight, UniformInfiniteLight};
use prism::material::{
    CoatedConductorMaterial, CoatedDiffuseMaterial, ConductorIor, FloatTexture, Ior, LayerSpec, Material, Roughness,
    SpectrumTexture,
};
use prism::render::{render, RenderSettings};
use prism::scene::{Emission, SceneBuilder};
use prism::spectrum::Spectrum;
use std::sync::Arc;

fn materials() -> Vec<(&'static str, Material)> {
    let c = |v: f32| SpectrumTexture::Constant(Spectrum::constant(v));
    let coated = |analytic: bool| CoatedDiffuseMaterial {
        analytic,
        ..CoatedDiffuseMaterial::new(c(0.6), Roughness::alpha(0.2), 1.5)
    };
    vec![
        ("diffuse", Material::diffuse(Spectrum::constant(0.7))),
        (
            "diffuse transmission",
            Material::DiffuseTransmission { reflectance: c(0.4), transmittance: c(0.4), scale: 1.0 },
        ),
        (
            "rough conductor",
            Material::Conductor {
                ior: ConductorIor::EtaK { eta: Spectrum::constant(0.2), k: Spectrum::constant(3.0) },
                roughness: Roughness::alpha(0.3),
            },
        ),
        ("rough dielectric", Material::Dielectric { eta: Ior::Constant(1.5), roughness: Roughness::alpha(0.3) }),
        ("coated diffuse", Material::CoatedDiffuse(Box::new(coated(false)))),
        ("analytic coated diffuse", Material::CoatedDiffuse(Box::new(coated(true)))),
        (
            "coated conductor",
            Material::CoatedConductor(Box::new(CoatedConductorMaterial {
                interface_roughness: Roughness::alpha(0.2),
                interface_eta: Ior::Constant(1.5),
                conductor: ConductorIor::Reflectance(c(0.8)),
                conductor_roughness: Roughness::alpha(0.3),
                layer: LayerSpec { albedo: c(0.5), thickness: FloatTexture::Constant(0.2), ..LayerSpec::default() },
            })),
        ),
    ]
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum LightKind {
    Area,
    Environment,
    Point,
    Spot,
}

fn render_with(material: &Material, light: LightKind, strategy: DirectStrategy, seed: u64) -> Film {
    let mut b = SceneBuilder::new();
    let m = b.add_material(material.clone());
    b.add_mesh(quad(Vec3::new(-2.0, 0.0, -2.0), Vec3::new(0.0, 0.0, 4.0), Vec3::new(4.0, 0.0, 0.0)), m, None);
    let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));
    match light {
        LightKind::Area => {
            let em = Emission { spectrum: Spectrum::blackbody(5000.0), scale: 4.0, two_sided: false };
            b.add_mesh(
                quad(Vec3::new(-0.5, 1.5, -0.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0)),
                black,
                Some(em),
            );
        }
        LightKind::Environment => b.add_light(Light::UniformInfinite(UniformInfiniteLight {
            spectrum: Arc::new(Spectrum::constant(1.0)),
            scale: 0.5,
        })),
        LightKind::Point => {
            b.add_light(Light::Point(PointLight::new(Vec3::new(0.3, 1.2, 0.1), Arc::new(Spectrum::constant(1.0)), 2.0)))
        }
        LightKind::Spot => b.add_light(Light::Spot(SpotLight::new(
            Vec3::new(0.0, 1.5, 0.0),
            -Vec3::Y,
            Arc::new(Spectrum::constant(1.0)),
            3.0,
            SpotFalloff::Warn { exponent: 4.0 },
        ))),
    }
    b.set_camera(Camera::look_at(Vec3::new(0.0, 1.0, -2.5), Vec3::ZERO, Vec3::Y), 50.0);
    let scene = b.build(AccelKind::Obvhs).unwrap();
    let base = test_settings((16, 16), 64, seed, 3);
    let s = RenderSettings { integrator: Integrator { strategy, ..base.integrator }, ..base };
    let (film, stats) = render(&scene, &s, |_| {}).unwrap();
    assert_eq!(stats.nonfinite, 0);
    film
}

#[test]
fn nee_bsdf_sampling_and_mis_agree_for_every_light_and_bsdf() {
    for (name, material) in materials() {
        for light in [LightKind::Area, LightKind::Environment, LightKind::Point, LightKind::Spot] {
            let mis = render_with(&material, light, DirectStrategy::Mis, 1);
            let nee = render_with(&material, light, DirectStrategy::LightOnly, 2);
            let (d, se, mean) = diff(&mis, &nee);
            assert!(mean > 1e-3, "{name} / {light:?}: black image");
            assert!(d.abs() <= 4.0 * se, "{name} / {light:?}: MIS vs NEE {d} ± {se} (mean {mean})");
            if matches!(light, LightKind::Area | LightKind::Environment) {
                let bsdf = render_with(&material, light, DirectStrategy::BsdfOnly, 3);
                let (d, se, _) = diff(&mis, &bsdf);
                assert!(d.abs() <= 4.0 * se, "{name} / {light:?}: MIS vs BSDF sampling {d} ± {se}");
            }
        }
    }
}
