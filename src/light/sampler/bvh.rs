//! pbrt-v4's BVH light sampler (PBR 4th ed. §12.6.3; Conty Estevez & Kulla 2018): a binary tree
//! over the lights with bounds, each node's [`LightBounds`] the union of its lights'. Sampling
//! walks from the root and picks a child in proportion to its importance at the shading point;
//! each choice rescales `u` into its interval, so the `u` that reaches the leaf is again a fresh
//! uniform (the choice is monotone in `u` at every level, which keeps stratification, as the
//! power sampler's inversion does). Lights at infinity have no bounds: they are chosen apart,
//! each with probability 1/(n_∞ + 1), the tree with the rest.
//!
//! The tree is split where the summed cost Φ · M_Ω · K_r · A over both halves is least, over
//! 12 buckets of the centroids along each axis: A the surface area of a half's box, M_Ω the
//! solid-angle measure of its normal cone widened by θ_e, K_r the parent box's longest side over
//! its side along the axis (which favours cutting long boxes across).

use super::bounds::{AngledBounds, LightBounds, PreparedBounds};
use crate::geometry::Bounds3;
use crate::math::PI;
use glam::Vec3;

/// Buckets per axis for the split search.
const BUCKETS: usize = 12;
/// Depth below which splits stop searching and halve the list (bounds the recursion).
const MAX_SEARCH_DEPTH: u32 = 64;
/// Lights below which a node's children are built one after the other, not in parallel.
const PARALLEL_BUILD: usize = 4096;
/// A light's entry in `leaf_of` when it has no leaf.
const NO_LEAF: u32 = u32::MAX;

#[derive(Clone, Debug)]
struct Node {
    bounds: PreparedBounds,
    /// The light's index for a leaf; the second child's node index otherwise (the first child
    /// follows its parent).
    child_or_light: u32,
    /// Parent node index (the root's is its own).
    parent: u32,
    leaf: bool,
    /// For an interior node whose children have the same bounds but for their flux (the two
    /// triangles of an axis-aligned rectangle, coincident lights), the first child's
    /// probabilities: their importances anywhere are in the ratio of their fluxes, so they are
    /// Φᵢ/(Φ₀ + Φ₁) and none needs evaluating. `None` otherwise.
    flux_split: Option<[f32; 2]>,
}

/// The tree over the bounded lights, and the lights at infinity.
#[derive(Clone, Debug)]
pub struct BvhLightSampler {
    nodes: Vec<Node>,
    /// Each light's leaf node, or [`NO_LEAF`].
    leaf_of: Vec<u32>,
    /// The lights without bounds (at infinity).
    infinite: Vec<u32>,
    /// Which lights are in `infinite`.
    is_infinite: Vec<bool>,
    /// The probability of choosing among the lights at infinity, n_∞/(n_∞ + 1) (1 without a
    /// tree).
    p_infinite: f32,
}

/// `bounds` of each light (`None` for lights at infinity) and whether it is at infinity.
pub struct BoundedLight {
    /// The light's bounds, if it has any and emits.
    pub bounds: Option<LightBounds>,
    /// The light is at infinity.
    pub infinite: bool,
}

/// Surface area of a box [scene units²] (0 for a point or an empty box).
fn surface_area(b: &Bounds3) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    let d = b.max - b.min;
    2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
}

/// The solid-angle measure M_Ω of a normal cone of half-angle θ_o whose emitters reach θ_e
/// beyond their normal (Conty Estevez & Kulla 2018, eq. 1): 2π(1 − cos θ_o) plus the cosine-
/// weighted band out to θ_w = min(θ_o + θ_e, π).
fn orientation_measure(b: &AngledBounds) -> f32 {
    let (theta_o, theta_e, cos_theta_o) = (b.theta_o, b.theta_e, b.bounds.cos_theta_o);
    let theta_w = (theta_o + theta_e).min(PI);
    let sin_o = (1.0 - cos_theta_o * cos_theta_o).max(0.0).sqrt();
    2.0 * PI * (1.0 - cos_theta_o)
        + PI / 2.0 * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o + cos_theta_o)
}

/// Cost of a half with bounds `b` split from a parent box of extent `parent_extent` along `axis`.
fn split_cost(b: &AngledBounds, parent_extent: Vec3, axis: usize) -> f32 {
    let k_r = parent_extent.max_element() / parent_extent[axis];
    b.bounds.phi * orientation_measure(b) * k_r * surface_area(&b.bounds.bounds)
}

/// The children's probabilities c0/(c0 + c1) and c1/(c0 + c1), in f64 so that two importances
/// near f32's largest value do not overflow, and each divided out (1 − p0 in f32 would keep
/// few digits of a small p1).
#[inline]
fn child_probabilities(c0: f32, c1: f32) -> [f32; 2] {
    let sum = c0 as f64 + c1 as f64;
    [(c0 as f64 / sum) as f32, (c1 as f64 / sum) as f32]
}

/// The two-way choice of a tree level: child 0 with probability `p[0]`, else child 1 (with
/// `p[1]`), `u` rescaled into the chosen interval (as a fresh uniform).
#[inline]
fn choose(p: [f32; 2], u: f32) -> (usize, f32, f32) {
    if u < p[0] {
        (0, p[0], (u / p[0]).min(1.0f32.next_down()))
    } else {
        (1, p[1], ((u - p[0]) / p[1]).clamp(0.0, 1.0f32.next_down()))
    }
}

impl BvhLightSampler {
    /// The tree over the lights with bounds; `lights[i]` describes light `i`.
    pub fn new(lights: &[BoundedLight]) -> Self {
        let mut s = Self {
            nodes: Vec::new(),
            leaf_of: vec![NO_LEAF; lights.len()],
            infinite: Vec::new(),
            is_infinite: lights.iter().map(|l| l.infinite).collect(),
            p_infinite: 0.0,
        };
        let mut bounded: Vec<(u32, AngledBounds)> = Vec::new();
        for (i, l) in lights.iter().enumerate() {
            if l.infinite {
                s.infinite.push(i as u32);
            } else if let Some(b) = l.bounds {
                bounded.push((i as u32, AngledBounds::new(b)));
            }
        }
        if let Some((_, first)) = bounded.first() {
            // A tree over n lights, one per leaf, has 2n − 1 nodes.
            let filler =
                Node { bounds: first.bounds.prepare(), child_or_light: 0, parent: 0, leaf: true, flux_split: None };
            s.nodes = vec![filler; 2 * bounded.len() - 1];
            build(&mut s.nodes, 0, &mut bounded, 0, 0);
            for (index, node) in s.nodes.iter().enumerate().filter(|(_, n)| n.leaf) {
                s.leaf_of[node.child_or_light as usize] = index as u32;
            }
        }
        let n_inf = s.infinite.len();
        s.p_infinite = n_inf as f32 / (n_inf + usize::from(!s.nodes.is_empty())).max(1) as f32;
        s
    }

    /// Picks a light for the point `p` with normal `n` (zero in a medium) and `u` in [0, 1):
    /// the index, its probability and `u` rescaled to a fresh uniform; `None` when no light can
    /// reach `p`.
    pub fn sample(&self, p: Vec3, n: Vec3, u: f32) -> Option<(usize, f32, f32)> {
        let p_inf = self.p_infinite;
        if u < p_inf {
            let n_inf = self.infinite.len();
            let v = u / p_inf * n_inf as f32;
            let k = (v as usize).min(n_inf - 1);
            return Some((
                self.infinite[k] as usize,
                p_inf / n_inf as f32,
                (v - k as f32).clamp(0.0, 1.0f32.next_down()),
            ));
        }
        if self.nodes.is_empty() || !self.root_reaches(p, n) {
            return None;
        }
        let mut u = ((u - p_inf) / (1.0 - p_inf)).clamp(0.0, 1.0f32.next_down());
        let mut pmf = 1.0 - p_inf;
        let mut index = 0usize;
        loop {
            let node = &self.nodes[index];
            if node.leaf {
                return Some((node.child_or_light as usize, pmf, u));
            }
            let (child, p_child, rest) = choose(self.children_probabilities(index, p, n)?, u);
            pmf *= p_child;
            u = rest;
            index = if child == 0 { index + 1 } else { node.child_or_light as usize };
        }
    }

    /// Probability with which [`BvhLightSampler::sample`] picks light `light` at `p`, `n`: the
    /// product of the child probabilities on the path from its leaf up to the root.
    pub fn pmf(&self, p: Vec3, n: Vec3, light: usize) -> f32 {
        if self.is_infinite.get(light).copied().unwrap_or(false) {
            return self.p_infinite / self.infinite.len() as f32;
        }
        let Some(&leaf) = self.leaf_of.get(light).filter(|&&l| l != NO_LEAF) else { return 0.0 };
        let mut pmf = 1.0 - self.p_infinite;
        let mut index = leaf as usize;
        while index != 0 {
            let parent = self.nodes[index].parent as usize;
            let Some(probabilities) = self.children_probabilities(parent, p, n) else { return 0.0 };
            pmf *= probabilities[usize::from(index == self.nodes[parent].child_or_light as usize)];
            index = parent;
        }
        if self.root_reaches(p, n) {
            pmf
        } else {
            0.0
        }
    }

    /// The probabilities of interior node `index`'s two children at `p`, `n`: by their flux
    /// under a flux split, else by their importances; `None` when neither can light `p`.
    #[inline]
    fn children_probabilities(&self, index: usize, p: Vec3, n: Vec3) -> Option<[f32; 2]> {
        let node = &self.nodes[index];
        if let Some(split) = node.flux_split {
            return Some(split);
        }
        let c0 = self.nodes[index + 1].bounds.importance(p, n);
        let c1 = self.nodes[node.child_or_light as usize].bounds.importance(p, n);
        (c0 + c1 > 0.0).then(|| child_probabilities(c0, c1))
    }

    /// Whether the root (the tree must have one) may light `p`, `n`. Below the root a node is
    /// only reached through its positive importance (or, under a flux split, its parent's,
    /// which is the same); the root itself needs this check when no two importances are
    /// compared there: a leaf, or a flux split.
    #[inline]
    fn root_reaches(&self, p: Vec3, n: Vec3) -> bool {
        let root = &self.nodes[0];
        !(root.leaf || root.flux_split.is_some()) || root.bounds.reaches(p, n)
    }
}

/// Writes the subtree over `items` below node `parent` into `nodes` (its 2 n − 1 nodes, depth
/// first, each node's first child after it; `nodes[0]` is node `index` of the tree); returns
/// its bounds. A subtree's size is known before it is built, so the two children of a large
/// node are built in parallel, each into its own part of `nodes`, into the tree a serial build
/// makes.
fn build(nodes: &mut [Node], index: u32, items: &mut [(u32, AngledBounds)], parent: u32, depth: u32) -> LightBounds {
    if let [(light, bounds)] = items {
        nodes[0] =
            Node { bounds: bounds.bounds.prepare(), child_or_light: *light, parent, leaf: true, flux_split: None };
        return bounds.bounds;
    }
    let bounds = items.iter().skip(1).fold(items[0].1, |acc, (_, b)| acc.union(b)).bounds;
    let mid = if depth < MAX_SEARCH_DEPTH { partition_by_cost(items, &bounds) } else { None };
    let mid = mid.unwrap_or(items.len() / 2);
    let parallel = items.len() >= PARALLEL_BUILD;
    let (left, right) = items.split_at_mut(mid);
    let (node, below) = nodes.split_first_mut().expect("a subtree has a node");
    let (left_nodes, right_nodes) = below.split_at_mut(2 * mid - 1);
    let second = index + 2 * mid as u32;
    let mut build_left = || build(left_nodes, index + 1, left, index, depth + 1);
    let mut build_right = || build(right_nodes, second, right, index, depth + 1);
    let (b0, b1) = if parallel { rayon::join(build_left, build_right) } else { (build_left(), build_right()) };
    // Children that differ in flux alone: the union of equal bounds is those bounds (with the
    // summed flux), so this node's importance is positive where its children's are.
    let flux_split = b0.same_but_flux(&b1).then(|| child_probabilities(b0.phi, b1.phi));
    debug_assert!(flux_split.is_none() || bounds.same_but_flux(&b0));
    *node = Node { bounds: bounds.prepare(), child_or_light: second, parent, leaf: false, flux_split };
    bounds
}

/// Reorders `items` into the two halves of the cheapest bucket split and returns the size of the
/// first, or `None` when no axis separates the centroids.
fn partition_by_cost(items: &mut [(u32, AngledBounds)], bounds: &LightBounds) -> Option<usize> {
    let centroid = |l: &AngledBounds| l.bounds.centroid();
    let centroids = items.iter().fold(Bounds3::EMPTY, |b, (_, l)| b.union_point(centroid(l)));
    let extent = bounds.bounds.max - bounds.bounds.min;
    let bucket_of = |c: Vec3, axis: usize| {
        let t = (c[axis] - centroids.min[axis]) / (centroids.max[axis] - centroids.min[axis]);
        ((t * BUCKETS as f32) as usize).min(BUCKETS - 1)
    };
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if centroids.max[axis] <= centroids.min[axis] {
            continue;
        }
        let mut buckets: [Option<AngledBounds>; BUCKETS] = [None; BUCKETS];
        for (_, l) in items.iter() {
            let b = &mut buckets[bucket_of(centroid(l), axis)];
            *b = Some(b.map_or(*l, |acc| acc.union(l)));
        }
        // The union of buckets in order, from the first that has lights (pbrt-v4 unions them
        // in this order, and the order decides the union's cone and the rounding of its flux).
        let add = |acc: Option<AngledBounds>, b: &Option<AngledBounds>| match (acc, b) {
            (Some(a), Some(b)) => Some(a.union(b)),
            (a, b) => a.or(*b),
        };
        // From the second bucket boundary on, as pbrt-v4's `BVHLightSampler::buildBVH`, which
        // never cuts after the first bucket (it computes that cost but does not compare it).
        // The buckets below a boundary are those below the previous one and one more.
        let mut below = buckets[0];
        for split in 1..BUCKETS - 1 {
            below = add(below, &buckets[split]);
            let above = buckets[split + 1..].iter().fold(None, add);
            let (Some(b0), Some(b1)) = (below, above) else {
                continue;
            };
            let cost = split_cost(&b0, extent, axis) + split_cost(&b1, extent, axis);
            if cost > 0.0 && best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, split));
            }
        }
    }
    let (_, axis, split) = best?;
    let mut first = 0;
    for j in 0..items.len() {
        if bucket_of(centroid(&items[j].1), axis) <= split {
            items.swap(first, j);
            first += 1;
        }
    }
    (first > 0 && first < items.len()).then_some(first)
}

#[cfg(test)]
#[path = "bvh_tests.rs"]
mod tests;
