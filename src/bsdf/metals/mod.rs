//! Measured complex refractive indices η + ik of metals, as plain (λ [nm], value) tables with
//! piecewise-linear evaluation. Sources: Johnson & Christy 1972 (Ag, Au, Cu) and 1974 (Cr, Ti)
//! as tabulated by refractiveindex.info (CC0); Al from the luxpop.com data shipped with
//! Mitsuba 0.6 (`data/ior/Al.*.spd`). Each table covers at least 290–880 nm.

mod tables;

/// A measured spectrum: (wavelength [nm], value) pairs sorted by wavelength.
pub type SpectrumTable = &'static [(f32, f32)];

/// Metals available, by chemical symbol.
pub const METALS: &[&str] = &["Ag", "Al", "Au", "Cr", "Cu", "Ti"];

/// (η, k) tables of a metal by symbol ("Cu") or pbrt-v4 spectrum name ("metal-Cu-eta" or
/// "metal-Cu-k": either selects the pair).
pub fn metal_eta_k(name: &str) -> Option<(SpectrumTable, SpectrumTable)> {
    let symbol = name
        .strip_prefix("metal-")
        .map(|s| s.strip_suffix("-eta").or_else(|| s.strip_suffix("-k")).unwrap_or(s))
        .unwrap_or(name);
    Some(match symbol.to_ascii_lowercase().as_str() {
        "ag" | "silver" => (tables::AG_ETA, tables::AG_K),
        "al" | "aluminium" | "aluminum" => (tables::AL_ETA, tables::AL_K),
        "au" | "gold" => (tables::AU_ETA, tables::AU_K),
        "cr" | "chromium" => (tables::CR_ETA, tables::CR_K),
        "cu" | "copper" => (tables::CU_ETA, tables::CU_K),
        "ti" | "titanium" => (tables::TI_ETA, tables::TI_K),
        _ => return None,
    })
}

/// The single table named by a pbrt-v4 spectrum name, e.g. "metal-Au-k".
pub fn named_spectrum(name: &str) -> Option<SpectrumTable> {
    let (eta, k) = metal_eta_k(name)?;
    if name.ends_with("-eta") {
        Some(eta)
    } else if name.ends_with("-k") {
        Some(k)
    } else {
        None
    }
}

/// Piecewise-linear interpolation of a table sorted by wavelength; clamped to the end values
/// outside its range; 0 for an empty table or a NaN wavelength.
pub fn eval_piecewise_linear(table: &[(f32, f32)], lambda_nm: f32) -> f32 {
    let (Some(first), Some(last)) = (table.first(), table.last()) else {
        return 0.0;
    };
    if lambda_nm.is_nan() {
        return 0.0;
    }
    if lambda_nm <= first.0 {
        return first.1;
    }
    if lambda_nm >= last.0 {
        return last.1;
    }
    let i = table.partition_point(|&(l, _)| l <= lambda_nm);
    let ((l0, v0), (l1, v1)) = (table[i - 1], table[i]);
    let t = (lambda_nm - l0) / (l1 - l0);
    v0 + t * (v1 - v0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::fr_complex;

    #[test]
    fn every_metal_covers_the_visible_range_and_is_sorted() {
        for &m in METALS {
            let (eta, k) = metal_eta_k(m).unwrap();
            for t in [eta, k] {
                assert!(t.first().unwrap().0 <= 300.0 && t.last().unwrap().0 >= 880.0, "{m}");
                assert!(t.windows(2).all(|w| w[0].0 < w[1].0), "{m}");
                assert!(t.iter().all(|&(_, v)| v > 0.0 && v < 20.0), "{m}");
            }
            assert_eq!(metal_eta_k(&format!("metal-{m}-eta")), Some((eta, k)));
            assert_eq!(named_spectrum(&format!("metal-{m}-k")), Some(k));
        }
        assert_eq!(metal_eta_k("metal-Unobtainium-eta"), None);
    }

    #[test]
    fn interpolation_hits_nodes_and_midpoints() {
        let t = [(400.0, 1.0), (500.0, 3.0)];
        assert_eq!(eval_piecewise_linear(&t, 400.0), 1.0);
        assert_eq!(eval_piecewise_linear(&t, 450.0), 2.0);
        assert_eq!(eval_piecewise_linear(&t, 300.0), 1.0);
        assert_eq!(eval_piecewise_linear(&t, 900.0), 3.0);
        assert_eq!(eval_piecewise_linear(&[], 500.0), 0.0);
        assert_eq!(eval_piecewise_linear(&t, f32::NAN), 0.0);
    }

    #[test]
    fn normal_incidence_reflectance_matches_known_colours() {
        // Gold and copper reflect red far better than blue; silver and aluminium are bright
        // and flat (> 0.85 over 450–700 nm).
        let r = |m: &str, l: f32| {
            let (e, k) = metal_eta_k(m).unwrap();
            fr_complex(1.0, eval_piecewise_linear(e, l), eval_piecewise_linear(k, l))
        };
        assert!(r("Au", 650.0) > 0.9 && r("Au", 450.0) < 0.45);
        assert!(r("Cu", 650.0) > 0.9 && r("Cu", 450.0) < 0.65);
        for l in [450.0, 550.0, 650.0, 700.0] {
            assert!(r("Ag", l) > 0.9 && r("Al", l) > 0.85, "{l}");
        }
        assert!(r("Cr", 550.0) > 0.5 && r("Cr", 550.0) < 0.7);
        assert!(r("Ti", 550.0) > 0.45 && r("Ti", 550.0) < 0.65);
    }
}
