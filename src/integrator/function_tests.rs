//! The `function` integrator's integrands against quadrature, and its error curves against what
//! the samplers' constructions imply: 1/n for independent samples, zero for the step at the
//! counts whose strata split the square at x = ½.

use super::{FunctionTest, FunctionTestError};
use crate::sampling::{Randomize, SamplerKind, TestFunction};

/// ∫f over [0, 1]² by rows: 2048 rows at their midpoints, each integrated over x by 2048
/// midpoints shifted by its own fraction of a step (the golden-ratio sequence), so that the
/// errors at the discontinuities of different rows are independent, about ±h/√12 each (h =
/// 1/2048), instead of adding up along a line through the grid.
fn quadrature(f: TestFunction) -> f64 {
    const N: u32 = 2048;
    let h = 1.0 / f64::from(N);
    let golden = (5f64.sqrt() - 1.0) / 2.0;
    let mut sum = 0.0;
    for j in 0..N {
        let y = (f64::from(j) + 0.5) * h;
        let shift = (f64::from(j) * golden).fract();
        sum += (0..N).map(|i| f.eval((f64::from(i) + shift) * h, y)).sum::<f64>();
    }
    sum * h * h
}

#[test]
fn every_function_integrates_to_one() {
    // The rotated checkerboard crosses a row at most 15 times: a row's error is at most about
    // √15 · 2h/√12 ≈ 1.1e-3, their mean over 2048 rows about 2.4e-5; 2e-4 is 8 of those.
    for &(name, f) in TestFunction::NAMES {
        let integral = quadrature(f);
        assert!((integral - 1.0).abs() < 2e-4, "{name}: ∫f = {integral}");
    }
}

/// A test of 64 × 64 pixels, seed 7.
fn test(function: TestFunction, sampler: SamplerKind, spp: u64, skip_bad: bool) -> FunctionTest {
    FunctionTest { function, sampler, spp, resolution: (64, 64), pixels: ((0, 64), (0, 64)), seed: 7, skip_bad }
}

/// MSE(n) of a curve.
fn mse_at(points: &[(u64, f64)], n: u64) -> f64 {
    points.iter().find(|p| p.0 == n).unwrap_or_else(|| panic!("no count {n} in {points:?}")).1
}

#[test]
fn independent_samples_err_as_one_over_n() {
    // The step is 0 or 2 with probability ½: f − 1 = ±1, Var f = 1, so MSE(n) = 1/n, and
    // exactly 1 at n = 1. The pixel mean of (I_n − 1)² has relative standard error
    // √((κ − 1)/P), κ = E[d⁴]/E[d²]² = 3 − 2/n for a binomial mean, P = 4096 pixels: 2.1 %
    // at n = 16 and 2.2 % at n = 256. 4σ allowed, on each and on their ratio.
    let curve = test(TestFunction::Step, SamplerKind::Independent, 256, true).run().unwrap();
    assert_eq!(curve.points.len(), 256, "every count is natural to the independent sampler");
    assert!((mse_at(&curve.points, 1) - 1.0).abs() < 1e-12, "{:?}", &curve.points[..2]);
    let rel_se = |n: f64| ((2.0 - 2.0 / n) / 4096.0).sqrt();
    for n in [16u64, 256] {
        let scaled = mse_at(&curve.points, n) * n as f64;
        assert!((scaled - 1.0).abs() < 4.0 * rel_se(n as f64), "n = {n}: n·MSE = {scaled}");
    }
    let ratio = mse_at(&curve.points, 16) / mse_at(&curve.points, 256);
    let ratio_se = 16.0 * (rel_se(16.0).powi(2) + rel_se(256.0).powi(2)).sqrt();
    assert!((ratio - 16.0).abs() < 4.0 * ratio_se, "MSE(16)/MSE(256) = {ratio}");
    // The pixels' mean estimate at 256 samples: 1 ± 1/√(256 · 4096).
    let se = 1.0 / (256.0f64 * 4096.0).sqrt();
    assert!((curve.mean_estimate - 1.0).abs() < 4.0 * se, "mean {}", curve.mean_estimate);
}

#[test]
fn samplers_stratified_at_x_one_half_integrate_the_step_exactly_at_their_counts() {
    // Whenever a sampler's n points fall one per column of an even number of columns, half of
    // them land in x < ½ and I_n = 1 exactly: stratified at 4 = 2², 16 = 4², 36, 64;
    // (padded, Owen-scrambled) Sobol' at every power of two from 2; Halton at 6 and 36 (its x
    // is the base-2 radical inverse of consecutive indices). Independent samples err as 1/n.
    let step = TestFunction::Step;
    let fast = Randomize::FastOwen;
    let cases = [
        (SamplerKind::Stratified { x: 8, y: 8, jitter: true }, vec![4, 16, 36, 64]),
        (SamplerKind::PaddedSobol(fast), vec![2, 4, 8, 16, 32, 64]),
        (SamplerKind::Sobol, vec![2, 4, 8, 16, 32, 64]),
        (SamplerKind::Halton(Randomize::PermuteDigits), vec![6, 36]),
    ];
    for (sampler, exact) in cases {
        let curve = test(step, sampler, 64, true).run().unwrap();
        for n in exact {
            assert_eq!(mse_at(&curve.points, n), 0.0, "{} at {n}: {:?}", sampler.name(), curve.points);
        }
    }
    // The others are not exact but well below 1/n at a power of two.
    for sampler in [SamplerKind::ZSobol(fast), SamplerKind::Pmj02bn] {
        let mse = mse_at(&test(step, sampler, 64, true).run().unwrap().points, 64);
        assert!(mse < 0.1 / 64.0, "{}: MSE(64) = {mse}", sampler.name());
    }
}

#[test]
fn skipbad_reports_the_counts_each_sampler_is_made_for() {
    let counts = |sampler, spp, skip_bad| test(TestFunction::Disk, sampler, spp, skip_bad).counts();
    let stratified = SamplerKind::Stratified { x: 4, y: 4, jitter: true };
    assert_eq!(counts(stratified, 20, true), [1, 4, 9, 16]);
    assert_eq!(counts(SamplerKind::PaddedSobol(Randomize::Owen), 20, true), [1, 2, 4, 8, 16]);
    assert_eq!(counts(SamplerKind::Halton(Randomize::Owen), 250, true), [1, 6, 36, 216]);
    assert_eq!(counts(SamplerKind::Independent, 5, true), [1, 2, 3, 4, 5]);
    assert_eq!(counts(stratified, 5, false), [1, 2, 3, 4, 5]);
    // The curve has a point at each, and without skipbad a stratified grid for each count.
    let curve = test(TestFunction::Step, stratified, 6, false).run().unwrap();
    assert_eq!(curve.points.iter().map(|p| p.0).collect::<Vec<_>>(), [1, 2, 3, 4, 5, 6]);
    // 2 = 2×1 and 6 = 3×2 strata: x split at ½ for 2 (exact), not for 6 (3 columns).
    assert_eq!(mse_at(&curve.points, 2), 0.0);
    assert!(mse_at(&curve.points, 6) > 0.0);
}

#[test]
fn the_global_sobol_sampler_is_refused_and_the_text_has_a_line_per_count() {
    let global = test(TestFunction::Step, SamplerKind::GlobalSobol(Randomize::FastOwen), 4, true);
    assert_eq!(global.run(), Err(FunctionTestError::GlobalSobol));
    let curve = test(TestFunction::Step, SamplerKind::PaddedSobol(Randomize::Owen), 4, true).run().unwrap();
    assert_eq!(curve.text(), "1 1\n2 0\n4 0\n");
    assert!(!curve.suspicious());
}
