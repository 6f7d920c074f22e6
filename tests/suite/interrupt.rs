//! SIGINT and SIGTERM during `prism render`: the render ends after its pass, writes the image (or
//! .film part) of the samples it has and the checkpoint when one was asked for, says so in one
//! line and exits with the shell's status for the signal; a checkpoint written so resumes to the
//! uninterrupted render. stderr is a pipe here, so progress comes as plain lines.

use crate::common::{film, prism, tmpdir};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::Stdio;

/// Runs `prism render ARGS -o OUT`, waits for its first progress line, sends it `signal` (`INT`
/// or `TERM`) and returns its exit status and stderr lines.
fn render_and_signal(args: &[&str], out: &Path, signal: &str) -> (Option<i32>, Vec<String>) {
    let mut child = prism().args(args).arg("-o").arg(out).stderr(Stdio::piped()).spawn().unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines().map(Result::unwrap);
    let mut seen = Vec::new();
    for line in lines.by_ref() {
        let progress = line.starts_with("prism: ") && line.contains(" spp, ");
        seen.push(line);
        if progress {
            break;
        }
    }
    assert!(seen.last().is_some_and(|l| l.contains(" spp, ")), "no progress line: {seen:?}");
    let kill = std::process::Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status();
    assert!(kill.unwrap().success());
    seen.extend(lines);
    (child.wait().unwrap().code(), seen)
}

/// The one "interrupted" line, and the samples per pixel it says were done.
fn interrupted_line(lines: &[String]) -> (String, u64) {
    let hits: Vec<&String> = lines.iter().filter(|l| l.contains("interrupted")).collect();
    assert_eq!(hits.len(), 1, "{lines:?}");
    let line = hits[0].clone();
    let n = line.split("interrupted after ").nth(1).and_then(|r| r.split(' ').next()).unwrap().parse().unwrap();
    (line, n)
}

/// Files in `dir` whose name starts with a dot: the temporaries of atomic writes.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let entries = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path());
    entries.filter(|p| p.file_name().unwrap().to_string_lossy().starts_with('.')).collect()
}

/// 100000 spp of the Cornell box take about a minute: the signal comes long before the end.
const LONG: [&str; 7] = ["render", "--spp", "100000", "--resolution", "16x16", "--accel", "obvhs"];

fn signal_writes_the_image_so_far(signal: &str, status: i32) {
    let d = tmpdir(&format!("interrupt-{signal}"));
    let out = d.join("out.exr");
    let (code, lines) = render_and_signal(&LONG, &out, signal);
    assert_eq!(code, Some(status), "{lines:?}");
    let (line, done) = interrupted_line(&lines);
    assert!(done > 0 && done < 100000, "{line}");
    assert!(line.contains("of 100000 samples per pixel") && line.contains("out.exr"), "{line}");
    let img = prism::image::read(&out).unwrap();
    assert_eq!((img.width, img.height), (16, 16));
    assert!(img.data.iter().all(|v| v.is_finite()) && img.data.iter().any(|&v| v > 0.0));
    assert!(temporaries(&d).is_empty(), "{:?}", temporaries(&d));
}

#[test]
fn sigint_writes_the_image_so_far_and_exits_130() {
    signal_writes_the_image_so_far("INT", 130);
}

#[test]
fn sigterm_writes_the_image_so_far_and_exits_143() {
    signal_writes_the_image_so_far("TERM", 143);
}

/// A second signal ends the process at once with the signal's status, leaving no temporary
/// (the image is then either whole or not there).
#[test]
fn a_second_sigint_exits_130_at_once_and_leaves_no_temporary() {
    let d = tmpdir("interrupt-twice");
    let out = d.join("out.exr");
    let mut child = prism().args(LONG).arg("-o").arg(&out).stderr(Stdio::piped()).spawn().unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines().map(Result::unwrap);
    assert!(lines.by_ref().any(|l| l.contains(" spp, ")), "no progress line");
    for _ in 0..2 {
        let kill = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status();
        assert!(kill.unwrap().success());
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let rest: Vec<String> = lines.collect();
    assert_eq!(child.wait().unwrap().code(), Some(130), "{rest:?}");
    assert!(temporaries(&d).is_empty(), "{:?}", temporaries(&d));
    if out.exists() {
        assert_eq!(prism::image::read(&out).map(|i| (i.width, i.height)).ok(), Some((16, 16)));
    }
}

/// An interrupted part is a .film holding the samples it took, named by its header, which
/// `prism merge` then reports as missing the rest.
#[test]
fn an_interrupted_part_saves_the_samples_it_took() {
    let d = tmpdir("interrupt-part");
    let out = d.join("part2.film");
    let (code, lines) = render_and_signal(&[&LONG[..], &["--part", "2/2"]].concat(), &out, "TERM");
    assert_eq!(code, Some(143), "{lines:?}");
    let (line, done) = interrupted_line(&lines);
    let (f, h) = prism::checkpoint::load(&out).unwrap();
    assert_eq!(h.samples, 50000..50000 + done, "{line}");
    assert!(done > 0 && done < 50000, "{line}");
    assert!(f.pixels.iter().all(|p| p.samples == done));
}

/// The checkpoint written on SIGINT continues (`--resume`) to the film of a render never
/// interrupted, bit for bit: the same samples added in the same order.
#[test]
fn a_checkpoint_written_on_sigint_resumes_to_the_uninterrupted_render() {
    let d = tmpdir("interrupt-resume");
    let out = d.join("r.film");
    // About 1.5 s of work on one thread; the signal comes after the first pass (1 spp). No
    // checkpoint is due by time: only the signal writes one.
    let args = [
        "render",
        "--spp",
        "1200",
        "--resolution",
        "24x24",
        "--accel",
        "obvhs",
        "--threads",
        "1",
        "--checkpoint-every",
        "1h",
    ];
    let (code, lines) = render_and_signal(&args, &out, "INT");
    assert_eq!(code, Some(130), "the render finished before the signal: {lines:?}");
    let (line, done) = interrupted_line(&lines);
    assert!(line.contains("r.film.ckpt"), "{line}");
    let ckpt = PathBuf::from(format!("{}.ckpt", out.display()));
    let (_, h) = prism::checkpoint::load(&ckpt).unwrap();
    assert_eq!(h.samples, 0..done);
    let o = prism().args(args).arg("--resume").arg("-o").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let whole = d.join("whole.film");
    let o = prism().args(args).arg("-o").arg(&whole).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (film(&out), film(&whole));
    assert_eq!(a.pixels.len(), b.pixels.len());
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        assert_eq!(p.samples, 1200);
        assert_eq!((p.xyz_sum, p.weight_sum, p.samples), (q.xyz_sum, q.weight_sum, q.samples));
    }
}
