//! pbrt-v4's `mix` material: at each hit one of two materials is chosen at random, the second
//! with probability `amount` (a stochastic blend, like alpha testing: in expectation the BSDF
//! is (1 − amount) f₀ + amount f₁). The choice is a hash of the hit, so every ray that finds
//! the same point from the same direction sees the same material (pbrt-v4 `MixMaterial`).

use super::{FloatTexture, Material, TextureEvalContext};
use crate::sampling::rng::{hash64, hash64_step};
use glam::Vec3;

/// Two materials and the probability of the second.
#[derive(Clone, Debug)]
pub struct MixMaterial {
    /// Probability of `materials[1]` ∈ [0, 1] (pbrt-v4's default 0.5).
    pub amount: FloatTexture,
    /// The materials mixed (each may be a mix itself).
    pub materials: [Material; 2],
}

impl MixMaterial {
    /// The material chosen at the shading point `ctx` by the uniform number `u` ∈ [0, 1).
    pub fn choose(&self, ctx: &TextureEvalContext, u: f32) -> &Material {
        let amount = self.amount.eval(ctx);
        if amount <= 0.0 || amount.is_nan() {
            &self.materials[0]
        } else if amount >= 1.0 || u < amount {
            &self.materials[1]
        } else {
            &self.materials[0]
        }
    }
}

/// The key of a hit for [`Material::resolve`]: a hash of the point and the direction toward
/// the viewer.
pub fn hit_key(p: Vec3, wo: Vec3) -> u64 {
    let [px, py, pz] = p.to_array().map(|x| x.to_bits() as u64);
    let [ox, oy, oz] = wo.to_array().map(|x| x.to_bits() as u64);
    hash64(&[px, py, pz, ox, oy, oz])
}

impl Material {
    /// The material that renders a hit with key `key` ([`hit_key`]) at the shading point
    /// `ctx`: itself, or for a mix the chosen material, nested mixes resolved in turn with
    /// independent choices.
    pub fn resolve(&self, key: u64, ctx: &TextureEvalContext) -> &Material {
        let mut m = self;
        let mut level = 0u64;
        while let Material::Mix(mix) = m {
            let h = hash64_step(key, level);
            // 24 bits: a uniform float in [0, 1) exactly.
            let u = (h >> 40) as f32 * (1.0 / (1u32 << 24) as f32);
            m = mix.choose(ctx, u);
            level += 1;
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Spectrum;
    use glam::Vec2;

    fn grey(v: f32) -> Material {
        Material::diffuse(Spectrum::constant(v))
    }

    fn reflectance(m: &Material) -> f32 {
        match m {
            Material::Diffuse { reflectance: super::super::SpectrumTexture::Constant(s) } => s.eval(550.0),
            other => panic!("not a constant diffuse: {other:?}"),
        }
    }

    fn mix(amount: f32, a: Material, b: Material) -> Material {
        Material::Mix(Box::new(MixMaterial { amount: FloatTexture::Constant(amount), materials: [a, b] }))
    }

    #[test]
    fn the_second_material_is_chosen_with_probability_amount() {
        // Nested: 0.3 of the outer goes to an inner 0.5/0.5 mix, so the leaves have
        // probabilities 0.7, 0.15, 0.15 (binomial counts, 4σ).
        let m = mix(0.3, grey(0.1), mix(0.5, grey(0.2), grey(0.3)));
        let n = 200_000;
        let mut counts = [0usize; 3];
        for i in 0..n {
            let p = Vec3::new(i as f32 * 1e-3, 0.5, -2.0);
            let leaf = m.resolve(hit_key(p, Vec3::Z), &TextureEvalContext::uv(Vec2::ZERO));
            counts[(reflectance(leaf) * 10.0).round() as usize - 1] += 1;
        }
        for (c, want) in counts.iter().zip([0.7f64, 0.15, 0.15]) {
            let sigma = (want * (1.0 - want) / n as f64).sqrt();
            let got = *c as f64 / n as f64;
            assert!((got - want).abs() < 4.0 * sigma, "{counts:?}: {got} vs {want}");
        }
    }

    #[test]
    fn the_choice_is_a_function_of_the_hit() {
        let m = mix(0.5, grey(0.1), grey(0.2));
        let (p, wo) = (Vec3::new(0.25, -1.0, 3.0), Vec3::new(0.0, 0.6, 0.8));
        let first = reflectance(m.resolve(hit_key(p, wo), &TextureEvalContext::uv(Vec2::ZERO)));
        for _ in 0..10 {
            assert_eq!(reflectance(m.resolve(hit_key(p, wo), &TextureEvalContext::uv(Vec2::ZERO))), first);
        }
        // Amounts at or beyond the ends pick one material whatever the hash.
        for i in 0..100 {
            let key = hit_key(Vec3::splat(i as f32), wo);
            assert_eq!(
                reflectance(mix(0.0, grey(0.1), grey(0.2)).resolve(key, &TextureEvalContext::uv(Vec2::ZERO))),
                0.1
            );
            assert_eq!(
                reflectance(mix(1.0, grey(0.1), grey(0.2)).resolve(key, &TextureEvalContext::uv(Vec2::ZERO))),
                0.2
            );
            assert_eq!(
                reflectance(mix(-3.0, grey(0.1), grey(0.2)).resolve(key, &TextureEvalContext::uv(Vec2::ZERO))),
                0.1
            );
            assert_eq!(
                reflectance(mix(f32::NAN, grey(0.1), grey(0.2)).resolve(key, &TextureEvalContext::uv(Vec2::ZERO))),
                0.1
            );
        }
    }
}
