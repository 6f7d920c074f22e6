//! Out of memory and failed devices: inputs that would need absurd allocations, and an
//! Embree device that cannot be created, end in a clear error naming the cause — one line from
//! the CLI, never an abort.

use std::path::PathBuf;
use std::process::Command;

use prism::pbrt::mesh_io::ply;

fn tmpdir(name: &str) -> PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("prism-resource-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// PLY headers claiming billions of elements, followed by a few bytes of data.
fn absurd_plys() -> Vec<(&'static str, Vec<u8>)> {
    let body = vec![0u8; 64];
    let with = |h: &str| {
        let mut v = h.as_bytes().to_vec();
        v.extend(&body);
        v
    };
    vec![
        (
            "4e9 binary vertices",
            with("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n"),
        ),
        (
            "3e9 ascii faces",
            with("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 3000000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"),
        ),
        (
            "2^64 - 1 entries",
            with("ply\nformat binary_big_endian 1.0\nelement vertex 18446744073709551615\nproperty double x\nproperty double y\nproperty double z\nend_header\n"),
        ),
        (
            "property-less element of 1e18",
            with("ply\nformat binary_little_endian 1.0\nelement junk 1000000000000000000\nend_header\n"),
        ),
    ]
}

#[test]
fn ply_headers_claiming_billions_of_elements_are_rejected_before_allocating() {
    for (what, bytes) in absurd_plys() {
        // Allocating what the header claims would take tens of GB (or overflow): the size check
        // against the data that follows must reject it first, quickly.
        let t = std::time::Instant::now();
        let err = ply::parse(&bytes).expect_err(what).to_string();
        assert!(err.contains("declares") || err.contains("entries"), "{what}: {err}");
        assert!(t.elapsed().as_secs_f32() < 1.0, "{what}: took {:?}", t.elapsed());
    }
}

#[test]
fn cli_reports_an_absurd_ply_in_one_line() {
    let dir = tmpdir("ply");
    std::fs::write(dir.join("huge.ply"), &absurd_plys()[0].1).unwrap();
    let scene = dir.join("scene.pbrt");
    std::fs::write(&scene, "WorldBegin\nShape \"plymesh\" \"string filename\" \"huge.ply\"\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_prism"))
        .args(["render", scene.to_str().unwrap(), "--spp", "1", "--resolution", "4x4", "-o"])
        .arg(dir.join("out.exr"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("scene.pbrt:2:") && err.contains("4000000000"), "{err}");
    assert!(!dir.join("out.exr").exists());
}

#[test]
fn a_film_that_does_not_fit_in_memory_is_a_one_line_error() {
    // An 8 GB address-space limit makes the 10 GiB film of a 16384² render fail to allocate on
    // any machine; prism must say so instead of aborting ("memory allocation failed").
    let dir = tmpdir("oom");
    let out = dir.join("huge.png");
    let cmd = format!(
        "ulimit -v 8000000 && exec '{}' render --resolution 16384x16384 --spp 1 -o '{}'",
        env!("CARGO_BIN_EXE_prism"),
        out.display()
    );
    let o = Command::new("sh").args(["-c", &cmd]).env("RUST_BACKTRACE", "0").output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("out of memory: a 16384x16384 film needs 10.0 GiB"), "{err}");
    assert!(!out.exists());
}

#[cfg(embree)]
mod embree {
    use super::*;
    use prism::accel::embree::{error_name, Device};

    #[test]
    fn a_device_that_cannot_be_created_is_an_error_naming_embrees_cause() {
        // Embree 3 rejects a malformed value (it ignores unknown names and ISAs).
        let err = Device::with_config("threads=abc").err().expect("a malformed configuration must not give a device");
        let msg = err.to_string();
        assert!(msg.contains("Embree device") && msg.contains("unknown error") && msg.contains("threads=abc"), "{msg}");
        assert!(Device::with_config("bad\0config").is_err());
        // The default configuration works.
        assert!(Device::with_config("").is_ok());
        assert_eq!(error_name(4), "out of memory");
    }

    #[test]
    fn cli_reports_a_failed_embree_device_in_one_line() {
        let dir = tmpdir("embree");
        let out = Command::new(env!("CARGO_BIN_EXE_prism"))
            .env("PRISM_EMBREE_CONFIG", "threads=abc")
            .args(["render", "--accel", "embree", "--spp", "1", "--resolution", "4x4", "-o"])
            .arg(dir.join("out.png"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains("Embree") && err.contains("PRISM_EMBREE_CONFIG"), "{err}");
    }
}
