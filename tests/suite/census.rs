//! pbrt-v4's 98 test scenes (reconstructed beside the repository, with small stand-ins for their
//! binary files): each renders under `--strict` at 16×16, 1 spp, from its own folder, except
//! those that need a feature prism lacks, named in `GAPS`. A scene failing for any other reason,
//! or a gap no scene shows any more, fails the test, so the list stays exact as features land.

use crate::common::{prism, stderr, tmpdir};
use std::path::PathBuf;

/// The unsupported features the census still meets, as the strict error names them.
const GAPS: &[&str] = &[];

#[test]
fn pbrt_v4s_test_scenes_render_under_strict_but_for_the_named_gaps() {
    let census = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/pbrt-v4-census");
    let Ok(list) = std::fs::read_to_string(census.join("scenes.txt")) else {
        eprintln!("skipped: {} is not available", census.display());
        return;
    };
    let out = tmpdir("census");
    let (mut passed, mut gaps_seen, mut wrong) = (0, vec![0usize; GAPS.len()], Vec::new());
    for scene in list.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let path = census.join(scene);
        let image = out.join(format!("{}.exr", scene.replace('/', "_")));
        let o = prism()
            .current_dir(path.parent().unwrap())
            .arg("render")
            .arg(path.file_name().unwrap())
            .args(["--strict", "--spp", "1", "--resolution", "16x16", "--threads", "1", "-o"])
            .arg(&image)
            .output()
            .unwrap();
        let e = stderr(&o);
        if o.status.success() && image.exists() {
            passed += 1;
            continue;
        }
        let gap = GAPS.iter().position(|g| e.contains(&format!("unsupported feature: {g}")));
        match gap {
            // The error is one line (warnings printed before it are other lines).
            Some(i) if e.lines().filter(|l| !l.starts_with("prism: warning:")).count() == 1 => gaps_seen[i] += 1,
            _ => wrong.push(format!("{scene}: {}", e.trim())),
        }
    }
    assert!(wrong.is_empty(), "{} scenes fail for a reason not in GAPS:\n{}", wrong.len(), wrong.join("\n"));
    let stale: Vec<&str> = GAPS.iter().zip(&gaps_seen).filter(|(_, n)| **n == 0).map(|(g, _)| *g).collect();
    assert!(stale.is_empty(), "no scene shows these gaps any more; remove them from GAPS: {stale:?}");
    eprintln!(
        "census: {passed} of {} render under --strict; gaps {gaps_seen:?}",
        passed + gaps_seen.iter().sum::<usize>()
    );
}
