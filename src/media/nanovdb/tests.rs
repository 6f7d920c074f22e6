//! The reader against files written by the OpenVDB/NanoVDB libraries
//! (`scripts/make-nanovdb-fixtures.sh`): every voxel equals the closed form the script wrote,
//! and damaged files are errors, never panics.

use super::*;
use crate::sampling::Rng;
use glam::{DVec3, IVec3, Vec3};
use std::path::PathBuf;

pub(crate) fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/nanovdb").join(name)
}

/// The density the script wrote at voxel (i, j, k) of density.nvdb (0: inactive or outside).
pub(crate) fn script_density(i: i32, j: i32, k: i32) -> f32 {
    let inside = |v: i32, a: i32, b: i32| (a..=b).contains(&v);
    if !(inside(i, -8, 31) && inside(j, -8, 31) && inside(k, -8, 31)) {
        return 0.0;
    }
    if inside(i, 8, 15) && inside(j, 0, 7) && inside(k, 16, 23) {
        return 0.0;
    }
    if inside(i, 16, 23) && inside(j, 16, 23) && inside(k, 0, 7) {
        return 0.625;
    }
    if (i + 2 * j + 3 * k).rem_euclid(11) == 0 {
        return 0.0;
    }
    let (u, v, w) = ((i + 8) as f64 / 39.0, (j + 8) as f64 / 39.0, (k + 8) as f64 / 39.0);
    (4.0 * u * (1.0 - u) * (0.25 + 0.75 * v) * (1.5 - w)) as f32
}

/// The temperature the script wrote at voxel (i, j, k) of density.nvdb [K].
pub(crate) fn script_temperature(i: i32, j: i32, k: i32) -> f32 {
    if [i, j, k].iter().all(|v| (0..24).contains(v)) {
        (1000 + 50 * i + 20 * j + 10 * k) as f32
    } else {
        0.0
    }
}

#[test]
fn every_voxel_of_the_density_fixture_is_the_scripts_function() {
    let file = NanoVdbFile::open(&fixture("density.nvdb")).unwrap();
    assert_eq!(file.grids.iter().map(|g| g.name.as_str()).collect::<Vec<_>>(), ["density", "temperature"]);
    let g = file.float_grid("density").unwrap();
    assert_eq!((g.name.as_str(), g.class, g.background), ("density", 2, 0.0));
    assert_eq!(g.index_bbox, (IVec3::splat(-8), IVec3::splat(31)));
    // The library derives the voxel size from its map, to a rounding of 0.05.
    assert!((g.voxel_size - DVec3::splat(0.05)).abs().max_element() < 1e-15, "{}", g.voxel_size);
    // World bounds: index −8 to 31 + 1 through x ↦ 0.05 x + (0.3, −0.2, 0.1).
    let origin = DVec3::new(0.3, -0.2, 0.1);
    let (lo, hi) = (origin + DVec3::splat(-8.0 * 0.05), origin + DVec3::splat(32.0 * 0.05));
    assert!((g.world_bbox.0 - lo).abs().max_element() < 1e-12, "{:?} vs {lo}", g.world_bbox.0);
    assert!((g.world_bbox.1 - hi).abs().max_element() < 1e-12, "{:?} vs {hi}", g.world_bbox.1);
    let mut checked = 0;
    for k in -12..36 {
        for j in -12..36 {
            for i in -12..36 {
                let (got, want) = (g.value(IVec3::new(i, j, k)), script_density(i, j, k));
                assert_eq!(got.to_bits(), want.to_bits(), "voxel ({i}, {j}, {k}): {got} vs {want}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 48 * 48 * 48);
    let t = file.float_grid("temperature").unwrap();
    for k in -2..26 {
        for j in -2..26 {
            for i in -2..26 {
                assert_eq!(t.value(IVec3::new(i, j, k)), script_temperature(i, j, k), "T at ({i}, {j}, {k})");
            }
        }
    }
}

#[test]
fn trilinear_samples_of_a_linear_field_are_the_field() {
    // plain.nvdb (codec NONE): g = (i + 8j + 64k)/512 over [0, 7]³, voxel 0.5, origin (1, 2, 3).
    // Trilinear interpolation reproduces a linear function exactly between voxel centres.
    let file = NanoVdbFile::open(&fixture("plain.nvdb")).unwrap();
    let g = file.float_grid("density").unwrap();
    assert_eq!(g.index_bbox, (IVec3::ZERO, IVec3::splat(7)));
    assert_eq!(g.world_bbox, (DVec3::new(1.0, 2.0, 3.0), DVec3::new(5.0, 6.0, 7.0)));
    let mut rng = Rng::new(3, 0);
    for _ in 0..10_000 {
        let x = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 7.0;
        let p = Vec3::new(1.0, 2.0, 3.0) + x * 0.5;
        let index = g.index_from_world(p);
        assert!((index - x).abs().max_element() < 1e-5, "{index} vs {x}");
        let want = (x.x + 8.0 * x.y + 64.0 * x.z) / 512.0;
        assert!((g.trilinear(index) - want).abs() < 2e-6, "at {x}: {} vs {want}", g.trilinear(index));
    }
    // Beyond the last voxel (index 7 to 8) the value falls linearly to the background 0.
    assert!((g.trilinear(Vec3::new(7.5, 0.0, 0.0)) - 0.5 * 7.0 / 512.0).abs() < 1e-7);
}

#[test]
fn root_and_upper_tiles_and_the_background_are_read() {
    // tiles.nvdb (ZIP): background 0.125, a root tile of 0.25 over [−4096, −1]×[0, 4095]², an
    // upper-node tile of 0.5 over [128, 255]×[0, 127]², voxels (1, 2, 3) = 0.75, (−1, −1, −1) = 0.875.
    let file = NanoVdbFile::open(&fixture("tiles.nvdb")).unwrap();
    let g = file.float_grid("density").unwrap();
    assert_eq!((g.class, g.background), (0, 0.125));
    let cases = [
        ((1, 2, 3), 0.75),
        ((-1, -1, -1), 0.875),
        ((0, 0, 0), 0.125),
        ((-2, -1, -1), 0.125),
        ((-4096, 0, 0), 0.25),
        ((-1, 4095, 4095), 0.25),
        ((-700, 123, 3000), 0.25),
        ((-4097, 0, 0), 0.125),
        ((128, 0, 0), 0.5),
        ((255, 127, 127), 0.5),
        ((200, 64, 5), 0.5),
        ((256, 0, 0), 0.125),
        ((127, 0, 0), 0.125),
        ((5000, -5000, 5000), 0.125),
    ];
    for ((i, j, k), want) in cases {
        assert_eq!(g.value(IVec3::new(i, j, k)), want, "voxel ({i}, {j}, {k})");
    }
    assert_eq!(g.index_bbox, (IVec3::new(-4096, -1, -1), IVec3::new(255, 4095, 4095)));
    match file.float_grid("velocity") {
        Err(NanoVdbError::UnsupportedValueType { value_type: "Vec3f", .. }) => {}
        other => panic!("a Vec3f grid must be refused: {other:?}"),
    }
    let missing = file.float_grid("smoke").unwrap_err().to_string();
    assert!(missing.contains("\"density\", \"velocity\""), "{missing}");
}

#[test]
fn codecs_versions_and_byte_orders_prism_does_not_read_are_named() {
    let plain = std::fs::read(fixture("plain.nvdb")).unwrap();
    let with = |at: usize, bytes: &[u8]| {
        let mut b = plain.clone();
        b[at..at + bytes.len()].copy_from_slice(bytes);
        NanoVdbFile::parse(b).and_then(|f| f.float_grid("density")).map(|_| ()).unwrap_err().to_string()
    };
    let blosc = with(14, &2u16.to_le_bytes());
    assert!(blosc.contains("BLOSC"), "{blosc}");
    let old = with(8, &(29u32 << 21 | 3 << 10).to_le_bytes());
    assert!(old.contains("29.3.0"), "{old}");
    let swapped = with(0, &MAGIC.to_be_bytes());
    assert!(swapped.contains("big-endian"), "{swapped}");
    assert!(with(0, b"NotVDB!!").contains("not a NanoVDB file"));
    // The grid buffer's own version is checked too (the grid starts after header, record, name).
    let grid_at = 16 + 176 + "density".len() + 1;
    assert!(with(grid_at + 16, &(33u32 << 21).to_le_bytes()).contains("33.0.0"));
}

/// Reads a damaged file as far as it goes: every step may fail, none may panic.
fn read_damaged(bytes: Vec<u8>) {
    let Ok(file) = NanoVdbFile::parse(bytes) else { return };
    let Ok(g) = file.float_grid("density") else { return };
    for c in [IVec3::ZERO, IVec3::splat(3), IVec3::splat(-9), IVec3::new(20, 7, -1)] {
        let _ = g.value(c);
        let _ = g.trilinear(c.as_vec3() + Vec3::splat(0.4));
    }
    let unit = crate::media::Homogeneous {
        sigma_a: crate::spectrum::Spectrum::constant(1.0),
        sigma_s: crate::spectrum::Spectrum::constant(1.0),
        scale: 1.0,
        le: crate::spectrum::Spectrum::constant(0.0),
        g: 0.0,
    };
    let _ = crate::media::NanoVdbMedium::new(glam::Mat4::IDENTITY, g, unit, None);
}

#[test]
fn truncated_and_corrupted_files_are_errors_not_panics() {
    let mut rng = Rng::new(17, 0);
    for name in ["plain.nvdb", "density.nvdb"] {
        let bytes = std::fs::read(fixture(name)).unwrap();
        // Every truncation inside the headers, then a spread through the data.
        let cuts = (0..1200).chain((1200..bytes.len()).step_by(997));
        for cut in cuts {
            let err = NanoVdbFile::parse(bytes[..cut].to_vec()).and_then(|f| f.float_grid("density"));
            assert!(err.is_err(), "{name} cut at {cut} of {} bytes read as a grid", bytes.len());
        }
        // Random bytes flipped: in the first 9 KB (headers, grid, tree, root, node headers) and
        // anywhere.
        for trial in 0..600 {
            let mut b = bytes.clone();
            let span = if trial % 2 == 0 { 9000.min(b.len()) } else { b.len() };
            for _ in 0..1 + trial % 4 {
                let at = ((rng.uniform() * span as f32) as usize).min(span - 1);
                b[at] ^= 1 << (trial % 8);
            }
            read_damaged(b);
        }
    }
}
