//! Multiple importance sampling weights (Veach & Guibas 1995, "Optimally Combining Sampling
//! Techniques for Monte Carlo Rendering"; Veach's thesis §9.2).

use crate::simd::Real;

/// Balance heuristic w_f = n_f p_f / (n_f p_f + n_g p_g), for `nf` samples from density `f_pdf`
/// and `ng` from `g_pdf`. Returns 0 when both densities vanish.
#[inline]
pub fn balance_heuristic(nf: u32, f_pdf: f32, ng: u32, g_pdf: f32) -> f32 {
    let f = nf as f32 * f_pdf;
    let g = ng as f32 * g_pdf;
    if f.is_infinite() {
        return 1.0;
    }
    let sum = f + g;
    if sum > 0.0 {
        f / sum
    } else {
        0.0
    }
}

/// Power heuristic with β = 2: w_f = (n_f p_f)² / ((n_f p_f)² + (n_g p_g)²). An infinite f
/// density (a delta lobe) gets weight 1.
#[inline]
pub fn power_heuristic(nf: u32, f_pdf: f32, ng: u32, g_pdf: f32) -> f32 {
    power_heuristic_lanes(nf as f32 * f_pdf, ng as f32 * g_pdf)
}

/// [`power_heuristic`] for every lane, of the weighted densities f = n_f p_f and g = n_g p_g.
#[inline(always)]
pub fn power_heuristic_lanes<R: Real>(f: R, g: R) -> R {
    let (f2, g2) = (f * f, g * g);
    let sum = f2 + g2;
    let w = R::select(R::splat(0.0).lt(sum), f2 / sum, R::splat(0.0));
    R::select(f2.eq(R::splat(f32::INFINITY)), R::splat(1.0), w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_of_two_techniques_sum_to_one() {
        for &(a, b) in &[(0.3f32, 2.0f32), (1.0, 1.0), (1e-20, 5.0), (7.0, 0.0)] {
            let s = power_heuristic(1, a, 1, b) + power_heuristic(1, b, 1, a);
            assert!((s - 1.0).abs() < 1e-6, "{a} {b} {s}");
            let s = balance_heuristic(2, a, 3, b) + balance_heuristic(3, b, 2, a);
            assert!((s - 1.0).abs() < 1e-6, "{a} {b} {s}");
        }
    }

    #[test]
    fn known_values_and_edge_cases() {
        assert!((power_heuristic(1, 1.0, 1, 2.0) - 0.2).abs() < 1e-6);
        assert!((balance_heuristic(1, 1.0, 1, 3.0) - 0.25).abs() < 1e-6);
        assert_eq!(power_heuristic(1, 0.0, 1, 0.0), 0.0);
        assert_eq!(power_heuristic(1, f32::INFINITY, 1, 3.0), 1.0);
        assert_eq!(power_heuristic(1, 1e30, 1, 3.0), 1.0);
        assert_eq!(balance_heuristic(1, 0.0, 1, 0.0), 0.0);
    }
}
