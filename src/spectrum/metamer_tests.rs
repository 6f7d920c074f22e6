//! Metamers: clearly different SPDs with the same XYZ.

use super::cie::xyz_of;
use super::Spectrum;
use glam::{DMat3, DVec3};

/// A hat of half-width 40 nm centred on `c` [nm].
fn hat(c: f64, l: f64) -> f64 {
    (1.0 - (l - c).abs() / 40.0).max(0.0)
}

#[test]
fn metameric_pair_has_the_same_xyz_but_a_different_spectrum() {
    // Start from a flat grey 0.5 and add a "metameric black" Σ aₖ hatₖ whose XYZ is zero:
    // fix a₃ = 0.3 and solve the 3×3 system for a₀..a₂ so that the X, Y, Z integrals cancel.
    let centres = [440.0, 520.0, 600.0, 480.0];
    let h = |k: usize| xyz_of(|l| hat(centres[k], l), &[centres[k] - 40.0, centres[k], centres[k] + 40.0]);
    let m = DMat3::from_cols(h(0), h(1), h(2));
    let a3 = 0.3;
    let a = m.inverse() * (-a3 * h(3));
    let coef = [a.x, a.y, a.z, a3];
    let lambdas: Vec<f64> = (0..=470).map(|i| 360.0 + i as f64).collect();
    let grey = Spectrum::constant(0.5);
    let values =
        lambdas.iter().map(|&l| 0.5 + (0..4).map(|k| coef[k] * hat(centres[k], l)).sum::<f64>()).collect::<Vec<_>>();
    assert!(values.iter().all(|&v| v >= 0.0), "physically realisable");
    let metamer = Spectrum::piecewise_linear_f64(lambdas.clone(), values).unwrap();
    let (x1, x2) = (grey.to_xyz_f64(), metamer.to_xyz_f64());
    assert!((x1 - x2).abs().max_element() < 1e-6, "{x1} vs {x2}");
    // ...yet the spectra differ by far more than the XYZ tolerance.
    let diff = lambdas.iter().map(|&l| (grey.eval_f64(l) - metamer.eval_f64(l)).abs()).fold(0.0, f64::max);
    assert!(diff > 0.1, "{diff}");
    assert!(x1 != DVec3::ZERO);
}
