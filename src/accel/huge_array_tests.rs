use super::*;

/// `n` distinct values.
fn pattern(n: usize) -> Vec<u64> {
    (0..n as u64).map(|i| i.wrapping_mul(0x9e37_79b9_7f4a_7c15)).collect()
}

/// The kernel's choice in a `/sys/kernel/mm/transparent_hugepage/*` file, e.g. "madvise".
fn thp_setting(name: &str) -> Option<String> {
    let text = std::fs::read_to_string(format!("/sys/kernel/mm/transparent_hugepage/{name}")).ok()?;
    Some(text.split_once('[')?.1.split_once(']')?.0.to_string())
}

#[test]
fn large_arrays_are_mapped_aligned_and_equal() {
    let items = pattern(HUGE_PAGE_BYTES / 8 * 3 / 2 + 7); // 1.5 huge pages and a bit
    let a = HugeArray::new(&items);
    assert_eq!(a.is_mapped(), cfg!(unix));
    assert_eq!(&a[..], &items[..]);
    if a.is_mapped() {
        assert_eq!(a.as_ptr() as usize % HUGE_PAGE_BYTES, 0);
    }
    let h = a.to_heap();
    assert!(!h.is_mapped());
    assert_eq!(&h[..], &items[..]);
    assert_eq!(h.huge_page_bytes().unwrap(), 0);
}

#[test]
fn small_arrays_stay_on_the_heap() {
    for n in [0, 1, 1000, HUGE_PAGE_BYTES / 8 - 1] {
        let items = pattern(n);
        let a = HugeArray::new(&items);
        assert!(!a.is_mapped(), "{n} elements");
        assert_eq!(&a[..], &items[..]);
    }
    assert!(HugeArray::<u64>::default().is_empty());
}

#[test]
fn smaps_sum_counts_only_areas_inside_the_range() {
    let smaps = "\
7f0000000000-7f0000400000 r--p 00000000 00:00 0 \n\
Size:               4096 kB\n\
AnonHugePages:      4096 kB\n\
7f0000400000-7f0000401000 r--p 00000000 00:00 0 \n\
AnonHugePages:         0 kB\n\
7f0000401000-7f0000800000 rw-p 00000000 00:00 0          [heap]\n\
AnonHugePages:      2048 kB\n\
VmFlags: rd mr mw me ac hg\n";
    assert_eq!(anon_huge_bytes(smaps, 0x7f00_0000_0000, 0x7f00_0040_1000), 4096 * 1024);
    assert_eq!(anon_huge_bytes(smaps, 0x7f00_0000_0000, 0x7f00_0080_0000), 6144 * 1024);
    assert_eq!(anon_huge_bytes(smaps, 0x7f00_0000_1000, 0x7f00_0040_1000), 0);
}

/// Where the kernel gives huge pages to madvised memory at fault time, a 4-huge-page array gets
/// at least one (all four unless physical memory is too fragmented to compact).
#[test]
fn huge_pages_are_obtained_where_the_kernel_offers_them() {
    let enabled = thp_setting("enabled");
    let defrag = thp_setting("defrag");
    let offered = matches!(enabled.as_deref(), Some("always" | "madvise"))
        && matches!(defrag.as_deref(), Some("always" | "madvise" | "defer+madvise"));
    if !offered {
        eprintln!("transparent huge pages: enabled {enabled:?}, defrag {defrag:?}: not checked");
        return;
    }
    let a = HugeArray::new(&pattern(HUGE_PAGE_BYTES / 8 * 4));
    assert!(a.is_mapped());
    let huge = a.huge_page_bytes().unwrap();
    assert!(huge >= HUGE_PAGE_BYTES, "AnonHugePages {huge} B of a 8 MiB array");
}
