//! Walker's alias method with Vose's O(n) construction (Vose 1991, "A Linear Algorithm for
//! Generating Random Numbers with a Given Distribution"; pbrt-v4 `AliasTable`): O(1) sampling of
//! an index with probability proportional to a weight, e.g. picking a light by power.

/// One bin: keep its own index with probability `q`, otherwise return `alias`.
#[derive(Clone, Copy, Debug)]
struct Bin {
    q: f32,
    alias: u32,
    pmf: f32,
}

/// A discrete distribution over `0..len()` proportional to the construction weights.
#[derive(Clone, Debug, Default)]
pub struct AliasTable {
    bins: Vec<Bin>,
}

impl AliasTable {
    /// A table for `weights`. Negative, NaN and infinite weights count as 0; when all weights are 0
    /// the distribution is uniform. Sums are accumulated in f64 so millions of entries keep their
    /// relative precision.
    pub fn new(weights: &[f32]) -> Self {
        let clean = |w: f32| {
            if w.is_finite() && w > 0.0 {
                w as f64
            } else {
                0.0
            }
        };
        let n = weights.len();
        if n == 0 {
            return Self::default();
        }
        let total: f64 = weights.iter().map(|&w| clean(w)).sum();
        let pmf: Vec<f64> =
            if total > 0.0 { weights.iter().map(|&w| clean(w) / total).collect() } else { vec![1.0 / n as f64; n] };
        // Scaled probabilities p·n: bins under 1 are topped up from bins over 1.
        let mut scaled: Vec<f64> = pmf.iter().map(|&p| p * n as f64).collect();
        let mut bins: Vec<Bin> =
            pmf.iter().enumerate().map(|(i, &p)| Bin { q: 1.0, alias: i as u32, pmf: p as f32 }).collect();
        let (mut under, mut over): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(&u), Some(&o)) = (under.last(), over.last()) {
            under.pop();
            bins[u].q = scaled[u] as f32;
            bins[u].alias = o as u32;
            // The donor gives away 1 - scaled[u]; rounding can leave it just under 1.
            scaled[o] = (scaled[o] + scaled[u]) - 1.0;
            if scaled[o] < 1.0 {
                over.pop();
                under.push(o);
            }
        }
        // Leftovers on either list are 1 up to rounding: they keep themselves (q = 1 by default).
        Self { bins }
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.bins.len()
    }

    /// True when built from no weights; `sample` then returns (0, 0).
    pub fn is_empty(&self) -> bool {
        self.bins.is_empty()
    }

    /// Index with probability `pmf(index)`, and that probability, for uniform `u` in [0, 1).
    /// Resolution: one f32 `u` holds 24 bits, so tables beyond ~2²⁰ entries lose some accuracy in
    /// the keep-or-alias choice (the index itself is exact up to 2²⁴ entries).
    #[inline]
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let n = self.bins.len();
        if n == 0 {
            return (0, 0.0);
        }
        let scaled = u.clamp(0.0, 1.0) as f64 * n as f64;
        let i = (scaled as usize).min(n - 1);
        // The fractional part is a fresh uniform deciding between the bin and its alias.
        let up = (scaled - i as f64) as f32;
        let bin = &self.bins[i];
        let k = if up < bin.q { i } else { bin.alias as usize };
        (k, self.bins[k].pmf)
    }

    /// Probability of index `i` (0 when out of range).
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.bins.get(i).map_or(0.0, |b| b.pmf)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Upper 1 − α quantile of χ²(df), Wilson–Hilferty approximation (accurate to ~1% for
    /// df ≥ 10). z = 3.09 for α = 0.001.
    pub(crate) fn chi2_critical(df: f64, z: f64) -> f64 {
        let a = 2.0 / (9.0 * df);
        df * (1.0 - a + z * a.sqrt()).powi(3)
    }

    /// Pearson χ² of sampled counts against the table's pmf.
    fn chi2(table: &AliasTable, n: usize, seed: u64) -> (f64, f64) {
        let mut counts = vec![0u64; table.len()];
        let mut rng = Rng::new(seed, 0);
        for _ in 0..n {
            let (i, p) = table.sample(rng.uniform());
            assert_eq!(p, table.pmf(i));
            counts[i] += 1;
        }
        let mut stat = 0.0;
        let mut df = -1.0;
        for (i, &c) in counts.iter().enumerate() {
            let expected = table.pmf(i) as f64 * n as f64;
            if expected > 0.0 {
                stat += (c as f64 - expected).powi(2) / expected;
                df += 1.0;
            } else {
                assert_eq!(c, 0, "sampled a zero-weight entry {i}");
            }
        }
        (stat, df)
    }

    #[test]
    fn samples_follow_weights_chi2() {
        let weights: Vec<f32> =
            (0..200).map(|i| if i % 7 == 3 { 0.0 } else { 1.0 + (i as f32 * 0.37).sin().abs() * 10.0 }).collect();
        let table = AliasTable::new(&weights);
        let total: f32 = weights.iter().sum();
        for (i, &w) in weights.iter().enumerate() {
            assert!((table.pmf(i) - w / total).abs() < 1e-6);
        }
        let (stat, df) = chi2(&table, 1_000_000, 3);
        assert!(stat < chi2_critical(df, 3.09), "χ² = {stat} for {df} dof");
    }

    #[test]
    fn a_wrong_table_fails_the_same_chi2_check() {
        // Guards the check itself: sampling uniform while claiming the weighted pmf must fail.
        let weights: Vec<f32> = (0..200).map(|i| 1.0 + (i % 3) as f32).collect();
        let claimed = AliasTable::new(&weights);
        let uniform = AliasTable::new(&[1.0; 200]);
        let mut counts = [0u64; 200];
        let mut rng = Rng::new(4, 0);
        for _ in 0..100_000 {
            counts[uniform.sample(rng.uniform()).0] += 1;
        }
        let stat: f64 = (0..200)
            .map(|i| {
                let e = claimed.pmf(i) as f64 * 1e5;
                (counts[i] as f64 - e).powi(2) / e
            })
            .sum();
        assert!(stat > chi2_critical(199.0, 3.09));
    }

    #[test]
    fn zero_and_invalid_weights_give_uniform_and_empty_is_safe() {
        let t = AliasTable::new(&[0.0, -1.0, f32::NAN, 0.0]);
        assert!((0..4).all(|i| t.pmf(i) == 0.25));
        assert_eq!(t.sample(0.99).0, 3);
        let t = AliasTable::new(&[0.0, f32::INFINITY, 2.0]);
        assert_eq!((t.pmf(0), t.pmf(1), t.pmf(2)), (0.0, 0.0, 1.0));
        assert_eq!(t.sample(0.0).0, 2);
        let e = AliasTable::new(&[]);
        assert!(e.is_empty());
        assert_eq!(e.sample(0.5), (0, 0.0));
        assert_eq!(e.pmf(3), 0.0);
    }

    #[test]
    fn huge_tables_keep_mass_and_extreme_ratios() {
        // 2M entries with one holding half the mass: the sum of sampled frequencies must match.
        let n = 2_000_000;
        let mut w = vec![1.0f32; n];
        w[123_456] = (n - 1) as f32;
        let t = AliasTable::new(&w);
        assert!((t.pmf(123_456) - 0.5).abs() < 1e-6);
        let mut rng = Rng::new(9, 0);
        let m = 200_000;
        let hits = (0..m).filter(|_| t.sample(rng.uniform()).0 == 123_456).count();
        // Binomial(m, 1/2): σ = sqrt(m)/2; 4σ.
        assert!((hits as f64 - m as f64 / 2.0).abs() < 4.0 * (m as f64).sqrt() / 2.0, "{hits}");
        assert!(t.sample(0.9999999).0 < n);
    }
}
