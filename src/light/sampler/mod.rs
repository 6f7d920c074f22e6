//! Choosing a light for next-event estimation (PBR 4th ed. §12.6): uniformly, in proportion to
//! power, or by a BVH over the lights' bounds that weighs each light's importance at the shading
//! point (pbrt-v4's default). Every sampler returns, with the light, the remainder of `u` within
//! the light's interval as a fresh uniform for sampling a point on the light ("sample reuse", as
//! Mitsuba 3's `DiscreteDistribution::sample_reuse`), so one stratified 2D point stays stratified
//! over a light made of many triangles.

mod bounds;
mod bvh;
mod cone;
mod power;

pub use bounds::LightBounds;
pub use bvh::BvhLightSampler;
pub use power::PowerLightSampler;

use super::Light;
use glam::Vec3;

/// Where light is gathered (pbrt-v4's `LightSampleContext`): the point and its shading normal,
/// or a zero normal for a point in a medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSampleContext {
    /// Reference point [scene units].
    pub p: Vec3,
    /// Unit shading normal, or zero in a medium.
    pub n: Vec3,
}

impl LightSampleContext {
    /// A point on a surface with unit normal `n`.
    pub fn surface(p: Vec3, n: Vec3) -> Self {
        Self { p, n }
    }

    /// A point in a medium (no normal).
    pub fn medium(p: Vec3) -> Self {
        Self { p, n: Vec3::ZERO }
    }
}

/// Which light sampler to build (pbrt-v4's Integrator "lightsampler"). pbrt-v4 files get
/// pbrt-v4's default, the BVH; scenes built in code (the built-in Cornell box, tests) get the
/// power sampler, which costs a scene of one or two emitters nothing (the BVH costs the Cornell
/// box 1% per sample, 10% before its rectangle shortcut: docs/benchmarks.md, "Light samplers").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSamplerKind {
    /// Every light with the same probability.
    Uniform,
    /// In proportion to emitted power.
    #[default]
    Power,
    /// By importance at the shading point through a BVH over the lights (pbrt-v4's default).
    Bvh,
}

crate::named::name_table!(LightSamplerKind, "light sampler", {
    "bvh" => LightSamplerKind::Bvh,
    "power" => LightSamplerKind::Power,
    "uniform" => LightSamplerKind::Uniform,
});

/// A light sampler over a scene's lights.
#[derive(Clone, Debug)]
pub enum LightSampler {
    /// Uniform choice among this many lights.
    Uniform(usize),
    /// Power-proportional choice.
    Power(PowerLightSampler),
    /// Importance through a light BVH.
    Bvh(Box<BvhLightSampler>),
}

impl LightSampler {
    /// The sampler of `kind` over `lights` (for lights at infinity, `scene_radius` sizes their
    /// power).
    pub fn new(kind: LightSamplerKind, lights: &[Light], scene_radius: f32) -> Self {
        match kind {
            LightSamplerKind::Uniform => Self::Uniform(lights.len()),
            LightSamplerKind::Power => Self::Power(PowerLightSampler::new(&power::light_powers(lights, scene_radius))),
            LightSamplerKind::Bvh => {
                let fluxes = power::light_bound_fluxes(lights);
                let bounded: Vec<bvh::BoundedLight> = lights
                    .iter()
                    .zip(fluxes)
                    .map(|(l, phi)| bvh::BoundedLight { bounds: l.bounds(phi), infinite: l.is_at_infinity() })
                    .collect();
                Self::Bvh(Box::new(BvhLightSampler::new(&bounded)))
            }
        }
    }

    /// Picks a light for `ctx` with `u` in [0, 1): its index, its probability and `u` rescaled
    /// to a fresh uniform in [0, 1); `None` when there is none to pick.
    #[inline]
    pub fn sample(&self, ctx: &LightSampleContext, u: f32) -> Option<(usize, f32, f32)> {
        match self {
            Self::Uniform(0) => None,
            &Self::Uniform(n) => {
                let v = u * n as f32;
                let i = (v as usize).min(n - 1);
                Some((i, 1.0 / n as f32, (v - i as f32).clamp(0.0, 1.0f32.next_down())))
            }
            Self::Power(s) => s.sample(u),
            Self::Bvh(s) => s.sample(ctx.p, ctx.n, u),
        }
    }

    /// Probability with which [`LightSampler::sample`] picks light `i` at `ctx`.
    #[inline]
    pub fn pmf(&self, ctx: &LightSampleContext, i: usize) -> f32 {
        match self {
            &Self::Uniform(n) => {
                if i < n {
                    1.0 / n as f32
                } else {
                    0.0
                }
            }
            Self::Power(s) => s.pmf(i),
            Self::Bvh(s) => s.pmf(ctx.p, ctx.n, i),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::AccelKind;
    use crate::geometry::shapes::quad;
    use crate::material::Material;
    use crate::sampling::Sampler;
    use crate::scene::{Emission, SceneBuilder};
    use crate::spectrum::{SampledWavelengths, Spectrum};
    use glam::DVec3;

    /// A square light of two triangles over a point: light sampling from one Sobol 2D point per
    /// sample must converge as a stratified estimate over the whole square, with every sampler. The estimate of
    /// G = ∫ cos θ dω over the light (cos θ at the point) converges from N = 64 to N = 1024 by
    /// at least 6× in RMS error over 512 differently scrambled pixels (32× measured). Choosing
    /// the triangle by a 1D draw from another, independently scrambled Sobol group splits the
    /// stratified points between the triangles at random, and gives 4× = √16 (4.3× measured,
    /// checked below). The exact G is a midpoint sum over the square in f64.
    #[test]
    fn a_light_of_two_triangles_is_sampled_as_one_stratified_square() {
        for kind in [LightSamplerKind::Power, LightSamplerKind::Bvh, LightSamplerKind::Uniform] {
            stratified_over_two_triangles(kind);
        }
    }

    fn stratified_over_two_triangles(kind: LightSamplerKind) {
        let (p0, e1, e2) = (Vec3::new(-1.0, 2.0, -1.0), Vec3::X * 2.0, Vec3::Z * 2.0);
        let mut b = SceneBuilder::new();
        let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));
        b.add_mesh(
            quad(p0, e1, e2),
            black,
            Some(Emission { spectrum: Spectrum::constant(1.0), scale: 1.0, two_sided: false }),
        );
        b.set_camera(glam::Mat4::IDENTITY, 60.0);
        b.set_light_sampler(kind);
        let scene = b.build(AccelKind::Obvhs).unwrap();
        let p = Vec3::new(0.3, 0.0, 0.1);
        let ctx = LightSampleContext::surface(p, Vec3::Y);
        let n = 2000;
        let exact: f64 = (0..n * n)
            .map(|k| {
                let (i, j) = ((k / n) as f64 + 0.5, (k % n) as f64 + 0.5);
                let q = p0.as_dvec3() + e1.as_dvec3() * (i / n as f64) + e2.as_dvec3() * (j / n as f64);
                let d: DVec3 = q - p.as_dvec3();
                let r2 = d.length_squared();
                let cos = d.y / r2.sqrt();
                cos * cos / r2 * (4.0 / (n * n) as f64)
            })
            .sum();
        let w = SampledWavelengths::sample_uniform(0.5);
        // `reuse`: one 2D point chooses the triangle and the point on it; otherwise a 1D draw
        // chooses the triangle (what this test must tell apart). Both after the camera's lens
        // draw, as in the renderer, which puts the old 1D choice and the 2D point in different,
        // independently scrambled Sobol groups.
        let rmse = |samples: u64, reuse: bool| {
            let mut s = Sampler::sobol();
            let sq: f64 = (0..512u32)
                .map(|pixel| {
                    let sum: f64 = (0..samples)
                        .map(|i| {
                            s.start_pixel_sample((pixel, 7), i, 3);
                            let _lens = s.get_2d();
                            let (_, light, pmf, u) = if reuse {
                                scene.sample_light(&ctx, s.get_2d()).unwrap()
                            } else {
                                let choice = glam::Vec2::new(s.get_1d(), 0.5);
                                let (id, light, pmf, _) = scene.sample_light(&ctx, choice).unwrap();
                                (id, light, pmf, s.get_2d())
                            };
                            light.sample_li(&ctx, u, &w).map_or(0.0, |ls| (ls.wi.y / (pmf * ls.pdf)) as f64)
                        })
                        .sum();
                    (sum / samples as f64 - exact).powi(2)
                })
                .sum();
            (sq / 512.0).sqrt()
        };
        let (e64, e1024) = (rmse(64, true), rmse(1024, true));
        assert!(e64 > 0.0 && e64 < 0.05 * exact, "{kind:?}: {e64} vs G = {exact}");
        assert!(e64 / e1024 > 6.0, "{kind:?}: RMSE {e64} at 64, {e1024} at 1024: ratio {}", e64 / e1024);
        let (i64, i1024) = (rmse(64, false), rmse(1024, false));
        assert!(i64 / i1024 < 5.0, "{kind:?}, independent choice: RMSE {i64} at 64, {i1024} at 1024");
    }
}
