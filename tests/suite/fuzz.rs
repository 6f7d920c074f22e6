//! Seeded mutation tests of every reader of a binary or referenced file: each seed in
//! `tests/data/fuzz/<format>/` (and `tests/data/nanovdb/tiles.nvdb`) is mutated by a fixed-seed
//! generator (bit flips, bytes set to 0/0xff/random, truncations, huge 32-bit counts, NaN/Inf in
//! text, duplicated chunks) and fed to the reader prism uses for it. Each mutant must give `Ok`
//! or a one-line error, without a panic, within a generous deadline. Mutants per format: [`MUTANTS`].

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use crate::common::tmpdir;
use prism::image::Backend;
use prism::pbrt::{load_file, ParseOptions};
use prism::sampling::Rng;

/// Mutants per seed file.
const MUTANTS: usize = 150;
/// Longest one mutant may take to be read (a hang, not a timing assertion).
const DEADLINE: Duration = Duration::from_secs(20);

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(rel)
}

/// One deterministic mutation of `seed`; text formats also get numbers replaced by NaN/Inf.
fn mutate(seed: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = seed.to_vec();
    for _ in 0..1 + rng.next_u32() % 3 {
        if b.is_empty() {
            break;
        }
        let i = rng.next_u32() as usize % b.len();
        match rng.next_u32() % 8 {
            0 => b[i] ^= 1 << (rng.next_u32() % 8),
            1 => b[i] = [0u8, 0xff, rng.next_u32() as u8][rng.next_u32() as usize % 3],
            2 => b.truncate(i),
            3 if i + 4 <= b.len() => {
                let v: [u32; 3] = [u32::MAX, 0x7fff_ffff, 0x1000_0000];
                b[i..i + 4].copy_from_slice(&v[rng.next_u32() as usize % 3].to_le_bytes());
            }
            4 => {
                let j = (i + 1 + rng.next_u32() as usize % 64).min(b.len());
                let chunk = b[i..j].to_vec();
                b.splice(i..i, chunk);
            }
            5 => {
                let words: [&[u8]; 5] = [b"nan", b"inf", b"-inf", b"1e40", b"4294967296"];
                let w = words[rng.next_u32() as usize % words.len()];
                let j = (i + 1 + rng.next_u32() as usize % 4).min(b.len());
                b.splice(i..j, w.iter().copied());
            }
            _ => b[i] = rng.next_u32() as u8,
        }
    }
    b
}

/// Runs `read` on a thread: a panic or a run past [`DEADLINE`] fails the test, and so does an
/// error of more than one line. Whether the reader refused the input.
fn assert_harmless(what: &str, read: impl FnOnce() -> Result<(), String> + Send + 'static) -> bool {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(read));
        let _ = tx.send(r);
    });
    match rx.recv_timeout(DEADLINE) {
        Ok(Ok(Ok(()))) => false,
        Ok(Ok(Err(e))) => {
            assert!(!e.trim().is_empty() && !e.contains('\n'), "{what}: not one line: {e:?}");
            true
        }
        Ok(Err(_)) => panic!("{what}: the reader panicked"),
        Err(_) => panic!("{what}: no answer within {DEADLINE:?}"),
    }
}

/// Mutates every seed of `seeds` [`MUTANTS`] times into `dir/<name>` and reads each with `read`.
fn fuzz(tag: &str, seeds: &[PathBuf], read: fn(&Path) -> Result<(), String>) {
    fuzz_n(tag, seeds, MUTANTS, read);
}

/// [`fuzz`] with `mutants` mutants per seed.
fn fuzz_n(tag: &str, seeds: &[PathBuf], mutants: usize, read: fn(&Path) -> Result<(), String>) {
    let dir = tmpdir(&format!("fuzz-{tag}"));
    let mut rng = Rng::new(0x5eed, tag.len() as u64);
    let mut refused = 0;
    for seed in seeds {
        let bytes = std::fs::read(seed).unwrap();
        let name = seed.file_name().unwrap().to_str().unwrap();
        // The seed itself must read: a mutant of an unreadable seed tests little.
        let copy = dir.join(name);
        std::fs::write(&copy, &bytes).unwrap();
        assert_eq!(read(&copy), Ok(()), "seed {}", seed.display());
        for k in 0..mutants {
            let mutant = dir.join(format!("{k}-{name}"));
            std::fs::write(&mutant, mutate(&bytes, &mut rng)).unwrap();
            let m = mutant.clone();
            refused += assert_harmless(&mutant.display().to_string(), move || read(&m)) as usize;
            std::fs::remove_file(&mutant).unwrap();
        }
    }
    // Some mutants must be refused, or the reader was never reached.
    assert!(refused > 0, "{tag}: every mutant read");
    eprintln!("{tag}: {} mutants, {refused} refused", seeds.len() * mutants);
}

fn seeds(format: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> =
        std::fs::read_dir(data(&format!("fuzz/{format}"))).unwrap().map(|e| e.unwrap().path()).collect();
    v.sort();
    v
}

/// Loads a scene `text` written beside `file` (which it names as `{}`).
fn load_scene(file: &Path, text: &str) -> Result<(), String> {
    let name = file.file_name().unwrap().to_str().unwrap();
    let scene = file.with_extension("pbrt");
    std::fs::write(&scene, text.replace("{}", name)).unwrap();
    let r = load_file(&scene, &ParseOptions::default()).map(|_| ()).map_err(|e| e.to_string());
    let _ = std::fs::remove_file(&scene);
    r
}

/// The scene text before a test's shapes.
macro_rules! world {
    () => {
        "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n"
    };
}

fn read_image(p: &Path) -> Result<(), String> {
    // Both backends when OpenImageIO is built in, each on its own (not only as the fallback).
    for &backend in Backend::available() {
        let img = prism::image::read_with(p, backend).map_err(|e| e.to_string())?;
        img.validate().map_err(|e| e.to_string())?;
    }
    Ok(())
}

#[test]
fn fuzz_images() {
    for format in ["png", "jpeg", "exr", "hdr", "tiff"] {
        fuzz(format, &seeds(format), read_image);
    }
}

#[test]
fn fuzz_image_textures_through_scenes() {
    fuzz("png-scene", &seeds("png"), |p| {
        load_scene(
            p,
            concat!(world!(), "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"{}\"\nShape \"sphere\"\n"),
        )
    });
}

#[test]
fn fuzz_ply_all_encodings() {
    fuzz("ply", &seeds("ply"), |p| load_scene(p, concat!(world!(), "Shape \"plymesh\" \"string filename\" \"{}\"\n")));
}

#[test]
fn fuzz_lens_files() {
    // Every lens file that reads costs the realistic camera's exit-pupil bounds (4 M rays
    // through the lens system), so fewer mutants than the other formats.
    fuzz_n("lens", &seeds("lens"), 40, |p| {
        let text =
            "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"realistic\" \"string lensfile\" \"{}\"\nWorldBegin\nShape \"sphere\"\n";
        load_scene(p, text)
    });
}

#[test]
fn fuzz_spd_files() {
    fuzz("spd", &seeds("spd"), |p| {
        load_scene(p, concat!(world!(), "Material \"diffuse\" \"spectrum reflectance\" \"{}\"\nShape \"sphere\"\n"))
    });
}

#[test]
fn fuzz_measured_bsdf_files() {
    // The seed: a GGX conductor tabulated by `prism::bsdf::measured::tabulate` (3 angles,
    // 6 wavelengths, 8² grids) in the RGL tensor format.
    fuzz("bsdf", &seeds("bsdf"), |p| {
        load_scene(p, concat!(world!(), "Material \"measured\" \"string filename\" \"{}\"\nShape \"sphere\"\n"))
    });
}

#[test]
fn fuzz_nanovdb() {
    fuzz("nanovdb", &[data("nanovdb/tiles.nvdb")], |p| {
        prism::media::nanovdb::NanoVdbFile::open(p).map_err(|e| e.to_string())?;
        prism::media::nanovdb::read_float_grids(p, &["density"]).map(|_| ()).map_err(|e| e.to_string())
    });
}

#[test]
fn fuzz_film_checkpoints() {
    fuzz("film", &seeds("film"), |p| prism::checkpoint::load(p).map(|_| ()).map_err(|e| e.to_string()));
}
