//! Fractal sums of noise (pbrt-v4 §10.6.2–10.6.4): fractional Brownian motion
//! Σ ωⁱ noise(λⁱ p), turbulence Σ ωⁱ |noise(λⁱ p)|, and "windy" waves, each antialiased by
//! leaving out the octaves whose frequency exceeds what the footprint (∂p/∂x, ∂p/∂y) can
//! resolve, the last one faded in smoothly.

use super::noise::noise;
use glam::Vec3;

/// Frequency ratio of successive octaves: slightly below 2 so the lattices of octaves do not
/// line up (pbrt-v4's value).
const LACUNARITY: f32 = 1.99;

/// Hermite smoothstep of `x` between `a` and `b`.
fn smooth_step(x: f32, a: f32, b: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// How many octaves (fractional) the footprint resolves, at most `max_octaves`: noise has
/// features about one unit wide, octave i has width 1.99⁻ⁱ, and the Nyquist limit allows
/// octaves whose width is at least twice the footprint's length ℓ, so n = −1 − log₂ ℓ.
/// A zero footprint resolves every octave.
fn resolved_octaves(dpdx: Vec3, dpdy: Vec3, max_octaves: u32) -> f32 {
    let len2 = dpdx.length_squared().max(dpdy.length_squared());
    let n = -1.0 - 0.5 * len2.log2();
    if n.is_nan() {
        0.0
    } else {
        n.clamp(0.0, max_octaves as f32)
    }
}

/// Fractional Brownian motion: Σ ωⁱ noise(1.99ⁱ p) over the resolved octaves, the partial
/// one faded in by a smoothstep of its fraction (pbrt-v4 `FBm`).
pub fn fbm(p: Vec3, dpdx: Vec3, dpdy: Vec3, omega: f32, max_octaves: u32) -> f32 {
    let n = resolved_octaves(dpdx, dpdy, max_octaves);
    let whole = n.floor() as u32;
    let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
    for _ in 0..whole {
        sum += o * noise(lambda * p);
        lambda *= LACUNARITY;
        o *= omega;
    }
    sum + o * smooth_step(n - whole as f32, 0.3, 0.7) * noise(lambda * p)
}

/// Turbulence: Σ ωⁱ |noise(1.99ⁱ p)|. Octaves the footprint cannot resolve contribute 0.2
/// each, about the average of |noise| (pbrt-v4 `Turbulence`), so the mean does not drift
/// with distance.
pub fn turbulence(p: Vec3, dpdx: Vec3, dpdy: Vec3, omega: f32, max_octaves: u32) -> f32 {
    let n = resolved_octaves(dpdx, dpdy, max_octaves);
    let whole = n.floor() as u32;
    let (mut sum, mut lambda, mut o) = (0.0, 1.0, 1.0);
    for _ in 0..whole {
        sum += o * noise(lambda * p).abs();
        lambda *= LACUNARITY;
        o *= omega;
    }
    let fade = smooth_step(n - whole as f32, 0.3, 0.7);
    sum += o * (0.2 + fade * (noise(lambda * p).abs() - 0.2));
    for _ in whole..max_octaves {
        sum += o * 0.2;
        o *= omega;
    }
    sum
}

/// Wind-swept waves: the wave height, an fBm of 6 octaves, scaled by the local wind strength,
/// the magnitude of a low-frequency fBm of 3 octaves at a tenth of the scale (pbrt-v4
/// `WindyTexture`).
pub fn windy(p: Vec3, dpdx: Vec3, dpdy: Vec3) -> f32 {
    let wind = fbm(0.1 * p, 0.1 * dpdx, 0.1 * dpdy, 0.5, 3);
    let wave = fbm(p, dpdx, dpdy, 0.5, 6);
    wind.abs() * wave
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zero_footprint_sums_every_octave() {
        let p = Vec3::new(0.37, 1.91, -2.3);
        let sum: f32 = (0..5).map(|i| 0.5f32.powi(i) * noise(1.99f32.powi(i) * p)).sum();
        // The partial octave after the last whole one has weight smoothstep(0) = 0.
        let f = fbm(p, Vec3::ZERO, Vec3::ZERO, 0.5, 5);
        assert!((f - sum).abs() < 1e-5, "{f} vs {sum}");
    }

    #[test]
    fn a_wide_footprint_leaves_only_the_first_octaves() {
        let p = Vec3::new(3.7, -0.2, 5.1);
        // ℓ = 2^-2.5 → n = −1 + 2.5 = 1.5: one whole octave, the second at smoothstep(0.5) = ½.
        let d = Vec3::new(2f32.powf(-2.5), 0.0, 0.0);
        let expect = noise(p) + 0.5 * 0.5 * noise(1.99 * p);
        let f = fbm(p, d, Vec3::ZERO, 0.5, 8);
        assert!((f - expect).abs() < 1e-5, "{f} vs {expect}");
        // A footprint wider than a noise cell resolves nothing: the mean, 0.
        assert_eq!(fbm(p, Vec3::splat(4.0), Vec3::ZERO, 0.5, 8), 0.0);
    }

    #[test]
    fn turbulence_of_an_unresolved_footprint_is_its_average() {
        // Nothing resolved: every one of the 4 octaves contributes 0.2 ωⁱ (and the partial
        // octave's fade is 0, adding another 0.2 ω⁰ for the first).
        let t = turbulence(Vec3::new(0.3, 0.4, 0.5), Vec3::splat(10.0), Vec3::ZERO, 0.5, 4);
        let expect = 0.2 + 0.2 * (1.0 + 0.5 + 0.25 + 0.125);
        assert!((t - expect).abs() < 1e-6, "{t} vs {expect}");
        // Resolved, it is the sum of |noise|.
        let p = Vec3::new(1.3, 2.4, 0.5);
        let full = turbulence(p, Vec3::ZERO, Vec3::ZERO, 0.5, 3);
        let sum: f32 = (0..3).map(|i| 0.5f32.powi(i) * noise(1.99f32.powi(i) * p).abs()).sum();
        assert!((full - (sum + 0.125 * 0.2)).abs() < 1e-5, "{full} vs {sum}");
    }

    #[test]
    fn windy_is_the_product_of_wind_and_waves() {
        let p = Vec3::new(4.2, 7.7, 1.1);
        let expect = fbm(0.1 * p, Vec3::ZERO, Vec3::ZERO, 0.5, 3).abs() * fbm(p, Vec3::ZERO, Vec3::ZERO, 0.5, 6);
        assert_eq!(windy(p, Vec3::ZERO, Vec3::ZERO), expect);
    }
}
