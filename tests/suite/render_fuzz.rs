//! Render-level fuzzing: the repository's scenes with one to three of their numbers replaced by
//! extreme values (0, ±1e30, NaN, ±inf, the i32 limits, ...) are read, built and rendered by
//! `prism render` at 6×6 pixels, 1 sample, on both backends. Each must end with an image or a
//! one-line error (exit status 0 or 1), never a panic, a crash or a hang. The parse-level fuzz
//! (`scene_fuzz.rs`) cannot reach what only a build or a render meets: BVH builds over boxes
//! that overflow, lights with infinite power, cameras with singular matrices.

use crate::common::{backends, prism, tmpdir, wait_within};
use prism::sampling::Rng;
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::Duration;

/// Mutated scenes rendered (half on each backend when there are two).
const CASES: usize = 240;

/// Longer than any case takes (a few to a few hundred milliseconds): a hang.
const TIME_LIMIT: Duration = Duration::from_secs(60);

const EXTREMES: &[&str] =
    &["0", "-1", "1e30", "-1e30", "1e-30", "nan", "inf", "-inf", "3", "1e9", "-0", "2147483647", "-2147483648", "0.5"];

/// The scene files mutated: the compatibility scenes and the example scenes.
fn sources() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<PathBuf> = ["tests/data/compat", "scenes"]
        .iter()
        .flat_map(|d| std::fs::read_dir(root.join(d)).unwrap().map(|e| e.unwrap().path()))
        .filter(|p| p.extension().is_some_and(|e| e == "pbrt"))
        .collect();
    files.sort();
    files
}

/// Byte ranges of the whitespace-separated tokens of `text` that read as numbers (brackets
/// stripped); quoted words never do.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices().chain([(text.len(), ' ')]) {
        match (c.is_whitespace() || c == '[' || c == ']', start) {
            (true, Some(s)) => {
                if text[s..i].parse::<f64>().is_ok() && !text[s..i].starts_with(['i', 'n', 'I', 'N', '+']) {
                    out.push((s, i));
                }
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    out
}

/// `text` with one to three of its numbers replaced by extremes.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut text = text.to_string();
    for _ in 0..1 + rng.next_u32() % 3 {
        let spots = numbers(&text);
        if spots.is_empty() {
            break;
        }
        let (s, e) = spots[rng.next_u32() as usize % spots.len()];
        text.replace_range(s..e, EXTREMES[rng.next_u32() as usize % EXTREMES.len()]);
    }
    text
}

/// A directory where a scene written beside `source`'s folder finds what it names: a link to
/// every entry of that folder.
fn beside(source: &Path, out: &Path) -> PathBuf {
    let folder = source.parent().unwrap();
    let name = folder.file_name().unwrap().to_string_lossy().into_owned();
    let dir = out.join(name);
    if !dir.exists() {
        std::fs::create_dir_all(&dir).unwrap();
        for entry in std::fs::read_dir(folder).unwrap() {
            let entry = entry.unwrap().path();
            std::os::unix::fs::symlink(&entry, dir.join(entry.file_name().unwrap())).unwrap();
        }
    }
    dir
}

#[test]
fn mutated_scenes_render_or_fail_cleanly_on_both_backends() {
    let out = tmpdir("render-fuzz");
    let sources = sources();
    assert!(sources.len() > 20, "{} scenes", sources.len());
    let backends = backends();
    let mut rng = Rng::new(2026, 12);
    let (mut rendered, mut refused) = (0, 0);
    for case in 0..CASES {
        let source = &sources[case % sources.len()];
        let text = mutate(&std::fs::read_to_string(source).unwrap(), &mut rng);
        let dir = beside(source, &out);
        let file = dir.join(format!("fuzz-{case}.pbrt"));
        std::fs::write(&file, &text).unwrap();
        let accel = backends[case % backends.len()];
        let log = out.join("stderr.txt");
        let mut child = prism()
            .current_dir(&dir)
            .args(["render", file.file_name().unwrap().to_str().unwrap()])
            .args(["--resolution", "6x6", "--spp", "1", "--threads", "1", "--accel", accel.name(), "-o"])
            .arg(out.join("fuzz.exr"))
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .unwrap();
        let Some(status) = wait_within(&mut child, TIME_LIMIT) else {
            panic!("{}: no end after {TIME_LIMIT:?} on {accel:?}:\n{text}", source.display());
        };
        let stderr = std::fs::read_to_string(&log).unwrap();
        let clean = matches!(status.code(), Some(0 | 1)) && !stderr.contains("panicked");
        assert!(clean, "{} on {accel:?}: {status}\n{stderr}\n--- scene:\n{text}", source.display());
        if status.success() {
            rendered += 1;
        } else {
            refused += 1;
        }
        std::fs::remove_file(&file).unwrap();
    }
    // Most mutations leave a scene that renders; some make it an error. Both must occur, or
    // the mutations miss the scenes' numbers.
    eprintln!("render fuzz: {rendered} rendered, {refused} refused");
    assert!(rendered > CASES / 4 && refused > 0, "{rendered} rendered, {refused} refused");
}
