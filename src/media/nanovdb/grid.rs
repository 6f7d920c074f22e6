//! A NanoVDB float grid decoded from its buffer (NanoVDB.h's `GridData`, `TreeData`,
//! `RootData`, `InternalData` and `LeafData` for `float`, major version 32), with random access by
//! voxel and trilinear sampling in index space.
//!
//! | part | where | size [bytes] | fields read |
//! |---|---|---|---|
//! | grid | 0 | 672 | magic u64 @0, version u32 @16, size u64 @32, name @40 (256), map @296 (inverse 3×3 f32 @36, translation f32 @72), world bbox 6×f64 @560, voxel size 3×f64 @608, class u32 @632, type u32 @636 |
//! | tree | 672 | 64 | offsets u64 of the first leaf, lower, upper node and the root, from the tree @0..32; counts u32 of leaves, lower, upper nodes @32..44 |
//! | root | tree + offset | 64 + 32 per tile | index bbox 6×i32 @0, tile count u32 @24, background f32 @28; tile: key u64 @0, child offset i64 from the root @8 (0: none), value f32 @20 |
//! | upper | upper offset + n × 270400 | 270400 | child mask (32768 bits) @4128, table @8256: 32768 × 8 bytes, a child offset i64 from this node or a tile value f32 |
//! | lower | lower offset + n × 33856 | 33856 | child mask (4096 bits) @544, table @1088: 4096 × 8 bytes, as the upper's |
//! | leaf | leaf offset + n × 2144 | 2144 | 512 values f32 @96, x slowest |
//!
//! The tree is decoded once into vectors whose indices are checked, so a lookup cannot fail;
//! every offset that does not land on a node of the right level, or a count that does not fit
//! the buffer, is a [`NanoVdbError::Malformed`].

use super::{check_version, value_type_name, Bytes, NanoVdbError, MAGIC};
use glam::{DVec3, IVec3, Mat3, Vec3};

const GRID_SIZE: u64 = 672;
const ROOT_SIZE: u64 = 64;
const ROOT_TILE_SIZE: u64 = 32;
const UPPER_SIZE: u64 = 270_400;
const UPPER_MASK: u64 = 4128;
const UPPER_TABLE: u64 = 8256;
const LOWER_SIZE: u64 = 33_856;
const LOWER_MASK: u64 = 544;
const LOWER_TABLE: u64 = 1088;
const LEAF_SIZE: u64 = 2144;
const LEAF_VALUES: u64 = 96;

/// The values of one 8³ leaf, index (x·64 + y·8 + z).
pub type LeafValues = [f32; 512];

/// An internal node: per table entry, a child index (child-mask bit set) or a tile value's bits.
#[derive(Clone, Debug)]
struct Internal {
    child_mask: Box<[u64]>,
    table: Box<[u32]>,
}

impl Internal {
    #[inline]
    fn child(&self, n: usize) -> Option<usize> {
        (self.child_mask[n >> 6] >> (n & 63) & 1 == 1).then(|| self.table[n] as usize)
    }
}

/// A root tile: a constant over 4096³ voxels or an upper node.
#[derive(Clone, Copy, Debug)]
enum RootEntry {
    Tile(f32),
    Child(usize),
}

/// What covers a region of index space in the tree.
#[derive(Clone, Copy, Debug)]
pub enum Node<'a> {
    /// One value over the region (a tile).
    Tile(f32),
    /// A leaf's voxels.
    Leaf(&'a LeafValues),
}

/// A float grid.
#[derive(Clone, Debug)]
pub struct FloatGrid {
    /// The grid's name.
    pub name: String,
    /// NanoVDB's grid class (0 unknown, 1 level set, 2 fog volume, …).
    pub class: u32,
    /// World (the grid's own, pbrt-v4's medium space) bounding box of the active values
    /// [world units], as the file stores it: the index bbox from its minimum to its maximum + 1.
    pub world_bbox: (DVec3, DVec3),
    /// The active values' index bounding box, both ends inclusive.
    pub index_bbox: (IVec3, IVec3),
    /// Size of a voxel [world units].
    pub voxel_size: DVec3,
    /// Index from world: the map's single-precision inverse matrix and its translation,
    /// index = M⁻¹ (p − t).
    inv_mat: Mat3,
    translation: Vec3,
    /// The value outside every tile and node.
    pub background: f32,
    root: Vec<(u64, RootEntry)>,
    uppers: Vec<Internal>,
    lowers: Vec<Internal>,
    leaves: Vec<LeafValues>,
}

/// The root table's key of a voxel: its 4096³ tile's coordinates packed 21 bits each.
#[inline]
fn root_key(c: IVec3) -> u64 {
    let part = |v: i32| ((v as u32) >> 12) as u64;
    part(c.z) | part(c.y) << 21 | part(c.x) << 42
}

/// The first voxel of the 4096³ tile of a root key.
fn key_origin(key: u64) -> IVec3 {
    let part = |bits: u64| ((bits & 0x1f_ffff) << 12) as u32 as i32;
    IVec3::new(part(key >> 42), part(key >> 21), part(key))
}

impl FloatGrid {
    /// Decodes a grid buffer; `name` is the file's name for it (for messages).
    pub fn decode(name: &str, buf: &[u8]) -> Result<Self, NanoVdbError> {
        let malformed = |reason: String| NanoVdbError::Malformed { grid: name.to_string(), reason };
        let b = Bytes(buf);
        let short = || malformed(format!("the buffer ends early ({} bytes)", buf.len()));
        if b.u64(0).ok_or_else(short)? != MAGIC {
            return Err(malformed("no magic number at the grid's start".into()));
        }
        check_version(b.u32(16).ok_or_else(short)?)?;
        let grid_type = b.u32(636).ok_or_else(short)?;
        if grid_type != 1 {
            return Err(NanoVdbError::UnsupportedValueType {
                grid: name.to_string(),
                value_type: value_type_name(grid_type),
            });
        }
        let f32s = |at: u64, n: usize| (0..n).map(|i| b.f32(at + 4 * i as u64)).collect::<Option<Vec<f32>>>();
        let f64s = |at: u64| (0..3).map(|i| b.f64(at + 8 * i)).collect::<Option<Vec<f64>>>();
        let inv = f32s(296 + 36, 9).ok_or_else(short)?;
        let t = f32s(296 + 72, 3).ok_or_else(short)?;
        // NanoVDB's matrices are row-major: index_r = Σ_c inv[3r + c] (p − t)_c.
        let inv_mat = Mat3::from_cols_array(&[inv[0], inv[3], inv[6], inv[1], inv[4], inv[7], inv[2], inv[5], inv[8]]);
        if !(inv.iter().chain(&t).all(|v| v.is_finite()) && inv_mat.determinant().abs() > 0.0) {
            return Err(malformed("its index-to-world map is singular or not finite".into()));
        }
        let (lo, hi, voxel) =
            (f64s(560).ok_or_else(short)?, f64s(584).ok_or_else(short)?, f64s(608).ok_or_else(short)?);
        let class = b.u32(632).ok_or_else(short)?;

        let tree = GRID_SIZE;
        let offset = |i: u64| b.u64(tree + 8 * i).ok_or_else(short);
        let count = |i: u64| b.u32(tree + 32 + 4 * i).ok_or_else(short).map(u64::from);
        let (leaf_count, lower_count, upper_count) = (count(0)?, count(1)?, count(2)?);
        // Each level's nodes lie one after another from its offset; all must fit the buffer.
        let level = |what: &str, off: u64, n: u64, size: u64| -> Result<u64, NanoVdbError> {
            let base = tree.checked_add(off);
            match base.and_then(|s| n.checked_mul(size).and_then(|len| s.checked_add(len))) {
                Some(end) if n == 0 || end <= buf.len() as u64 => Ok(base.unwrap_or(0)),
                _ => Err(malformed(format!("{n} {what} nodes at offset {off} do not fit {} bytes", buf.len()))),
            }
        };
        let leaf_base = level("leaf", offset(0)?, leaf_count, LEAF_SIZE)?;
        let lower_base = level("lower", offset(1)?, lower_count, LOWER_SIZE)?;
        let upper_base = level("upper", offset(2)?, upper_count, UPPER_SIZE)?;
        let root_at = tree.checked_add(offset(3)?).ok_or_else(short)?;
        let tile_count = b.u32(root_at + 24).ok_or_else(short)? as u64;
        level("root", root_at - tree, 1, ROOT_SIZE + tile_count * ROOT_TILE_SIZE)?;
        let bbox = (0..6).map(|i| b.i32(root_at + 4 * i)).collect::<Option<Vec<i32>>>().ok_or_else(short)?;
        let background = b.f32(root_at + 28).ok_or_else(short)?;

        // A child at `node + rel` must be the start of node k of its level.
        let child_index = |what: &str, node: u64, rel: i64, base: u64, size: u64, n: u64| {
            let at = node.checked_add_signed(rel);
            match at.and_then(|a| a.checked_sub(base)) {
                Some(d) if d % size == 0 && d / size < n => Ok((d / size) as usize),
                _ => Err(malformed(format!("a {what} child offset {rel} from byte {node} is not a {what} node"))),
            }
        };
        let mut root = Vec::with_capacity(tile_count as usize);
        for t in 0..tile_count {
            let at = root_at + ROOT_SIZE + t * ROOT_TILE_SIZE;
            let (key, child) = (b.u64(at).ok_or_else(short)?, b.i64(at + 8).ok_or_else(short)?);
            let entry = if child == 0 {
                RootEntry::Tile(b.f32(at + 20).ok_or_else(short)?)
            } else {
                RootEntry::Child(child_index("upper", root_at, child, upper_base, UPPER_SIZE, upper_count)?)
            };
            root.push((key, entry));
        }
        let internal =
            |at: u64, mask: u64, table: u64, entries: u64, child: &dyn Fn(u64, i64) -> Result<usize, NanoVdbError>| {
                let child_mask: Box<[u64]> = (0..entries / 64).map(|w| b.u64(at + mask + 8 * w).unwrap_or(0)).collect();
                let mut values = vec![0u32; entries as usize].into_boxed_slice();
                for n in 0..entries {
                    let e = at + table + 8 * n;
                    values[n as usize] = if child_mask[(n >> 6) as usize] >> (n & 63) & 1 == 1 {
                        child(at, b.i64(e).unwrap_or(0))? as u32
                    } else {
                        b.u32(e).unwrap_or(0)
                    };
                }
                Ok::<_, NanoVdbError>(Internal { child_mask, table: values })
            };
        let to_lower = |at: u64, rel: i64| child_index("lower", at, rel, lower_base, LOWER_SIZE, lower_count);
        let to_leaf = |at: u64, rel: i64| child_index("leaf", at, rel, leaf_base, LEAF_SIZE, leaf_count);
        let uppers = (0..upper_count)
            .map(|k| internal(upper_base + k * UPPER_SIZE, UPPER_MASK, UPPER_TABLE, 32_768, &to_lower))
            .collect::<Result<Vec<_>, _>>()?;
        let lowers = (0..lower_count)
            .map(|k| internal(lower_base + k * LOWER_SIZE, LOWER_MASK, LOWER_TABLE, 4096, &to_leaf))
            .collect::<Result<Vec<_>, _>>()?;
        let leaves = (0..leaf_count)
            .map(|k| {
                let at = leaf_base + k * LEAF_SIZE + LEAF_VALUES;
                std::array::from_fn(|n| b.f32(at + 4 * n as u64).unwrap_or(0.0))
            })
            .collect();
        let name_bytes = &buf[40..296];
        let end = name_bytes.iter().position(|&c| c == 0).unwrap_or(name_bytes.len());
        Ok(Self {
            name: String::from_utf8_lossy(&name_bytes[..end]).into_owned(),
            class,
            world_bbox: (DVec3::from_slice(&lo), DVec3::from_slice(&hi)),
            index_bbox: (IVec3::from_slice(&bbox[..3]), IVec3::from_slice(&bbox[3..])),
            voxel_size: DVec3::from_slice(&voxel),
            inv_mat,
            translation: Vec3::from_slice(&t),
            background,
            root,
            uppers,
            lowers,
            leaves,
        })
    }

    /// The node holding voxel `c`: its leaf, or the tile (or background) value around it.
    #[inline]
    fn node(&self, c: IVec3) -> Node<'_> {
        let key = root_key(c);
        let Some(&(_, entry)) = self.root.iter().find(|(k, _)| *k == key) else {
            return Node::Tile(self.background);
        };
        let upper = match entry {
            RootEntry::Tile(v) => return Node::Tile(v),
            RootEntry::Child(u) => &self.uppers[u],
        };
        let n = (((c.x & 4095) >> 7) << 10 | ((c.y & 4095) >> 7) << 5 | ((c.z & 4095) >> 7)) as usize;
        let Some(l) = upper.child(n) else {
            return Node::Tile(f32::from_bits(upper.table[n]));
        };
        let lower = &self.lowers[l];
        let n = (((c.x & 127) >> 3) << 8 | ((c.y & 127) >> 3) << 4 | ((c.z & 127) >> 3)) as usize;
        match lower.child(n) {
            Some(leaf) => Node::Leaf(&self.leaves[leaf]),
            None => Node::Tile(f32::from_bits(lower.table[n])),
        }
    }

    /// The value of voxel `c`: a leaf's stored value (active or not, as NanoVDB's `getValue`),
    /// a tile's value, or the background.
    #[inline]
    pub fn value(&self, c: IVec3) -> f32 {
        match self.node(c) {
            Node::Tile(v) => v,
            Node::Leaf(values) => values[leaf_offset(c)],
        }
    }

    /// Index-space coordinates of world (medium-space) point `p`, as NanoVDB's `worldToIndexF`.
    #[inline]
    pub fn index_from_world(&self, p: Vec3) -> Vec3 {
        self.inv_mat * (p - self.translation)
    }

    /// World (medium-space) point of index-space coordinates `x`: the inverse of
    /// [`Self::index_from_world`].
    pub fn world_from_index(&self) -> impl Fn(Vec3) -> Vec3 {
        let (m, t) = (self.inv_mat.inverse(), self.translation);
        move |x| m * x + t
    }

    /// The trilinear interpolation at index-space point `x` of the voxels around it (voxel
    /// (i, j, k) sits at the integer point; NanoVDB's `SampleFromVoxels` of order 1).
    pub fn trilinear(&self, x: Vec3) -> f32 {
        // Far outside any tree the value is the background; the clamp keeps i + 1 in range.
        let x = x.clamp(Vec3::splat(-1.0e9), Vec3::splat(1.0e9));
        let base = x.floor();
        let f = x - base;
        let c = base.as_ivec3();
        let mut v = [0f32; 8];
        if (c & IVec3::splat(7)).cmplt(IVec3::splat(7)).all() {
            // All eight corners in one leaf-sized block: one descent.
            match self.node(c) {
                Node::Tile(t) => return t,
                Node::Leaf(values) => {
                    let o = leaf_offset(c);
                    for (k, vk) in v.iter_mut().enumerate() {
                        *vk = values[o + (k >> 2) * 64 + ((k >> 1) & 1) * 8 + (k & 1)];
                    }
                }
            }
        } else {
            for (k, vk) in v.iter_mut().enumerate() {
                let d = IVec3::new((k >> 2) as i32, ((k >> 1) & 1) as i32, (k & 1) as i32);
                *vk = self.value(c + d);
            }
        }
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        // v[k]: corner (k>>2, (k>>1)&1, k&1) in (x, y, z).
        let z00 = lerp(v[0], v[1], f.z);
        let z01 = lerp(v[2], v[3], f.z);
        let z10 = lerp(v[4], v[5], f.z);
        let z11 = lerp(v[6], v[7], f.z);
        lerp(lerp(z00, z01, f.y), lerp(z10, z11, f.y), f.x)
    }

    /// Visits every tile and leaf of the tree with the first voxel and edge length [voxels] of
    /// the region it covers; the background fills the rest.
    pub fn visit(&self, mut f: impl FnMut(IVec3, i32, Node<'_>)) {
        for &(key, entry) in &self.root {
            let origin = key_origin(key);
            let u = match entry {
                RootEntry::Tile(v) => {
                    f(origin, 4096, Node::Tile(v));
                    continue;
                }
                RootEntry::Child(u) => &self.uppers[u],
            };
            for n in 0..32_768usize {
                let o = origin + IVec3::new((n >> 10) as i32, ((n >> 5) & 31) as i32, (n & 31) as i32) * 128;
                let Some(l) = u.child(n) else {
                    f(o, 128, Node::Tile(f32::from_bits(u.table[n])));
                    continue;
                };
                let lower = &self.lowers[l];
                for m in 0..4096usize {
                    let q = o + IVec3::new((m >> 8) as i32, ((m >> 4) & 15) as i32, (m & 15) as i32) * 8;
                    match lower.child(m) {
                        Some(leaf) => f(q, 8, Node::Leaf(&self.leaves[leaf])),
                        None => f(q, 8, Node::Tile(f32::from_bits(lower.table[m]))),
                    }
                }
            }
        }
    }
}

/// A voxel's place in its leaf: x slowest, z fastest.
#[inline]
pub fn leaf_offset(c: IVec3) -> usize {
    (((c.x & 7) << 6) | ((c.y & 7) << 3) | (c.z & 7)) as usize
}
