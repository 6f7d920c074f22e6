//! Multiple importance sampling weights of bidirectional path tracing (Veach 1997, §10.2–10.3;
//! PBR 3rd ed. §16.3.4): a path x₀ … x_{n−1} (x₀ on a light, x_{n−1} on the camera) can be made
//! by n − 1 strategies, s = 0 … n − 2 vertices from the light and t = n − s ≥ 2 from the camera,
//! or s = n − 1 with t = 1 (a light subpath connected to the lens). Strategy s makes it with
//! density p_s = Π_{i<s} p←(x_i) · Π_{i≥s} p→(x_i), where p← is the area density with which
//! the light subpath reaches x_i and p→ the one with which the camera subpath does; the balance
//! heuristic weights it p_s / Σ_k p_k, computed from the ratios p_{k+1}/p_k = p←(x_k)/p→(x_k).
//!
//! Strategies that cannot make the path take no part in the sum: those whose connecting edge
//! ends at a vertex sampled by a delta lobe (specular), s = 0 for lights at a point (a ray never
//! hits them), and s = 1, t = 1 (which the estimator does not use: s = 0, t = 2 sees a light
//! directly). A zero density — of a delta lobe — counts as 1 in the ratios (pbrt's `remap0`),
//! so that it cancels between the two subpaths.

/// What the weights need of one vertex of the full path.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct VertexDensity {
    /// Area density [1/m²] with which the light subpath reaches this vertex (for x₀: the
    /// light's choice probability times its point's area density).
    pub from_light: f32,
    /// Area density [1/m²] with which the camera subpath reaches it.
    pub from_camera: f32,
    /// The vertex scatters by a delta lobe: no connection can end at it.
    pub delta: bool,
}

/// Vertices of a full path [`DensityPath`] holds without a heap allocation: `maxdepth` 14
/// (light and camera subpaths together).
const INLINE_VERTICES: usize = 16;

/// The densities of a full path's `n` vertices, on the stack up to [`INLINE_VERTICES`] and on
/// the heap beyond, so that the weight of a connection allocates nothing at common depths.
pub(super) enum DensityPath {
    Inline([VertexDensity; INLINE_VERTICES], usize),
    Heap(Vec<VertexDensity>),
}

impl DensityPath {
    /// `n` vertices of default (zero) densities.
    pub(super) fn new(n: usize) -> Self {
        if n <= INLINE_VERTICES {
            Self::Inline([VertexDensity::default(); INLINE_VERTICES], n)
        } else {
            Self::Heap(vec![VertexDensity::default(); n])
        }
    }
}

impl std::ops::Deref for DensityPath {
    type Target = [VertexDensity];
    fn deref(&self) -> &[VertexDensity] {
        match self {
            Self::Inline(v, n) => &v[..*n],
            Self::Heap(v) => v,
        }
    }
}

impl std::ops::DerefMut for DensityPath {
    fn deref_mut(&mut self) -> &mut [VertexDensity] {
        match self {
            Self::Inline(v, n) => &mut v[..*n],
            Self::Heap(v) => v,
        }
    }
}

/// `pdf`, or 1 where it is 0.
fn remap0(pdf: f32) -> f32 {
    if pdf == 0.0 {
        1.0
    } else {
        pdf
    }
}

/// True when strategy `s` (s vertices from the light) can make the path `path`, whose light
/// sits at a point when `point_light`.
fn usable(path: &[VertexDensity], s: usize, point_light: bool) -> bool {
    let n = path.len();
    if s + 1 > n || (s == 1 && n == 2) {
        return false;
    }
    if s == 0 {
        return !point_light;
    }
    !path[s - 1].delta && !path[s].delta
}

/// The balance-heuristic weight of strategy `s` for `path` (light end first), 0 when `s`
/// cannot make it.
pub(super) fn balance_weight(path: &[VertexDensity], s: usize, point_light: bool) -> f32 {
    if !usable(path, s, point_light) {
        return 0.0;
    }
    let n = path.len();
    // Σ_k p_k / p_s over the usable strategies k.
    let mut sum = 1.0f64;
    let mut r = 1.0f64;
    for k in s..n - 1 {
        // r = p_{k+1} / p_s.
        r *= remap0(path[k].from_light) as f64 / remap0(path[k].from_camera) as f64;
        if usable(path, k + 1, point_light) {
            sum += r;
        }
    }
    r = 1.0;
    for k in (0..s).rev() {
        // r = p_k / p_s.
        r *= remap0(path[k].from_camera) as f64 / remap0(path[k].from_light) as f64;
        if usable(path, k, point_light) {
            sum += r;
        }
    }
    (1.0 / sum) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::Rng;

    /// p_s computed directly as the product of its densities (delta densities taken as 1).
    fn density(path: &[VertexDensity], s: usize) -> f64 {
        let light: f64 = path[..s].iter().map(|v| remap0(v.from_light) as f64).product();
        let camera: f64 = path[s..].iter().map(|v| remap0(v.from_camera) as f64).product();
        light * camera
    }

    #[test]
    fn the_weights_of_all_strategies_of_a_path_sum_to_one_and_are_the_balance_heuristic() {
        let mut rng = Rng::new(7, 11);
        for case in 0..2000 {
            let n = 2 + case % 8;
            let point_light = case % 3 == 0;
            let path: Vec<VertexDensity> = (0..n)
                .map(|i| {
                    // Interior vertices are specular now and then; a specular vertex's
                    // densities are 0 (the lobe's delta).
                    let delta = i > 0 && i + 1 < n && rng.uniform() < 0.2;
                    let pdf = |r: &mut Rng| if delta { 0.0 } else { 10f32.powf(4.0 * r.uniform() - 2.0) };
                    VertexDensity { from_light: pdf(&mut rng), from_camera: pdf(&mut rng), delta }
                })
                .collect();
            let weights: Vec<f32> = (0..n).map(|s| balance_weight(&path, s, point_light)).collect();
            let usable_count = (0..n).filter(|&s| usable(&path, s, point_light)).count();
            let total: f32 = weights.iter().sum();
            if usable_count == 0 {
                assert_eq!(total, 0.0);
                continue;
            }
            assert!((total - 1.0).abs() < 1e-5, "{path:?}: {weights:?}");
            // Each weight is p_s / Σ p_k over the usable strategies, p computed directly.
            let sum: f64 = (0..n).filter(|&s| usable(&path, s, point_light)).map(|s| density(&path, s)).sum();
            for (s, w) in weights.iter().enumerate() {
                let expected = if usable(&path, s, point_light) { density(&path, s) / sum } else { 0.0 };
                assert!((*w as f64 - expected).abs() < 1e-5, "s = {s}: {w} vs {expected}");
            }
        }
        // A light at a point is never hit, and (s, t) = (1, 1) is not used: a two-vertex path
        // of a point light has no strategy, one of an area light only s = 0.
        let two = [VertexDensity { from_light: 1.0, from_camera: 2.0, delta: false }; 2];
        assert_eq!(balance_weight(&two, 0, true), 0.0);
        assert_eq!(balance_weight(&two, 0, false), 1.0);
        assert_eq!(balance_weight(&two, 1, false), 0.0);
    }

    #[test]
    fn a_density_path_holds_n_vertices_on_the_stack_or_the_heap() {
        for n in [0, 1, INLINE_VERTICES, INLINE_VERTICES + 1, 40] {
            let mut path = DensityPath::new(n);
            assert_eq!(path.len(), n);
            assert_eq!(matches!(path, DensityPath::Heap(_)), n > INLINE_VERTICES);
            for (i, d) in path.iter_mut().enumerate() {
                d.from_light = i as f32;
            }
            assert!(path.iter().enumerate().all(|(i, d)| d.from_light == i as f32 && d.from_camera == 0.0));
        }
    }
}
