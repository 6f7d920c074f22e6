//! pbrt-v4's procedural cloud ("cloud"): density from a sum of five octaves of Perlin noise at
//! a point first displaced by two octaves of the noise's gradient ("wispiness"), thinning with
//! height y and filling the box's lower half, clamped to [0, 1]; σ_a and σ_s are scaled by it.
//! Its majorant is σ_t over the whole box (the density never exceeds 1).

use super::coefficients::{Homogeneous, MediumPoint};
use super::grid::{clip_to_unit_cube, unit_cube_from_world};
use super::majorant::MajorantSegments;
use crate::spectrum::SampledSpectrum;
use crate::texture::noise::noise;
use glam::{Mat4, Vec3};

/// The cloud's shape parameters.
#[derive(Clone, Copy, Debug)]
pub struct CloudShape {
    /// Overall density multiplier.
    pub density: f32,
    /// Strength of the gradient displacement.
    pub wispiness: f32,
    /// Spatial frequency of the noise [1/medium unit].
    pub frequency: f32,
}

/// Finite-difference gradient of the noise (step 0.01, as pbrt-v4's `DNoise`).
fn noise_gradient(p: Vec3) -> Vec3 {
    let h = 0.01;
    let n = noise(p);
    Vec3::new(noise(p + Vec3::X * h) - n, noise(p + Vec3::Y * h) - n, noise(p + Vec3::Z * h) - n) / h
}

impl CloudShape {
    /// The density in [0, 1] at medium-space `p`.
    pub fn density(&self, p: Vec3) -> f32 {
        let mut pp = p * self.frequency;
        if self.wispiness > 0.0 {
            let (mut omega, mut lambda) = (0.05 * self.wispiness, 10.0f32);
            for _ in 0..2 {
                pp += noise_gradient(pp * lambda) * omega;
                omega *= 0.5;
                lambda *= 1.99;
            }
        }
        let (mut d, mut omega, mut lambda) = (0.0f32, 0.5f32, 1.0f32);
        for _ in 0..5 {
            d += omega * noise(pp * lambda);
            omega *= 0.5;
            lambda *= 1.99;
        }
        let d = ((1.0 - p.y) * 4.5 * self.density * d).clamp(0.0, 1.0) + 2.0 * (0.5 - p.y).max(0.0);
        d.clamp(0.0, 1.0)
    }
}

/// A cloud over the box [p0, p1] of medium space.
#[derive(Clone, Debug)]
pub struct CloudMedium {
    medium_from_world: Mat4,
    unit_from_world: Mat4,
    shape: CloudShape,
    /// The coefficients at density 1 (no emission).
    pub coefficients: Homogeneous,
}

impl CloudMedium {
    /// `None` when the box is empty or the transform singular.
    pub fn new(
        world_from_medium: Mat4,
        p0: Vec3,
        p1: Vec3,
        shape: CloudShape,
        coefficients: Homogeneous,
    ) -> Option<Self> {
        let unit_from_world = unit_cube_from_world(world_from_medium, p0, p1)?;
        Some(Self { medium_from_world: world_from_medium.inverse(), unit_from_world, shape, coefficients })
    }

    /// The coefficients at world-space `p`, from those at density 1.
    pub fn point(&self, p: Vec3, unit: &MediumPoint) -> MediumPoint {
        let q = self.unit_from_world.transform_point3(p);
        if q.cmplt(Vec3::ZERO).any() || q.cmpgt(Vec3::ONE).any() {
            return MediumPoint { sigma_a: SampledSpectrum::zero(), sigma_s: SampledSpectrum::zero(), ..*unit };
        }
        let d = self.shape.density(self.medium_from_world.transform_point3(p));
        MediumPoint { sigma_a: unit.sigma_a * d, sigma_s: unit.sigma_s * d, ..*unit }
    }

    /// One segment over the part of the ray inside the box, majorant σ_t at density 1.
    pub fn majorant_segments(&self, o: Vec3, d: Vec3, t_max: f32, sigma_t: SampledSpectrum) -> MajorantSegments<'_> {
        let (uo, ud) = (self.unit_from_world.transform_point3(o), self.unit_from_world.transform_vector3(d));
        match clip_to_unit_cube(uo, ud, t_max) {
            Some((t0, t1)) => MajorantSegments::single(t0, t1, sigma_t),
            None => MajorantSegments::none(),
        }
    }
}
