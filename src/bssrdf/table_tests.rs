use super::*;
use crate::bssrdf::reference::{dipole_total_reflectance, half_space_albedo};
use crate::math::{Vec2, Vec3, PI};
use crate::sampling::chi2::{Chi2Test, Domain};

#[test]
fn radius_sampling_matches_the_profile_chi2() {
    let table = BssrdfTable::new(0.0, 1.33);
    let rhos = [0.3f32, 0.9, 0.995];
    for rho in rhos {
        // A square covering ~95 % of the mass; the rest falls in the χ² test's outside cell.
        let half = table.sample_radius(rho, 0.95).unwrap();
        let test = Chi2Test {
            domain: Domain::Plane { min: Vec2::splat(-half), max: Vec2::splat(half) },
            theta_res: 40,
            phi_res: 40,
            sample_count: 200_000,
            test_count: rhos.len(),
            ..Default::default()
        };
        let r = test.run(
            |_, u| {
                let r = table.sample_radius(rho, u.x)?;
                let phi = 2.0 * PI * u.y;
                Some(Vec3::new(r * phi.cos(), r * phi.sin(), 0.0))
            },
            // Planar density = radial density / (2π r).
            |p| {
                let r = p.truncate().length();
                if r > 0.0 {
                    table.radius_pdf(rho, r) / (2.0 * PI * r)
                } else {
                    0.0
                }
            },
        );
        assert!(r.passed, "ρ = {rho}: {r}");
    }
}

#[test]
fn effective_albedo_is_monotone_and_inverts() {
    let table = BssrdfTable::new(0.0, 1.33);
    let mut prev = -1.0;
    for k in 0..=200 {
        let rho = k as f32 / 200.0;
        let e = table.rho_eff(rho);
        assert!(e >= prev && e <= 1.0, "ρ_eff({rho}) = {e} after {prev}");
        prev = e;
        if (0.05..0.99).contains(&rho) {
            let back = table.invert_rho_eff(e);
            assert!((back - rho).abs() < 2e-3, "invert(ρ_eff({rho})) = {back}");
        }
    }
    assert_eq!(table.invert_rho_eff(-1.0), 0.0);
    assert_eq!(table.invert_rho_eff(2.0), 1.0);
}

/// The tabulated PBD total reflectance against two closed forms. Diffusion theory is an
/// approximation, so the tolerances are the model's error as measured here, stated:
/// - index-matched (η = 1), isotropic: the exact half-space albedo (Chandrasekhar's H-function).
///   PBD overestimates by 6–14 % for ρ ∈ [0.3, 0.999] (0.1284 vs 0.1152 at ρ = 0.5, 0.8426 vs
///   0.7527 at 0.99); tolerance 15 % relative, and 0.01 absolute below ρ = 0.3;
/// - η = 1.33: the classical dipole of Jensen et al. 2001 (different boundary condition, no
///   exact single scattering): within 11 % for ρ ≥ 0.5 (0.0664 vs 0.0742 at ρ = 0.5).
#[test]
fn pbd_total_reflectance_matches_closed_forms() {
    let matched = BssrdfTable::new(0.0, 1.0);
    let water = BssrdfTable::new(0.0, 1.33);
    for rho in [0.1f32, 0.2, 0.3, 0.5, 0.8, 0.9, 0.95, 0.99, 0.999] {
        let exact = half_space_albedo(rho as f64, 1.0);
        let pbd = matched.rho_eff(rho) as f64;
        let ok = if rho >= 0.3 { (pbd - exact).abs() < 0.15 * exact } else { (pbd - exact).abs() < 0.01 };
        assert!(ok, "η=1, ρ={rho}: PBD {pbd:.4} vs exact {exact:.4}");
        if rho >= 0.5 {
            let dipole = dipole_total_reflectance(rho as f64, 1.33);
            let pbd = water.rho_eff(rho) as f64;
            assert!((pbd - dipole).abs() < 0.11 * dipole, "η=1.33, ρ={rho}: PBD {pbd:.4} vs dipole {dipole:.4}");
        }
    }
    // Energy: never more than everything back, and all of it at ρ = 1 (after the row scaling).
    assert!((water.rho_eff(1.0) - 1.0).abs() < 1e-6 && (matched.rho_eff(1.0) - 1.0).abs() < 1e-6);
}

#[test]
fn half_space_albedo_limits() {
    // ω = 1: everything comes back; ω = 0: nothing does.
    assert!((half_space_albedo(1.0, 1.0) - 1.0).abs() < 1e-3);
    assert!(half_space_albedo(0.0, 1.0).abs() < 1e-9);
}
