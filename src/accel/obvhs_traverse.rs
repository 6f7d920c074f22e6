//! Our own traversal of obvhs' compressed wide BVH8 nodes (Ylitie, Karras, Laine 2017, Alg. 1:
//! node groups and primitive groups as bit masks, children visited in the order the build sorted
//! them for the ray's octant).
//!
//! obvhs' own traversal converts the 48 quantised plane bytes of a node one by one; here they are
//! widened eight at a time (the loops below vectorise), the ray interval starts at 0 instead of
//! obvhs' fixed 10⁻⁴, and 1/d is clamped at ±10³⁰ so an axis-parallel ray never computes 0·∞.

use ::obvhs::cwbvh::node::CwBvhNode;
use glam::{Vec3, Vec3A};

/// Entries in the traversal stack. Every entry is a level of the current path, so a tree whose
/// depth (root = 0) is below this never overflows it; deeper trees use a linear scan instead.
pub(super) const STACK_SIZE: usize = 32;

/// Largest inverse-direction magnitude in the slab test (finite: avoids 0·∞ = NaN).
const INV_DIR_LIMIT: f32 = 1e30;

/// Per-ray constants of the quantised slab test.
#[derive(Clone, Copy, Debug)]
pub(super) struct BoxRay {
    o: Vec3A,
    inv: Vec3A,
    neg: [bool; 3],
    /// obvhs' octant code: 0x04040404 | 0x02020202 | 0x01010101 for non-negative x, y, z.
    oct_inv4: u32,
}

impl BoxRay {
    /// Constants for origin `o` and direction `d` (finite, non-zero).
    #[inline(always)]
    pub(super) fn new(o: Vec3, d: Vec3) -> Self {
        // Adding +0 turns -0 into +0 so the slab order (from `d < 0`) and the sign of 1/d agree.
        let d = d + Vec3::ZERO;
        let inv = |x: f32| if x == 0.0 { INV_DIR_LIMIT } else { (1.0 / x).clamp(-INV_DIR_LIMIT, INV_DIR_LIMIT) };
        let neg = [d.x < 0.0, d.y < 0.0, d.z < 0.0];
        let oct_inv4 = (if neg[0] { 0 } else { 0x0404_0404 })
            | (if neg[1] { 0 } else { 0x0202_0202 })
            | (if neg[2] { 0 } else { 0x0101_0101 });
        Self { o: Vec3A::from(o), inv: Vec3A::new(inv(d.x), inv(d.y), inv(d.z)), neg, oct_inv4 }
    }
}

#[inline(always)]
fn max(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

#[inline(always)]
fn min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// Bit i set when child slot i's box overlaps [0, t_max] along the ray. A child plane is
/// p + q·2^e (q the stored byte), so its t is q·(2^e/d) + (p − o)/d: one multiply and one add
/// per plane, the per-node factors computed once.
///
/// Written as one loop over the eight slots on byte arrays copied by value (the near and far
/// planes chosen per axis by the sign of d before the loop), so that it compiles to eight-wide
/// vector code: widen bytes, convert, multiply, add, min/max, compare. Choosing the planes by
/// reference inside per-axis helpers made LLVM mix 4-lane, scalar and byte-insert code (about
/// three times the instructions).
#[inline(always)]
fn slot_hits(node: &CwBvhNode, r: &BoxRay, t_max: f32) -> u32 {
    let scale = (node.compute_extent() * r.inv).to_array();
    let offset = ((Vec3A::from(node.p) - r.o) * r.inv).to_array();
    let pick = |lo: [u8; 8], hi: [u8; 8], neg: bool| if neg { (hi, lo) } else { (lo, hi) };
    let (nx, fx) = pick(node.child_min_x, node.child_max_x, r.neg[0]);
    let (ny, fy) = pick(node.child_min_y, node.child_max_y, r.neg[1]);
    let (nz, fz) = pick(node.child_min_z, node.child_max_z, r.neg[2]);
    let mut hit = [false; 8];
    for i in 0..8 {
        let t_near = max(
            max(nx[i] as f32 * scale[0] + offset[0], ny[i] as f32 * scale[1] + offset[1]),
            max(nz[i] as f32 * scale[2] + offset[2], 0.0),
        );
        let t_far = min(
            min(fx[i] as f32 * scale[0] + offset[0], fy[i] as f32 * scale[1] + offset[1]),
            min(fz[i] as f32 * scale[2] + offset[2], t_max),
        );
        hit[i] = t_near <= t_far;
    }
    let mut hits = 0;
    for (i, &h) in hit.iter().enumerate() {
        hits |= (h as u32) << i;
    }
    hits
}

/// obvhs' hit mask from the slots hit: internal children set bits 24..32 (by traversal
/// priority), leaves set their primitives' bits 0..24. Empty slots contribute nothing.
#[inline(always)]
fn hit_mask(node: &CwBvhNode, mut slots: u32, oct_inv4: u32) -> u32 {
    let (child_bits, bit_index) = node.get_child_and_index_bits(oct_inv4);
    let mut mask = 0;
    while slots != 0 {
        let shift = slots.trailing_zeros() * 8;
        slots &= slots - 1;
        mask |= (((child_bits >> shift) & 0xff) as u32) << ((bit_index >> shift) & 0xff);
    }
    mask
}

/// Loads (and discards) both ends of the children of `node` that the ray will visit, so that
/// their cache misses overlap with each other and with the work before their turn comes.
#[inline(always)]
fn touch_children(nodes: &[CwBvhNode], node: &CwBvhNode, mask: u32, oct_inv4: u32) {
    let mut pending = mask >> 24;
    while pending != 0 {
        let slot = pending.trailing_zeros() ^ (oct_inv4 & 0xff);
        pending &= pending - 1;
        let index = node.child_base_idx + (node.imask as u32 & !(u32::MAX << slot)).count_ones();
        if let Some(child) = nodes.get(index as usize) {
            std::hint::black_box((child.p.x, child.child_max_z[7]));
        }
    }
}

/// Calls `visit(k, &mut t_max)` for every BVH primitive `k` (an index into the CWBVH's
/// `primitive_indices`) in a leaf whose box the ray reaches within [0, t_max]. `visit` may
/// shrink t_max (closest hit) and returns true to stop (any hit); `touch(k)` is called for all
/// primitives of a node before the first `visit`, to start their memory loads early. The tree's
/// depth must be below [`STACK_SIZE`].
#[inline(always)]
pub(super) fn traverse(
    bvh: &[CwBvhNode],
    r: &BoxRay,
    mut t_max: f32,
    touch: impl Fn(u32),
    mut visit: impl FnMut(u32, &mut f32) -> bool,
) {
    if bvh.is_empty() {
        return;
    }
    let mut stack = [(0u32, 0u32); STACK_SIZE];
    let mut depth = 0;
    // (first child node index, hit bits 24..32 | internal-child mask 0..8); the root is a group
    // of one whose single bit makes it node 0.
    let mut nodes = (0u32, 0x8000_0000u32);
    loop {
        let mut prims = (0u32, 0u32);
        if nodes.1 & 0xff00_0000 != 0 {
            let hits = nodes.1;
            let bit = 31 - hits.leading_zeros();
            nodes.1 &= !(1 << bit);
            if nodes.1 & 0xff00_0000 != 0 {
                stack[depth] = nodes;
                depth += 1;
            }
            let slot = (bit - 24) ^ (r.oct_inv4 & 0xff);
            let node = &bvh[(nodes.0 + (hits & !(u32::MAX << slot)).count_ones()) as usize];
            let mask = hit_mask(node, slot_hits(node, r, t_max), r.oct_inv4);
            touch_children(bvh, node, mask, r.oct_inv4);
            let mut leaves = mask & 0x00ff_ffff;
            while leaves != 0 {
                touch(node.primitive_base_idx + leaves.trailing_zeros());
                leaves &= leaves - 1;
            }
            nodes = (node.child_base_idx, (mask & 0xff00_0000) | node.imask as u32);
            prims = (node.primitive_base_idx, mask & 0x00ff_ffff);
        } else {
            nodes = (0, 0);
        }
        while prims.1 != 0 {
            let bit = 31 - prims.1.leading_zeros();
            prims.1 &= !(1 << bit);
            if visit(prims.0 + bit, &mut t_max) {
                return;
            }
        }
        if nodes.1 & 0xff00_0000 == 0 {
            if depth == 0 {
                return;
            }
            depth -= 1;
            nodes = stack[depth];
        }
    }
}
