//! Smits' RGB → spectrum method (B. Smits, "An RGB-to-Spectrum Conversion for Reflectances",
//! JGT 4(4), 1999): remove the smallest component as white,
//! then the smaller of the remaining pair as cyan/magenta/yellow, then the last as
//! red/green/blue, adding each basis SPD with the amount removed. Not linear in RGB.

use super::color_space::ColorSpace;
use super::data::{SMITS_BLUE, SMITS_CYAN, SMITS_GREEN, SMITS_MAGENTA, SMITS_RED};
use super::data::{SMITS_WHITE, SMITS_YELLOW};
use super::spd::Spectrum;

/// Whether the spectrum describes a reflectance or an emitter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmitsKind {
    /// Smits' reflectance basis as published.
    Reflectance,
    /// The reflectance basis times the colour space's white illuminant (Y = 1), so that
    /// (1,1,1) is that white: the illumination basis set. Smits published only reflectance
    /// spectra; this keeps W ↦ the space's white, which is what an emitter basis must do.
    Illumination,
}

/// One of Smits' seven basis spectra.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmitsBasis {
    /// W(λ).
    White,
    /// C(λ) = green + blue.
    Cyan,
    /// M(λ) = red + blue.
    Magenta,
    /// Y(λ) = red + green.
    Yellow,
    /// R(λ).
    Red,
    /// G(λ).
    Green,
    /// B(λ).
    Blue,
}

impl SmitsBasis {
    fn table(self) -> &'static [f64; 10] {
        match self {
            SmitsBasis::White => &SMITS_WHITE,
            SmitsBasis::Cyan => &SMITS_CYAN,
            SmitsBasis::Magenta => &SMITS_MAGENTA,
            SmitsBasis::Yellow => &SMITS_YELLOW,
            SmitsBasis::Red => &SMITS_RED,
            SmitsBasis::Green => &SMITS_GREEN,
            SmitsBasis::Blue => &SMITS_BLUE,
        }
    }

    /// The basis reflectance at `lambda` [nm]: linear between Smits' 10 samples (380–720 nm,
    /// spacing 340/9 nm), held constant beyond them.
    pub fn eval(self, lambda: f64) -> f64 {
        let t = self.table();
        let u = ((lambda - 380.0) / (340.0 / 9.0)).clamp(0.0, 9.0);
        let i = (u as usize).min(8);
        let f = u - i as f64;
        t[i] + f * (t[i + 1] - t[i])
    }
}

/// One step of the decomposition: S(λ) += `amount` · `basis`(λ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmitsStep {
    /// The basis spectrum added.
    pub basis: SmitsBasis,
    /// How much of it (the component value removed from the triplet).
    pub amount: f64,
}

/// Smits' decomposition of `rgb` (components clamped to ≥ 0), skipping zero steps.
pub fn smits_steps(rgb: [f64; 3]) -> Vec<SmitsStep> {
    let mut c = rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
    let mut steps = Vec::with_capacity(3);
    let mut push = |basis, amount: f64| {
        if amount > 0.0 {
            steps.push(SmitsStep { basis, amount });
        }
    };
    // 1. The smallest of the three is white.
    let lo = (0..3).min_by(|&a, &b| c[a].total_cmp(&c[b])).unwrap_or(0);
    let w = c[lo];
    push(SmitsBasis::White, w);
    c.iter_mut().for_each(|v| *v -= w);
    // 2. The smaller of the other two is the secondary (complement of the zeroed one).
    let (a, b) = ((lo + 1) % 3, (lo + 2) % 3);
    let pair = c[a].min(c[b]);
    let secondary = [SmitsBasis::Cyan, SmitsBasis::Magenta, SmitsBasis::Yellow][lo];
    push(secondary, pair);
    c[a] -= pair;
    c[b] -= pair;
    // 3. What is left is a primary.
    let last = if c[a] >= c[b] { a } else { b };
    let primary = [SmitsBasis::Red, SmitsBasis::Green, SmitsBasis::Blue][last];
    push(primary, c[last]);
    steps
}

/// Smits' spectrum for `rgb`: Σ amount · basis, on the 10-sample grid extended to 360–830 nm;
/// for `Illumination`, times `space`'s white illuminant.
pub fn smits_spectrum(rgb: [f64; 3], kind: SmitsKind, space: &ColorSpace) -> Spectrum {
    let steps = smits_steps(rgb);
    let mut lambdas = vec![360.0];
    lambdas.extend((0..10).map(|i| 380.0 + 340.0 / 9.0 * i as f64));
    lambdas.push(830.0);
    let values = lambdas.iter().map(|&l| steps.iter().map(|s| s.amount * s.basis.eval(l)).sum::<f64>());
    // Smits' published red basis peaks at 1.0149: a reflectance must not exceed 1 (energy
    // conservation), so the reflectance form is clamped; the emitter form is unbounded.
    let values = match kind {
        SmitsKind::Reflectance => values.map(|v| v.clamp(0.0, 1.0)).collect(),
        SmitsKind::Illumination => values.map(|v| v.max(0.0)).collect(),
    };
    let s = Spectrum::piecewise_linear_f64(lambdas, values).expect("fixed grid is well formed");
    match kind {
        SmitsKind::Reflectance => s,
        SmitsKind::Illumination => s.product(space.illuminant.clone()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worked_example_decomposes_into_white_magenta_red() {
        // Worked example (0.6, 0.2, 0.5): white 0.2 (the minimum) leaves (0.4, 0, 0.3); magenta 0.3
        // (the smaller of red and blue) leaves (0.1, 0, 0); red 0.1.
        let s = smits_steps([0.6, 0.2, 0.5]);
        assert_eq!(s.len(), 3);
        assert_eq!(s[0].basis, SmitsBasis::White);
        assert!((s[0].amount - 0.2).abs() < 1e-12);
        assert_eq!(s[1].basis, SmitsBasis::Magenta);
        assert!((s[1].amount - 0.3).abs() < 1e-12);
        assert_eq!(s[2].basis, SmitsBasis::Red);
        assert!((s[2].amount - 0.1).abs() < 1e-12);
    }

    #[test]
    fn every_ordering_picks_the_right_bases() {
        let cases = [
            ([0.1, 0.5, 0.3], [SmitsBasis::White, SmitsBasis::Cyan, SmitsBasis::Green]),
            ([0.5, 0.1, 0.3], [SmitsBasis::White, SmitsBasis::Magenta, SmitsBasis::Red]),
            ([0.3, 0.5, 0.1], [SmitsBasis::White, SmitsBasis::Yellow, SmitsBasis::Green]),
            ([0.2, 0.4, 0.9], [SmitsBasis::White, SmitsBasis::Cyan, SmitsBasis::Blue]),
        ];
        for (rgb, bases) in cases {
            let s = smits_steps(rgb);
            let got: Vec<_> = s.iter().map(|x| x.basis).collect();
            assert_eq!(got, bases, "{rgb:?}");
            let total: f64 = s.iter().map(|x| x.amount).sum();
            assert!((total - rgb.iter().cloned().fold(0.0, f64::max)).abs() < 1e-12);
        }
    }

    #[test]
    fn grey_is_white_and_sum_matches_samples() {
        let s = smits_steps([0.5, 0.5, 0.5]);
        assert_eq!(s, vec![SmitsStep { basis: SmitsBasis::White, amount: 0.5 }]);
        let sp = smits_spectrum([0.6, 0.2, 0.5], SmitsKind::Reflectance, ColorSpace::srgb());
        let l = 380.0 + 340.0 / 9.0 * 3.0;
        let want = 0.2 * SMITS_WHITE[3] + 0.3 * SMITS_MAGENTA[3] + 0.1 * SMITS_RED[3];
        assert!((sp.eval_f64(l) - want).abs() < 1e-12);
        assert_eq!(sp.eval_f64(365.0), sp.eval_f64(380.0));
    }

    #[test]
    fn not_linear_in_rgb() {
        let a = smits_spectrum([0.6, 0.2, 0.5], SmitsKind::Reflectance, ColorSpace::srgb());
        let b = smits_spectrum([0.2, 0.6, 0.5], SmitsKind::Reflectance, ColorSpace::srgb());
        let sum = smits_spectrum([0.8, 0.8, 1.0], SmitsKind::Reflectance, ColorSpace::srgb());
        let gap = (400..=700)
            .map(|l| (a.eval_f64(l as f64) + b.eval_f64(l as f64) - sum.eval_f64(l as f64)).abs())
            .fold(0.0, f64::max);
        assert!(gap > 1e-3, "{gap}");
    }
}
