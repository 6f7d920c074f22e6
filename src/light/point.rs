//! Point and spot lights. Intensity I [W/(sr·nm)]; E at distance r is I cos θ / r²
//! (isotropic point light I = Φ/4π, E = Φ/(4πr²); Warn's spotlight I(ω) = I₀ cos^s θ, D. R. Warn,
//! "Lighting Controls for Synthetic Images", SIGGRAPH 1983).

use super::sampler::LightBounds;
use super::selection_flux::{max_value, visible_flux};
use super::LightSample;
use crate::geometry::Bounds3;
use crate::math::{Frame, PI};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;
use std::sync::Arc;

/// Isotropic point light.
#[derive(Clone, Debug)]
pub struct PointLight {
    /// Position [scene units].
    pub position: Vec3,
    /// Spectral shape of the intensity.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` into intensity I [W/(sr·nm)].
    pub scale: f32,
}

impl PointLight {
    /// A point light of intensity `scale · spectrum(λ)`.
    pub fn new(position: Vec3, spectrum: Arc<Spectrum>, scale: f32) -> Self {
        Self { position, spectrum, scale }
    }

    /// A point light emitting total flux `flux` [W] over 360–830 nm: I = Φ / 4π.
    pub fn with_flux(position: Vec3, spectrum: Arc<Spectrum>, flux: f32) -> Self {
        let scale = flux / (4.0 * PI * spectral_integral(&spectrum));
        Self { position, spectrum, scale }
    }

    pub(super) fn sample_li(&self, p: Vec3, w: &SampledWavelengths) -> Option<LightSample> {
        delta_sample(self.position, p, self.spectrum.sample(w) * self.scale)
    }

    /// pbrt-v4's `PointLight::Phi` for the power sampler: 4π I (see `selection_flux`).
    pub(super) fn power(&self) -> f32 {
        4.0 * PI * self.scale * visible_flux(&self.spectrum)
    }

    /// pbrt-v4's `PointLight::Bounds` flux: 4π scale MaxValue(I) (see `selection_flux`).
    pub(super) fn bound_flux(&self) -> f32 {
        4.0 * PI * self.scale * max_value(&self.spectrum)
    }

    /// Bounds for many-light sampling, emitting flux `phi`: a point emitting over the whole
    /// sphere.
    pub(super) fn bounds(&self, phi: f32) -> LightBounds {
        LightBounds::isotropic_point(self.position, phi)
    }
}

/// How a spotlight's intensity falls off with the angle θ from its axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpotFalloff {
    /// Warn 1983: I(θ) = I₀ cos^s θ on the forward hemisphere; flux Φ = 2π I₀ / (s+1).
    Warn {
        /// Exponent s ≥ 0.
        exponent: f32,
    },
    /// pbrt-v4: full intensity inside `cos_start`, smoothstep to zero at `cos_end`.
    Cone {
        /// cos of the angle where the falloff begins.
        cos_start: f32,
        /// cos of the total cone angle.
        cos_end: f32,
    },
}

impl SpotFalloff {
    /// I(θ)/I₀ for cos θ.
    #[inline]
    pub fn factor(&self, cos_theta: f32) -> f32 {
        match *self {
            SpotFalloff::Warn { exponent } => {
                if cos_theta <= 0.0 {
                    0.0
                } else {
                    cos_theta.powf(exponent)
                }
            }
            SpotFalloff::Cone { cos_start, cos_end } => smoothstep(cos_theta, cos_end, cos_start),
        }
    }

    /// ∫ I(ω)/I₀ dω over the sphere [sr]: Φ = I₀ × this.
    pub fn solid_angle_integral(&self) -> f32 {
        match *self {
            // ∫_{H²} cos^s θ dω = 2π ∫₀¹ μ^s dμ = 2π/(s+1).
            SpotFalloff::Warn { exponent } => 2.0 * PI / (exponent + 1.0),
            // pbrt-v4 SpotLight::Phi: 2π((1 − cosStart) + (cosStart − cosEnd)/2).
            SpotFalloff::Cone { cos_start, cos_end } => 2.0 * PI * ((1.0 - cos_start) + (cos_start - cos_end) / 2.0),
        }
    }
}

fn smoothstep(x: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A spotlight at `position` pointing along `frame.n`.
#[derive(Clone, Debug)]
pub struct SpotLight {
    /// Position [scene units].
    pub position: Vec3,
    /// Frame whose normal is the spot axis.
    pub frame: Frame,
    /// Spectral shape of the on-axis intensity I₀.
    pub spectrum: Arc<Spectrum>,
    /// Multiplier turning `spectrum` into I₀ [W/(sr·nm)].
    pub scale: f32,
    /// Angular falloff.
    pub falloff: SpotFalloff,
}

impl SpotLight {
    /// A spotlight with on-axis intensity `scale · spectrum(λ)`.
    pub fn new(position: Vec3, axis: Vec3, spectrum: Arc<Spectrum>, scale: f32, falloff: SpotFalloff) -> Self {
        Self { position, frame: Frame::from_normal(axis.normalize()), spectrum, scale, falloff }
    }

    /// A spotlight emitting total flux `flux` [W] over 360–830 nm: I₀ = Φ / ∫(I/I₀)dω
    /// (for Warn's model, I₀ = Φ (s+1) / 2π).
    pub fn with_flux(position: Vec3, axis: Vec3, spectrum: Arc<Spectrum>, flux: f32, falloff: SpotFalloff) -> Self {
        let scale = flux / (falloff.solid_angle_integral() * spectral_integral(&spectrum));
        Self::new(position, axis, spectrum, scale, falloff)
    }

    pub(super) fn sample_li(&self, p: Vec3, w: &SampledWavelengths) -> Option<LightSample> {
        let f = self.falloff.factor(self.cos_to(p));
        if f == 0.0 {
            return None;
        }
        delta_sample(self.position, p, self.spectrum.sample(w) * (self.scale * f))
    }

    /// cos θ of the cone outside which the spotlight emits nothing (Warn's lobe: the forward
    /// hemisphere).
    pub(super) fn cone_cos_max(&self) -> f32 {
        match self.falloff {
            SpotFalloff::Cone { cos_end, .. } => cos_end.clamp(-1.0, 1.0),
            SpotFalloff::Warn { .. } => 0.0,
        }
    }

    /// cos θ between the spot axis and the direction from the light to `p`.
    fn cos_to(&self, p: Vec3) -> f32 {
        self.frame.n.dot((p - self.position).normalize_or_zero())
    }

    /// pbrt-v4's `SpotLight::Phi` for the power sampler: I₀ times the falloff's solid-angle
    /// integral (see `selection_flux`).
    pub(super) fn power(&self) -> f32 {
        self.scale * self.falloff.solid_angle_integral() * visible_flux(&self.spectrum)
    }

    /// pbrt-v4's `SpotLight::Bounds` flux: 4π scale MaxValue(I), as an isotropic point light of
    /// the on-axis intensity, so that the importance inside the cone is that light's (the cone
    /// is in the bounds' angles, not in the flux).
    pub(super) fn bound_flux(&self) -> f32 {
        4.0 * PI * self.scale * max_value(&self.spectrum)
    }

    /// Bounds for many-light sampling, with flux `phi` ([`SpotLight::bound_flux`]): a point
    /// emitting over a cone about the axis, full within θ_start and falling to 0 at θ_end
    /// (Warn's cos^s lobe: all of the forward hemisphere). Where θ_end − θ_start rounds to a
    /// cosine of 1 in a cone that does fall off, cos θ_e is 0.999, as in pbrt-v4.
    pub(super) fn bounds(&self, phi: f32) -> LightBounds {
        let (cos_theta_o, cos_theta_e) = match self.falloff {
            SpotFalloff::Cone { cos_start, cos_end } => {
                let (start, end) = (cos_start.clamp(-1.0, 1.0).acos(), cos_end.clamp(-1.0, 1.0).acos());
                let cos_theta_e = (end - start).max(0.0).cos();
                (cos_start, if cos_theta_e == 1.0 && cos_end != cos_start { 0.999 } else { cos_theta_e })
            }
            SpotFalloff::Warn { .. } => (1.0, 0.0),
        };
        let bounds = Bounds3::EMPTY.union_point(self.position);
        LightBounds { bounds, w: self.frame.n, phi, cos_theta_o, cos_theta_e, two_sided: false }
    }
}

/// The sample of a point-like light at `position` seen from `p`: direction, distance and the
/// inverse-square law applied to the intensity toward `p` (E = I / r² along `wi`).
pub(super) fn delta_sample(position: Vec3, p: Vec3, intensity: SampledSpectrum) -> Option<LightSample> {
    let d = position - p;
    let r2 = d.length_squared();
    if r2 == 0.0 {
        return None;
    }
    let dist = r2.sqrt();
    let wi = d / dist;
    Some(LightSample { li: intensity * (1.0 / r2), wi, pdf: 1.0, p_light: position, dist })
}

/// ∫ s(λ) dλ over 360–830 nm [nm × the spectrum's unit], by the trapezoid rule at 1 nm.
pub(crate) fn spectral_integral(s: &Spectrum) -> f32 {
    let mut acc = 0.0f64;
    let mut prev = s.eval(360.0) as f64;
    for l in 361..=830 {
        let v = s.eval(l as f32) as f64;
        acc += 0.5 * (prev + v);
        prev = v;
    }
    acc as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warn_flux_integral_matches_the_closed_form() {
        // Numerically integrate cos^s θ over the hemisphere and compare with 2π/(s+1).
        for s in [0.0f32, 1.0, 10.0, 100.0] {
            let f = SpotFalloff::Warn { exponent: s };
            let n = 200_000;
            let mut acc = 0.0f64;
            for i in 0..n {
                let mu = (i as f64 + 0.5) / n as f64; // cos θ
                acc += f.factor(mu as f32) as f64;
            }
            let numeric = 2.0 * std::f64::consts::PI * acc / n as f64;
            let closed = f.solid_angle_integral() as f64;
            assert!((numeric - closed).abs() / closed < 1e-3, "s={s}: {numeric} vs {closed}");
        }
    }

    #[test]
    fn cone_flux_integral_matches_numeric() {
        let f = SpotFalloff::Cone { cos_start: 30f32.to_radians().cos(), cos_end: 45f32.to_radians().cos() };
        let n = 400_000;
        let mut acc = 0.0f64;
        for i in 0..n {
            let mu = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
            acc += f.factor(mu as f32) as f64;
        }
        let numeric = 2.0 * std::f64::consts::PI * acc * 2.0 / n as f64;
        let closed = f.solid_angle_integral() as f64;
        assert!((numeric - closed).abs() / closed < 1e-3, "{numeric} vs {closed}");
    }
}
