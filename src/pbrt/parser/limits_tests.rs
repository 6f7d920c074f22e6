//! The bounds on how much scene text one parse reads.

use super::*;

/// Parses `path` on another thread: `None` if it takes longer than a minute.
fn parse_in_time(path: PathBuf) -> Option<Result<(), String>> {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let r = parse_file(&path, &ParseOptions::default()).map(|_| ()).map_err(|e| e.to_string());
        let _ = tx.send(r);
    });
    rx.recv_timeout(std::time::Duration::from_secs(60)).ok()
}

#[test]
fn include_fan_out_is_bounded_by_a_limit_the_error_names() {
    let dir = std::env::temp_dir().join(format!("prism-fan-out-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // f0 includes f1 twice, f1 includes f2 twice, …: 2^24 inclusions of f23.
    for i in 0..24 {
        let next = format!("Include \"f{}.pbrt\"\n", i + 1);
        std::fs::write(dir.join(format!("f{i}.pbrt")), next.repeat(2)).unwrap();
    }
    std::fs::write(dir.join("f24.pbrt"), "Scale 1 1 1\n").unwrap();
    let e = parse_in_time(dir.join("f0.pbrt")).expect("the parse never ended").unwrap_err();
    assert!(e.contains(&MAX_INCLUDES.to_string()) && e.contains("PRISM_MAX_INCLUDES"), "{e}");
    assert!((e.contains(".pbrt:1:1:") || e.contains(".pbrt:2:1:")) && !e.contains('\n'), "{e}");

    // A file included many times in sequence counts each time: the same bound holds.
    let inc = "Include \"f24.pbrt\"\n".repeat(MAX_INCLUDES + 1);
    std::fs::write(dir.join("many.pbrt"), inc).unwrap();
    let e = parse_in_time(dir.join("many.pbrt")).unwrap().unwrap_err();
    assert!(e.contains(&format!("many.pbrt:{}:1:", MAX_INCLUDES + 1)), "{e}");
    // Below the bound it parses.
    let inc = "Include \"f24.pbrt\"\n".repeat(MAX_INCLUDES - 1);
    std::fs::write(dir.join("many.pbrt"), inc).unwrap();
    parse_in_time(dir.join("many.pbrt")).unwrap().unwrap();
    std::fs::remove_dir_all(&dir).ok();
}
