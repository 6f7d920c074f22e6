//! Photon beam diffusion (Habel, Christensen & Jarosz 2013) for a semi-infinite homogeneous
//! medium below a smooth dielectric boundary: radial reflectance profiles R(r) of the multiple-
//! (dipole per point along the refracted beam) and single-scattering terms, as in pbrt-v3/v4
//! (`BeamDiffusionMS`, `BeamDiffusionSS`). Lengths are in units of the mean free path when the
//! caller passes σ_t = 1. Evaluated in f64: the table is built once.

use crate::bsdf::fresnel::fr_dielectric;
use crate::media::HenyeyGreenstein;
use std::f64::consts::PI;

/// First Fresnel moment ∫₀¹ F_r(μ) μ dμ for light arriving from the side of index η (relative
/// to the other side), in pbrt-v4's polynomial fit (`FresnelMoment1`; d'Eon & Irving 2011).
/// η > 1: the inside of a dense medium, where total internal reflection makes it large.
pub fn fresnel_moment1(eta: f32) -> f32 {
    let e = eta as f64;
    let (e2, e3, e4, e5) = (e * e, e * e * e, e.powi(4), e.powi(5));
    let v = if e < 1.0 {
        0.45966 - 1.73965 * e + 3.37668 * e2 - 3.904945 * e3 + 2.49277 * e4 - 0.68441 * e5
    } else {
        -4.61686 + 11.1136 * e - 10.4646 * e2 + 5.11455 * e3 - 1.27198 * e4 + 0.12746 * e5
    };
    v as f32
}

/// Second Fresnel moment ∫₀¹ F_r(μ) μ² dμ, same convention (pbrt-v4 `FresnelMoment2`).
pub fn fresnel_moment2(eta: f32) -> f32 {
    let e = eta as f64;
    let (e2, e3, e4, e5) = (e * e, e * e * e, e.powi(4), e.powi(5));
    let v = if e < 1.0 {
        0.27614 - 0.87350 * e + 1.12077 * e2 - 0.65095 * e3 + 0.07883 * e4 + 0.04860 * e5
    } else {
        let (r, r2, r3) = (1.0 / e, 1.0 / e2, 1.0 / e3);
        -547.033 + 45.3087 * r3 - 218.725 * r2 + 458.843 * r + 404.557 * e - 189.519 * e2 + 54.9327 * e3 - 9.00603 * e4
            + 0.63942 * e5
    };
    v as f32
}

/// Quadrature points along the beam (pbrt uses 100).
const BEAM_SAMPLES: usize = 100;

/// Multiple-scattering radial reflectance R_ms(r) [1/length²]: a dipole for each point of the
/// refracted beam at depth z_r (sampled ∝ σ'_t e^{−σ'_t z}), with the PBD extended-source
/// boundary condition (Habel et al. 2013 eqs. 4–9; Grosjean's diffusion coefficient
/// D = (2σ_a + σ'_s)/(3σ'_t²)).
pub fn beam_diffusion_ms(sigma_s: f64, sigma_a: f64, g: f64, eta: f32, r: f64) -> f64 {
    let sigmap_s = sigma_s * (1.0 - g);
    let sigmap_t = sigma_a + sigmap_s;
    if sigmap_t <= 0.0 {
        return 0.0;
    }
    let rhop = sigmap_s / sigmap_t;
    let d_g = (2.0 * sigma_a + sigmap_s) / (3.0 * sigmap_t * sigmap_t);
    let sigma_tr = (sigma_a / d_g).max(0.0).sqrt();
    let (fm1, fm2) = (fresnel_moment1(eta) as f64, fresnel_moment2(eta) as f64);
    // Extrapolation distance of the partial-current boundary condition.
    let ze = -2.0 * d_g * (1.0 + 3.0 * fm2) / (1.0 - 2.0 * fm1);
    let (c_phi, c_e) = (0.25 * (1.0 - 2.0 * fm1), 0.5 * (1.0 - 3.0 * fm2));
    let mut ed = 0.0;
    for i in 0..BEAM_SAMPLES {
        let zr = -(1.0 - (i as f64 + 0.5) / BEAM_SAMPLES as f64).ln() / sigmap_t;
        let zv = -zr + 2.0 * ze;
        let (dr, dv) = ((r * r + zr * zr).sqrt(), (r * r + zv * zv).sqrt());
        // Fluence and its normal derivative of the real/virtual source pair.
        let phi_d = 1.0 / (4.0 * PI) / d_g * ((-sigma_tr * dr).exp() / dr - (-sigma_tr * dv).exp() / dv);
        let ed_n = 1.0 / (4.0 * PI)
            * (zr * (1.0 + sigma_tr * dr) * (-sigma_tr * dr).exp() / (dr * dr * dr)
                - zv * (1.0 + sigma_tr * dv) * (-sigma_tr * dv).exp() / (dv * dv * dv));
        let e = phi_d * c_phi + ed_n * c_e;
        // PBD's correction for sources near the exit point.
        let kappa = 1.0 - (-2.0 * sigmap_t * (dr + zr)).exp();
        ed += kappa * rhop * rhop * e;
    }
    ed / BEAM_SAMPLES as f64
}

/// Single-scattering radial reflectance R_ss(r) [1/length²] of the refracted normal beam
/// (Habel et al. 2013 eq. 11; pbrt-v4 `BeamDiffusionSS`), integrated along the beam beyond the
/// critical depth t_crit = r √(η² − 1) below which light cannot exit.
pub fn beam_diffusion_ss(sigma_s: f64, sigma_a: f64, g: f64, eta: f32, r: f64) -> f64 {
    let sigma_t = sigma_a + sigma_s;
    if sigma_t <= 0.0 {
        return 0.0;
    }
    let rho = sigma_s / sigma_t;
    let e = eta as f64;
    let t_crit = r * (e * e - 1.0).max(0.0).sqrt();
    let phase = HenyeyGreenstein::new(g as f32);
    let mut ess = 0.0;
    for i in 0..BEAM_SAMPLES {
        let ti = t_crit - (1.0 - (i as f64 + 0.5) / BEAM_SAMPLES as f64).ln() / sigma_t;
        let d = (r * r + ti * ti).sqrt();
        let cos_o = ti / d;
        // Scattering from the downward beam into the direction up towards the exit point.
        let p = crate::media::hg_density(-cos_o as f32, phase.g) as f64;
        let ft = 1.0 - fr_dielectric(-cos_o as f32, eta) as f64;
        ess += rho * (-sigma_t * (d + t_crit)).exp() / (d * d) * p * ft * cos_o.abs();
    }
    ess / BEAM_SAMPLES as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial fits against midpoint quadrature of their definitions (fit error ≈ 2e-3).
    #[test]
    fn fresnel_moments_match_quadrature() {
        for eta in [0.75f32, 1.1, 1.33, 1.5, 2.0] {
            let n = 20_000;
            let (mut m1, mut m2) = (0.0f64, 0.0f64);
            for i in 0..n {
                let mu = (i as f64 + 0.5) / n as f64;
                // fr_dielectric takes η_transmitted/η_incident: the reciprocal of the fit's η.
                let fr = fr_dielectric(mu as f32, 1.0 / eta) as f64;
                m1 += fr * mu / n as f64;
                m2 += fr * mu * mu / n as f64;
            }
            assert!(
                (fresnel_moment1(eta) as f64 - m1).abs() < 5e-3,
                "η={eta}: FM1 fit {} vs {m1}",
                fresnel_moment1(eta)
            );
            assert!(
                (fresnel_moment2(eta) as f64 - m2).abs() < 5e-3,
                "η={eta}: FM2 fit {} vs {m2}",
                fresnel_moment2(eta)
            );
        }
    }
}
