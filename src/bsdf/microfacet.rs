//! Trowbridge–Reitz (GGX) microfacet distribution with Smith masking and visible-normal
//! sampling (Trowbridge & Reitz 1975; Walter et al. 2007; Heitz 2014 "Understanding the
//! Masking-Shadowing Function"; Heitz 2018 "Sampling the GGX Distribution of Visible Normals";
//! pbrt-v4 §9.6).

use super::local::{cos2_theta, tan2_theta};
use crate::math::{Vec2, Vec3, PI};
use crate::sampling::warp::sample_uniform_disk_polar;

/// Below this α a surface is treated as perfectly smooth (a delta lobe), like pbrt-v4's
/// `EffectivelySmooth`: the microfacet lobe would be narrower than f32 can resolve well.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// Anisotropic GGX with widths `alpha_x`, `alpha_y` along the shading tangents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    /// Width along the first tangent (α = roughness of the slope distribution).
    pub alpha_x: f32,
    /// Width along the second tangent.
    pub alpha_y: f32,
}

impl TrowbridgeReitz {
    /// Isotropic or anisotropic distribution; α clamped to ≥ 0.
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        let clean = |a: f32| if a.is_finite() { a.max(0.0) } else { 0.0 };
        Self { alpha_x: clean(alpha_x), alpha_y: clean(alpha_y) }
    }

    /// Perceptual roughness ∈ [0, 1] → α = √roughness (pbrt-v4 `RoughnessToAlpha`).
    pub fn roughness_to_alpha(roughness: f32) -> f32 {
        roughness.max(0.0).sqrt()
    }

    /// Path regularisation (Kaplanyan & Dachsbacher 2013, "Path Space Regularization for
    /// Holistic and Robust Light Transport"), as pbrt-v4's `TrowbridgeReitzDistribution::
    /// Regularize`: each α below 0.3 is doubled and kept within [0.1, 0.3], so a smooth or
    /// nearly smooth lobe becomes one light sampling can reach.
    pub fn regularize(&mut self) {
        let widen = |a: f32| if a < 0.3 { (2.0 * a).clamp(0.1, 0.3) } else { a };
        (self.alpha_x, self.alpha_y) = (widen(self.alpha_x), widen(self.alpha_y));
    }

    /// True when the lobe is treated as a delta (α < [`SMOOTH_ALPHA`]).
    #[inline]
    pub fn effectively_smooth(&self) -> bool {
        self.alpha_x.max(self.alpha_y) < SMOOTH_ALPHA
    }

    /// Normal distribution D(ωm) [1/sr]:
    /// 1 / (π αx αy cos⁴θm (1 + tan²θm (cos²φ/αx² + sin²φ/αy²))²).
    pub fn d(&self, wm: Vec3) -> f32 {
        let t2 = tan2_theta(wm);
        if !t2.is_finite() {
            return 0.0;
        }
        let c4 = cos2_theta(wm) * cos2_theta(wm);
        if c4 < 1e-16 {
            return 0.0;
        }
        let e = t2 * self.slope_weight(wm);
        1.0 / (PI * self.alpha_x * self.alpha_y * c4 * (1.0 + e) * (1.0 + e))
    }

    /// cos²φ/αx² + sin²φ/αy² for direction `w`.
    fn slope_weight(&self, w: Vec3) -> f32 {
        let r2 = w.x * w.x + w.y * w.y;
        if r2 == 0.0 {
            return 1.0 / (self.alpha_x * self.alpha_x);
        }
        (w.x * w.x / (self.alpha_x * self.alpha_x) + w.y * w.y / (self.alpha_y * self.alpha_y)) / r2
    }

    /// Smith's Λ(ω) = (√(1 + α² tan²θ) − 1)/2 with α the projected width along φ.
    pub fn lambda(&self, w: Vec3) -> f32 {
        let t2 = tan2_theta(w);
        if !t2.is_finite() {
            return f32::INFINITY;
        }
        let r2 = w.x * w.x + w.y * w.y;
        let alpha2 = if r2 == 0.0 {
            self.alpha_x * self.alpha_x
        } else {
            (w.x * w.x * self.alpha_x * self.alpha_x + w.y * w.y * self.alpha_y * self.alpha_y) / r2
        };
        0.5 * ((1.0 + alpha2 * t2).sqrt() - 1.0)
    }

    /// Smith masking G1(ω) = 1/(1 + Λ(ω)).
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing G(ωo, ωi) = 1/(1 + Λ(ωo) + Λ(ωi)) (Heitz 2014 eq. 99).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Distribution of normals visible from `w`: D_ω(ωm) = G1(ω) max(0, ω·ωm) D(ωm) / |cos θ|
    /// (Heitz 2014 eq. 38); also the density of [`Self::sample_wm`] [1/sr]. A `w` below the
    /// surface is mirrored to the upper side first, as in the sampling; `wm` has z > 0.
    pub fn pdf(&self, w: Vec3, wm: Vec3) -> f32 {
        self.visible_pdf(w, wm, self.d(wm), self.lambda(w))
    }

    /// [`Self::pdf`] given D(ωm) and Λ(ω), for callers that need them for the BSDF as well.
    #[inline]
    pub fn visible_pdf(&self, w: Vec3, wm: Vec3, d: f32, lambda: f32) -> f32 {
        let cos = w.z.abs();
        if cos == 0.0 {
            return 0.0;
        }
        let visible = (w.dot(wm) * w.z.signum()).max(0.0);
        d * visible / (cos * (1.0 + lambda))
    }

    /// Samples a visible normal for `w` (Heitz 2018): stretch to the α = 1 configuration,
    /// sample the projected hemisphere of visible normals there, unstretch.
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        let mut wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        let t1 = if wh.z < 0.99999 { Vec3::Z.cross(wh).normalize() } else { Vec3::X };
        let t2 = wh.cross(t1);
        let mut p = sample_uniform_disk_polar(u);
        // Warp the disk so its lower half covers only the visible part of the hemisphere.
        let h = (1.0 - p.x * p.x).max(0.0).sqrt();
        let s = 0.5 * (1.0 + wh.z);
        p.y = (1.0 - s) * h + s * p.y;
        let pz = (1.0 - p.length_squared()).max(0.0).sqrt();
        let nh = p.x * t1 + p.y * t2 + pz * wh;
        Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::Chi2Test;

    #[test]
    fn regularization_doubles_narrow_lobes_within_a_tenth_and_three_tenths() {
        // pbrt-v4's rule per axis: α < 0.3 → clamp(2α, 0.1, 0.3); wider lobes unchanged.
        for (a, want) in [(0.0, 0.1), (0.04, 0.1), (0.1, 0.2), (0.2, 0.3), (0.29, 0.3), (0.3, 0.3), (0.7, 0.7)] {
            let mut mf = TrowbridgeReitz::new(a, 0.7);
            mf.regularize();
            assert_eq!((mf.alpha_x, mf.alpha_y), (want, 0.7), "α = {a}");
        }
        let mut smooth = TrowbridgeReitz::new(0.0, 0.0);
        smooth.regularize();
        assert!(!smooth.effectively_smooth());
    }

    #[test]
    fn projected_area_of_normals_is_one() {
        // ∫ D(ωm) cos θm dωm = 1 (midpoint rule in (θ, φ)).
        for &a in &[0.05f32, 0.3, 1.0] {
            let mf = TrowbridgeReitz::new(a, a * 0.7);
            let (nt, np) = (4000, 64);
            let mut sum = 0.0f64;
            for i in 0..nt {
                let th = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
                for j in 0..np {
                    let ph = (j as f64 + 0.5) / np as f64 * 2.0 * std::f64::consts::PI;
                    let w = Vec3::new((th.sin() * ph.cos()) as f32, (th.sin() * ph.sin()) as f32, th.cos() as f32);
                    sum += mf.d(w) as f64 * th.cos() * th.sin();
                }
            }
            sum *= std::f64::consts::FRAC_PI_2 / nt as f64 * 2.0 * std::f64::consts::PI / np as f64;
            assert!((sum - 1.0).abs() < 2e-3, "α = {a}: {sum}");
        }
    }

    #[test]
    fn visible_normal_sampling_passes_chi2() {
        let suite: Vec<(f32, f32, f32)> = vec![(0.2, 0.2, 0.3), (0.5, 0.2, 1.2), (1.0, 1.0, 1.5)];
        for &(ax, ay, theta) in &suite {
            let mf = TrowbridgeReitz::new(ax, ay);
            let w = Vec3::new(theta.sin() * 0.6, theta.sin() * 0.8, theta.cos());
            let t = Chi2Test { sample_count: 300_000, test_count: suite.len(), ..Chi2Test::default() };
            let r = t.run(|_, u| Some(mf.sample_wm(w, u)), |wm| if wm.z > 0.0 { mf.pdf(w, wm) } else { 0.0 });
            assert!(r.passed, "α = ({ax}, {ay}), θ = {theta}: {r}");
        }
    }
}
