//! A read-only array in memory advised for transparent huge pages.
//!
//! Incoherent rays over a large BVH load nodes and triangles from all over tens of megabytes;
//! with 4 KiB pages nearly every such load also misses the TLB (a page walk before the cache
//! miss). A 2 MiB page covers 512 times as much memory per TLB entry. Linux hands out
//! transparent huge pages only to memory that asks for them when
//! `/sys/kernel/mm/transparent_hugepage/enabled` is `madvise` (as on Debian's default), and a
//! Rust `Vec` never asks. [`HugeArray`] copies its elements into an anonymous mapping whose
//! start is 2 MiB aligned, advises every whole 2 MiB page of it with `MADV_HUGEPAGE` before the
//! first write (so the write faults take huge pages directly) and from then on only reads it. The
//! tail after the last whole 2 MiB page stays in small pages, so no memory is wasted. Arrays
//! smaller than one huge page, platforms without `madvise` and failed mappings use a `Vec`.

use std::fmt;
use std::ops::Deref;

use bytemuck::Pod;
use memmap2::MmapMut;

/// Size and alignment of an x86-64 transparent huge page (2 MiB).
pub const HUGE_PAGE_BYTES: usize = 2 << 20;

/// Where the elements live.
enum Storage<T> {
    Heap(Vec<T>),
    /// `len` elements from byte `offset` (a multiple of [`HUGE_PAGE_BYTES`] in address space).
    Mapped {
        map: MmapMut,
        offset: usize,
        len: usize,
    },
}

/// A read-only array of plain-old-data elements, huge-page advised when it spans at least one
/// huge page (see the module documentation). Dereferences to `[T]`.
pub struct HugeArray<T: Pod> {
    storage: Storage<T>,
}

impl<T: Pod> HugeArray<T> {
    /// Copies `items` into huge-page-advised memory (a `Vec` if it is under one huge page or
    /// the mapping fails).
    pub fn new(items: &[T]) -> Self {
        Self::from_exact_iter(items.iter().copied())
    }

    /// Writes the items straight into huge-page-advised memory, with no intermediate `Vec`
    /// (a `Vec` if they are under one huge page or the mapping fails).
    pub fn from_exact_iter(items: impl ExactSizeIterator<Item = T>) -> Self {
        let bytes = items.len() * std::mem::size_of::<T>();
        if cfg!(unix) && bytes >= HUGE_PAGE_BYTES {
            if let Ok(map) = Self::map_anon(bytes) {
                return Self { storage: Self::fill(map, items) };
            }
        }
        Self::on_heap(items.collect())
    }

    /// Keeps `items` in an ordinary `Vec` (no huge pages): the baseline for comparisons.
    pub fn on_heap(items: Vec<T>) -> Self {
        Self { storage: Storage::Heap(items) }
    }

    /// True when the elements live in a huge-page-advised mapping.
    pub fn is_mapped(&self) -> bool {
        matches!(self.storage, Storage::Mapped { .. })
    }

    /// A copy of this array in an ordinary `Vec`-backed array.
    pub fn to_heap(&self) -> Self {
        Self::on_heap(self.to_vec())
    }

    /// A writable anonymous mapping with a 2 MiB-aligned run of `bytes` bytes at the returned
    /// offset, its whole huge pages advised with `MADV_HUGEPAGE`.
    #[cfg(unix)]
    fn map_anon(bytes: usize) -> std::io::Result<(MmapMut, usize)> {
        // Over-allocate address space (not memory: untouched pages are never backed) so that a
        // 2 MiB-aligned start exists inside the mapping.
        let map = MmapMut::map_anon(bytes + HUGE_PAGE_BYTES)?;
        let address = map.as_ptr() as usize;
        let offset = address.next_multiple_of(HUGE_PAGE_BYTES) - address;
        // Only whole huge pages: the kernel would back a partial one with small pages anyway.
        // Advising before the first write lets the write faults take huge pages directly.
        map.advise_range(memmap2::Advice::HugePage, offset, bytes / HUGE_PAGE_BYTES * HUGE_PAGE_BYTES)?;
        Ok((map, offset))
    }

    #[cfg(not(unix))]
    fn map_anon(_: usize) -> std::io::Result<(MmapMut, usize)> {
        Err(std::io::ErrorKind::Unsupported.into())
    }

    /// Writes `items` at `offset`. The mapping stays writable, but nothing writes to it again:
    /// [`HugeArray`] hands out only shared slices.
    fn fill((mut map, offset): (MmapMut, usize), items: impl ExactSizeIterator<Item = T>) -> Storage<T> {
        let len = items.len();
        let out: &mut [T] = bytemuck::cast_slice_mut(&mut map[offset..offset + len * std::mem::size_of::<T>()]);
        // `zip` stops at the shorter side, so a lying `len()` cannot write out of range.
        let mut written = 0;
        for (slot, item) in out.iter_mut().zip(items) {
            *slot = item;
            written += 1;
        }
        Storage::Mapped { map, offset, len: written }
    }

    /// Bytes of this array the kernel currently backs with huge pages (the `AnonHugePages` of
    /// its mapping in `/proc/self/smaps`); 0 when it is on the heap. Linux only.
    pub fn huge_page_bytes(&self) -> std::io::Result<usize> {
        let Storage::Mapped { map, .. } = &self.storage else { return Ok(0) };
        let (start, end) = (map.as_ptr() as usize, map.as_ptr() as usize + map.len());
        let smaps = std::fs::read_to_string("/proc/self/smaps")?;
        Ok(anon_huge_bytes(&smaps, start, end))
    }
}

/// Sum of `AnonHugePages` over the mappings of `smaps` that lie inside [start, end) (madvise
/// splits one mapping into several areas).
fn anon_huge_bytes(smaps: &str, start: usize, end: usize) -> usize {
    let mut inside = false;
    let mut total = 0;
    for line in smaps.lines() {
        let header = line.split_once(' ').and_then(|(range, _)| range.split_once('-'));
        if let Some((a, b)) = header.filter(|(a, _)| !a.contains(':')) {
            if let (Ok(a), Ok(b)) = (usize::from_str_radix(a, 16), usize::from_str_radix(b, 16)) {
                inside = a >= start && b <= end;
                continue;
            }
        }
        if let (true, Some(kb)) = (inside, line.strip_prefix("AnonHugePages:")) {
            total += kb.trim().trim_end_matches("kB").trim().parse::<usize>().unwrap_or(0) * 1024;
        }
    }
    total
}

impl<T: Pod> Deref for HugeArray<T> {
    type Target = [T];

    #[inline]
    fn deref(&self) -> &[T] {
        match &self.storage {
            Storage::Heap(v) => v,
            Storage::Mapped { map, offset, len } => {
                bytemuck::cast_slice(&map[*offset..*offset + len * std::mem::size_of::<T>()])
            }
        }
    }
}

impl<T: Pod> Default for HugeArray<T> {
    fn default() -> Self {
        Self::on_heap(Vec::new())
    }
}

impl<T: Pod + fmt::Debug> fmt::Debug for HugeArray<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HugeArray").field("len", &self.len()).field("mapped", &self.is_mapped()).finish()
    }
}

#[cfg(test)]
#[path = "huge_array_tests.rs"]
mod tests;
