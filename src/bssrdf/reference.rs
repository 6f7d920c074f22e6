//! Closed forms for the total diffuse reflectance of a semi-infinite medium, the yardsticks of
//! the diffusion table and of the random walk.

/// Exact total reflectance (planar albedo) of an index-matched semi-infinite medium with
/// isotropic scattering and single-scattering albedo `omega`, lit by a collimated beam at
/// cos θ = `mu0`: A(μ₀) = 1 − H(μ₀) √(1 − ω), with Chandrasekhar's H-function solved from
/// 1/H(μ) = √(1 − ω) + (ω/2) ∫₀¹ μ′ H(μ′)/(μ + μ′) dμ′ (Chandrasekhar 1960, "Radiative
/// Transfer", §29 eq. 59 and §45) by fixed-point iteration on a midpoint grid.
pub fn half_space_albedo(omega: f64, mu0: f64) -> f64 {
    let omega = omega.clamp(0.0, 1.0);
    let n = 2000;
    let mu: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) / n as f64).collect();
    let s = (1.0 - omega).sqrt();
    let mut h = vec![1.0f64; n];
    let integral =
        |h: &[f64], x: f64| -> f64 { mu.iter().zip(h).map(|(&m, &hm)| m * hm / (x + m)).sum::<f64>() / n as f64 };
    for _ in 0..500 {
        let next: Vec<f64> = mu.iter().map(|&x| 1.0 / (s + 0.5 * omega * integral(&h, x))).collect();
        let change = next.iter().zip(&h).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        h = next;
        if change < 1e-10 {
            break;
        }
    }
    let h_mu0 = 1.0 / (s + 0.5 * omega * integral(&h, mu0));
    1.0 - h_mu0 * s
}

/// Total diffuse reflectance of the classical dipole (Jensen et al. 2001, "A Practical Model
/// for Subsurface Light Transport", eq. 5 integrated): R_d = (α′/2)(1 + e^{−(4/3)A√(3(1−α′))})
/// e^{−√(3(1−α′))}, with reduced albedo α′ and A = (1 + F_dr)/(1 − F_dr), F_dr the diffuse
/// Fresnel reflectance fit of Egan & Hilgeman for relative index η.
pub fn dipole_total_reflectance(alpha_prime: f64, eta: f64) -> f64 {
    let f_dr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    let a = (1.0 + f_dr) / (1.0 - f_dr);
    let s = (3.0 * (1.0 - alpha_prime)).sqrt();
    0.5 * alpha_prime * (1.0 + (-4.0 / 3.0 * a * s).exp()) * (-s).exp()
}
