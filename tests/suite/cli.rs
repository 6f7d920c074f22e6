//! The `prism` binary end to end: clear one-line errors, no half-written files, stats JSON,
//! split/merge equality, time limits, and resuming after `kill -9`.

use crate::common::{film, prism, stderr, tmpdir};
use std::path::{Path, PathBuf};
use std::process::Output;

fn run(args: &[&str]) -> Output {
    prism().args(args).output().expect("run prism")
}

/// Bad input: a non-zero exit, one line starting "prism: error:", no panic.
fn assert_clean_error(args: &[&str], needle: &str) {
    let o = run(args);
    let e = stderr(&o);
    assert!(!o.status.success(), "{args:?} succeeded");
    assert!(!e.contains("panicked"), "{args:?} panicked: {e}");
    let line = e.lines().find(|l| l.starts_with("prism: error:")).unwrap_or_else(|| panic!("{args:?}: {e}"));
    assert!(line.contains(needle), "{args:?}: '{line}' lacks '{needle}'");
    let others: Vec<&str> = e.lines().filter(|l| !l.starts_with("prism: warn") && *l != line).collect();
    assert!(others.is_empty(), "{args:?}: the error is more than one line: {e}");
}

#[test]
fn bad_input_gets_one_clear_line() {
    let d = tmpdir("errors");
    let out = d.join("x.png");
    let out = out.to_str().unwrap();
    assert_clean_error(&["render", "--accel", "optix", "-o", out], "unknown accelerator 'optix'");
    assert_clean_error(&["render", "/no/such/scene.pbrt", "-o", out], "does not exist");
    assert_clean_error(&["render", "-o", "/no/such/dir/out.png"], "cannot write");
    assert_clean_error(&["render", "-o", d.join("out.bmpx").to_str().unwrap()], "unsupported output format 'bmpx'");
    assert_clean_error(&["render", "--spp", "0", "-o", out], "--spp must be positive");
    assert_clean_error(&["render", "--spp", "-3", "-o", out], "--spp must be positive");
    assert_clean_error(&["render", "--resolution", "0x64", "-o", out], "resolution must be positive");
    assert_clean_error(&["render", "--resolution", "-4x64", "-o", out], "resolution must be positive");
    assert_clean_error(&["render", "--threads", "0", "-o", out], "--threads must be at least 1");
    // Too long a duration, a part of no samples, a statistics file that cannot be written: all
    // refused before rendering.
    assert_clean_error(&["render", "--time-limit", "1e30s", "-o", out], "duration '1e30s' is too long");
    assert_clean_error(&["render", "--checkpoint-every", "1e300s", "-o", out], "duration '1e300s' is too long");
    let film = d.join("part.film");
    let film = film.to_str().unwrap();
    assert_clean_error(&["render", "--spp", "4", "--part", "3/8", "-o", film], "leave this part none");
    assert_clean_error(
        &["render", "--stats-json", "/no/such/dir/s.json", "-o", out],
        "cannot write /no/such/dir/s.json",
    );
    assert!(!Path::new(film).exists(), "no part may be written on error");
    // clap's own errors (a value out of range, an unknown flag) are one line too.
    assert_clean_error(&["compat", "--repeat", "0", "--out", d.to_str().unwrap()], "--repeat");
    assert_clean_error(&["render", "--no-such-flag"], "unexpected argument '--no-such-flag'");
    let depth = "--max-depth must be at least 0, or -1 for no limit";
    assert_clean_error(&["render", "--max-depth", "-2", "-o", out], depth);
    assert_clean_error(&["measure", "radiance", "--at", "0,0,0", "--dir", "0,0,0"], "--dir must not be zero");
    assert_clean_error(&["measure", "irradiance", "--at", "0,0", "--normal", "0,0,1"], "--at '0,0' is not three");
    assert!(!Path::new(out).exists(), "no image may be written on error");
    let bench_out = d.join("bench");
    let bench_args = ["bench", "builtin:nope", "--out", bench_out.to_str().unwrap()];
    assert_clean_error(&bench_args, "unknown built-in scene 'builtin:nope'");
    let bench_out_s = bench_out.to_str().unwrap();
    assert_clean_error(&["bench", "--reference-spp", "0", "--out", bench_out_s], "--reference-spp must be positive");
    assert_clean_error(&["bench", "--spp-ladder", "1,0", "--out", bench_out_s], "--spp-ladder must be positive");
    assert_clean_error(&["bench", "--threads", "0", "--out", bench_out_s], "--threads must be at least 1");
    let target = "--target-rmse: '-1' is not a positive";
    assert_clean_error(&["bench", "--target-rmse", "0.01,-1", "--out", bench_out_s], target);
    assert_clean_error(&["bench", "--max-depth", "-2", "--out", bench_out_s], depth);
    assert_clean_error(&["measure", "radiance", "--at", "0,0,0", "--dir", "0,0,1", "--max-depth", "-2"], depth);
    assert!(!bench_out.exists(), "bench must fail before rendering anything");
    let sss_out = d.join("sss");
    let sss = |extra: &[&str], needle: &str| {
        let mut args = vec!["sss-report", "--out", sss_out.to_str().unwrap()];
        args.extend_from_slice(extra);
        assert_clean_error(&args, needle);
    };
    sss(&["--size", "0"], "--size must be positive");
    sss(&["--reference-spp", "0"], "--reference-spp must be positive");
    sss(&["--convergence-spp", "0"], "--convergence-spp must be positive");
    sss(&["--ladder", "0,4"], "--ladder must be positive");
    assert!(!sss_out.exists(), "sss-report must fail before rendering anything");
    // A missing file's OS error is said once, not again by the error's chain of causes.
    let missing = d.join("missing.film");
    let missing = missing.to_str().unwrap();
    for args in [vec!["merge", missing, "-o", out], vec!["color", "xyz", "--spd", missing]] {
        assert_clean_error(&args, "No such file");
        assert_eq!(stderr(&run(&args)).matches("No such file").count(), 1, "{args:?}");
    }
}

#[test]
fn render_writes_image_and_stats_json_and_leaves_no_temp_files() {
    let d = tmpdir("render");
    let png = d.join("cb.png");
    let json = d.join("stats.json");
    let o = run(&[
        "render",
        "--spp",
        "2",
        "--resolution",
        "32x24",
        "--accel",
        "obvhs",
        "-o",
        png.to_str().unwrap(),
        "--stats-json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = prism::image::read(&png).unwrap();
    assert_eq!((img.width, img.height), (32, 24));
    assert!(img.data.iter().any(|&v| v > 0.05), "black image");
    let stats: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in ["elapsed_s", "spp", "width", "height", "rays", "rays_per_s", "samples_per_s", "accel"] {
        assert!(stats.get(key).is_some(), "stats lack {key}");
    }
    assert_eq!(stats["spp"], 2);
    assert_eq!(stats["accel"], "obvhs");
    assert_eq!(stats["nonfinite_samples"], 0);
    // The time to first pixel holds the build.
    let (build, startup) = (stats["build_s"].as_f64().unwrap(), stats["startup_s"].as_f64().unwrap());
    assert!(build > 0.0 && startup >= build, "build {build} s, start-up {startup} s");
    let leftovers: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

#[test]
fn parts_merge_to_the_single_render() {
    let d = tmpdir("parts");
    let common = ["--spp", "6", "--resolution", "20x16", "--accel", "obvhs", "--seed", "3"];
    let whole = d.join("whole.film");
    let o = prism().arg("render").args(common).args(["-o", whole.to_str().unwrap()]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let mut parts = Vec::new();
    for i in 1..=3 {
        let p = d.join(format!("part{i}.film"));
        let o = prism()
            .arg("render")
            .args(common)
            .args(["--part", &format!("{i}/3"), "-o", p.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        parts.push(p);
    }
    let merged = d.join("merged.film");
    let o = prism()
        .arg("merge")
        .args(parts.iter().map(|p| p.to_str().unwrap()))
        .args(["-o", merged.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (film(&whole), film(&merged));
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        assert_eq!(p.samples, q.samples);
        // The same samples summed in a different grouping: equal up to f64 rounding.
        assert!((p.xyz_sum - q.xyz_sum).abs().max_element() <= 1e-9 * (1.0 + p.xyz_sum.abs().max_element()));
    }
    // Parts from a different render are refused.
    let other = d.join("other.film");
    let o = prism()
        .args([
            "render",
            "--spp",
            "6",
            "--resolution",
            "20x16",
            "--accel",
            "obvhs",
            "--seed",
            "4",
            "--part",
            "1/3",
            "-o",
            other.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let o = prism()
        .args(["merge", other.to_str().unwrap(), parts[1].to_str().unwrap(), "-o", d.join("bad.png").to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!o.status.success() && stderr(&o).contains("different scenes or settings"), "{}", stderr(&o));
}

#[test]
fn time_limit_stops_at_a_pass_and_writes_a_valid_image() {
    let d = tmpdir("limit");
    let out = d.join("t.exr");
    let t0 = std::time::Instant::now();
    let o = run(&[
        "render",
        "--spp",
        "100000",
        "--resolution",
        "16x16",
        "--accel",
        "obvhs",
        "--time-limit",
        "1s",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(t0.elapsed().as_secs_f64() < 60.0);
    let img = prism::image::read(&out).unwrap();
    assert!(img.data.iter().all(|v| v.is_finite()) && img.data.iter().any(|&v| v > 0.0));
}

#[test]
fn resume_after_kill_matches_an_uninterrupted_render() {
    let d = tmpdir("resume");
    let out = d.join("r.film");
    // About 1.5 s of work on one thread, seven times the checkpoint interval: the render must still
    // be running when it is killed (at 400 spp it sometimes finished first and removed its
    // checkpoint).
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
        "0.2s",
        "-o",
    ];
    let mut child = prism().args(args).arg(&out).spawn().unwrap();
    let ckpt = PathBuf::from(format!("{}.ckpt", out.display()));
    let t0 = std::time::Instant::now();
    while !ckpt.exists() && t0.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    std::thread::sleep(std::time::Duration::from_millis(100));
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(ckpt.exists(), "no checkpoint was written");
    let (partial, h) = prism::checkpoint::load(&ckpt).unwrap();
    assert!(h.samples.end < 1200, "the render finished before it was killed");
    assert!(partial.pixels[0].samples > 0);
    let o = prism().args(args).arg(&out).arg("--resume").output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let whole = d.join("whole.film");
    let o = prism().args(args).arg(&whole).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // Same samples (indices are deterministic), so equal up to summation grouping.
    let (a, b) = (film(&out), film(&whole));
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        assert_eq!(p.samples, 1200);
        assert!((p.xyz_sum - q.xyz_sum).abs().max_element() <= 1e-9 * (1.0 + p.xyz_sum.abs().max_element()));
    }
}

/// `--accel` lists the three backends in `render --help` and in its error, and
/// `embree-watertight` renders (and is named in the stats), or is a clear error without Embree.
#[test]
fn accel_choices_are_listed_and_embree_watertight_renders() {
    let help = String::from_utf8_lossy(&run(&["render", "--help"]).stdout).into_owned();
    assert!(help.contains("embree-watertight") && help.contains("obvhs"), "{help}");
    let d = tmpdir("accel");
    let (png, json) = (d.join("w.png"), d.join("w.json"));
    let (png, json) = (png.to_str().unwrap(), json.to_str().unwrap());
    assert_clean_error(&["render", "--accel", "optix", "-o", png], "valid: embree, embree-watertight, obvhs");
    let args = ["render", "--accel", "embree-watertight", "--spp", "1", "--resolution", "8x8", "-o", png];
    if cfg!(embree) {
        let o = run(&[&args[..], &["--stats-json", json]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        let stats: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
        assert_eq!(stats["accel"], "embree-watertight");
    } else {
        assert_clean_error(&args, "built without Embree");
    }
}

#[test]
fn bench_writes_every_output_and_reuses_its_cached_reference() {
    let d = tmpdir("bench");
    let out = d.join("out");
    let accels = if cfg!(embree) { "embree,obvhs" } else { "obvhs" };
    let args = [
        "bench",
        "--accel",
        accels,
        "--spp-ladder",
        "1,16",
        "--reference-spp",
        "64",
        "--resolution",
        "24x16",
        "--max-depth",
        "4",
        "--threads",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    let first = run(&args);
    assert!(first.status.success(), "{}", stderr(&first));
    for f in ["bench.csv", "bench.json", "bench.md", "run.json", "error_vs_time.png", "error_vs_time.svg"] {
        assert!(std::fs::metadata(out.join(f)).is_ok_and(|m| m.len() > 0), "{f} missing or empty");
    }
    let json = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(out.join(name)).unwrap()).unwrap()
    };
    let points = json("bench.json");
    let points = points.as_array().unwrap();
    let n_accels = accels.split(',').count();
    assert_eq!(points.len(), n_accels * 2 * 2, "accels × samplers × ladder");
    let rmse = |accel: &str, sampler: &str, spp: u64| {
        let p = points.iter().find(|p| p["accel"] == accel && p["sampler"] == sampler && p["spp"] == spp);
        p.unwrap_or_else(|| panic!("no point {accel} {sampler} {spp}"))["rmse"].as_f64().unwrap()
    };
    for p in points {
        let f = |k: &str| p[k].as_f64().unwrap();
        // Every sample traces at least its camera ray.
        assert!(f("samples_per_s") > 0.0 && f("rays_per_s") >= f("samples_per_s"), "{p}");
        // The accelerator's own count of its bytes: at least its triangles' 36 bytes of vertices.
        assert!(f("accel_own_bytes") >= 36.0 * f("triangles") && f("triangles") > 0.0, "{p}");
    }
    // The default target is the lowest RMSE every curve reaches, so each curve reaches it no
    // later than its last ladder point.
    let times = json("time_to_rmse.json");
    let times = times.as_array().unwrap();
    assert_eq!(times.len(), n_accels * 2, "one time per curve: {times:?}");
    for t in times {
        let curve = points.iter().filter(|p| p["accel"] == t["accel"] && p["sampler"] == t["sampler"]);
        let (last_time, best) = curve.fold((0.0f64, f64::MAX), |(lt, b), p| {
            (lt.max(p["time_s"].as_f64().unwrap()), b.min(p["rmse"].as_f64().unwrap()))
        });
        let (target, time) = (t["target_rmse"].as_f64().unwrap(), t["time_s"].as_f64().unwrap());
        assert!(target >= best && time > 0.0 && time <= last_time * (1.0 + 1e-9), "{t} of {points:?}");
    }
    assert!(std::fs::read_to_string(out.join("bench.md")).unwrap().contains("time to RMSE"));
    for sampler in ["independent", "sobol"] {
        // 16× the samples: Monte Carlo error falls ~4× (more with Sobol); 2× leaves room for the
        // noise of a 384-pixel RMSE and of the 64-spp reference.
        let (e1, e16) = (rmse("obvhs", sampler, 1), rmse("obvhs", sampler, 16));
        assert!(e16 > 0.0 && e1 > 2.0 * e16, "{sampler}: RMSE {e1} at 1 spp, {e16} at 16");
        if cfg!(embree) {
            // The backends trace the same paths, so their images (and errors) are the same.
            let e = rmse("embree", sampler, 16);
            assert!((e - e16).abs() <= 1e-3 * e16, "{sampler}: embree {e} vs obvhs {e16}");
        }
    }
    let info = json("run.json");
    assert_eq!((info["threads"].as_u64(), info["max_depth"].as_u64()), (Some(1), Some(4)));
    assert_eq!(info["resolution"], serde_json::json!([24, 16]));
    assert!(std::fs::read_to_string(out.join("bench.md")).unwrap().starts_with("- machine: "));
    // A second run with the same settings reuses the reference and measures the same errors.
    let second = run(&args);
    assert!(stderr(&second).contains("using the cached reference"), "{}", stderr(&second));
    let again = json("bench.json");
    for (a, b) in points.iter().zip(again.as_array().unwrap()) {
        assert_eq!(a["rmse"], b["rmse"]);
    }
    // Targets given: a tighter one takes every curve longer.
    let third = run(&[&args[..], &["--target-rmse", "0.5,0.05"]].concat());
    assert!(third.status.success(), "{}", stderr(&third));
    let times = json("time_to_rmse.json");
    let time = |t: &serde_json::Value, target: f64| {
        let same = |u: &&serde_json::Value| u["accel"] == t["accel"] && u["sampler"] == t["sampler"];
        let at = times.as_array().unwrap().iter().filter(same).find(|u| u["target_rmse"] == target);
        at.unwrap_or_else(|| panic!("no time to {target} in {times}"))["time_s"].as_f64().unwrap()
    };
    for t in times.as_array().unwrap() {
        assert!(time(t, 0.05) > time(t, 0.5), "{times}");
    }
    // A given reference of another size is refused before anything renders.
    let reference = out.join("reference.exr");
    let other = d.join("other");
    let wrong =
        ["bench", "--reference", reference.to_str().unwrap(), "--resolution", "8x8", "--out", other.to_str().unwrap()];
    assert_clean_error(&wrong, "is 24x16, but the bench renders 8x8 (--resolution)");
    assert!(!other.join("bench.json").exists());
}

#[test]
fn bench_renders_a_new_reference_after_its_scene_or_a_file_it_reads_changes() {
    let d = tmpdir("bench-scene");
    let scene = d.join("s.pbrt");
    let body = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\nWorldBegin\n\
                Include \"light.pbrt\"\nShape \"sphere\"\nShape \"objmesh\" \"string filename\" \"tri.obj\"\n";
    std::fs::write(&scene, body).unwrap();
    let light = "LightSource \"point\" \"rgb I\" [10 10 10] \"point3 from\" [0 3 3]\n";
    std::fs::write(d.join("light.pbrt"), light).unwrap();
    let mesh = "v -2 -2 -1\nv 2 -2 -1\nv 0 2 -1\nf 1 2 3\n";
    std::fs::write(d.join("tri.obj"), mesh).unwrap();
    let out = d.join("out");
    let args = [
        "bench",
        scene.to_str().unwrap(),
        "--accel",
        "obvhs",
        "--sampler",
        "sobol",
        "--spp-ladder",
        "1",
        "--reference-spp",
        "4",
        "--resolution",
        "8x8",
        "--out",
        out.to_str().unwrap(),
    ];
    let rendered = |o: &Output| {
        assert!(o.status.success(), "{}", stderr(o));
        stderr(o).contains("rendering a reference")
    };
    assert!(rendered(&run(&args)), "first run renders the reference");
    assert!(!rendered(&run(&args)), "an unchanged scene reuses it");
    std::fs::write(&scene, format!("{body}# edited\n")).unwrap();
    assert!(rendered(&run(&args)), "an edited scene file renders a new one");
    std::fs::write(d.join("light.pbrt"), light.replace("[10 10 10]", "[20 20 20]")).unwrap();
    assert!(rendered(&run(&args)), "an edited included file renders a new one");
    assert!(!rendered(&run(&args)), "and the new one is reused");
    std::fs::write(d.join("tri.obj"), mesh.replace("v 0 2 -1", "v 0 3 -1")).unwrap();
    assert!(rendered(&run(&args)), "an edited mesh file renders a new one");
}

#[test]
fn compare_prints_the_metrics_and_writes_the_difference_image() {
    let d = tmpdir("compare");
    let image = |name: &str, (w, h): (u32, u32), v: f32| {
        let path = d.join(name);
        let img = prism::image::Image { width: w, height: h, channels: 3, data: vec![v; (w * h * 3) as usize] };
        prism::image::write(&path, &img).unwrap();
        path.to_str().unwrap().to_owned()
    };
    let (a, b, small) = (image("a.exr", (8, 4), 0.5), image("b.exr", (8, 4), 0.25), image("s.exr", (4, 4), 0.25));
    let diff = d.join("diff.png");
    let o = run(&["compare", &a, &b, "--json", "--diff", diff.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // Every sample differs by 0.25 (exact in half and single precision).
    for k in ["rmse", "mae", "max_abs"] {
        assert_eq!(m[k].as_f64(), Some(0.25), "{k}: {m}");
    }
    // The compatibility report's error: 0.5/1.5 − 0.25/1.25 = 2/15 in every sample.
    assert!((m["compat_error"].as_f64().unwrap() - 2.0 / 15.0).abs() < 1e-6, "{m}");
    let png = prism::image::read(&diff).unwrap();
    assert_eq!((png.width, png.height), (8, 4));
    // Images of two sizes, and a difference image that cannot be written: one line, no metrics.
    assert_clean_error(&["compare", &a, &small], &format!("comparing {a} with {small}: image size mismatch"));
    let o = run(&["compare", &a, &b, "--diff", "/no/such/dir/d.png"]);
    assert!(!o.status.success() && o.stdout.is_empty(), "{}", String::from_utf8_lossy(&o.stdout));
    assert!(stderr(&o).starts_with("prism: error: cannot write /no/such/dir/d.png"), "{}", stderr(&o));
}

#[test]
fn a_reader_that_closes_the_pipe_early_is_no_error() {
    // `prism compare a b | head -c0`: head exits before prism writes, so prism's write fails
    // with EPIPE; it must exit 0 without a panic, as `cat` would.
    let d = tmpdir("pipe");
    let path = d.join("a.exr");
    let img = prism::image::Image { width: 4, height: 4, channels: 3, data: vec![0.5; 48] };
    prism::image::write(&path, &img).unwrap();
    let a = path.to_str().unwrap();
    let script = format!("'{}' compare '{a}' '{a}' | head -c0; exit ${{PIPESTATUS[0]}}", env!("CARGO_BIN_EXE_prism"));
    let o = std::process::Command::new("bash").args(["-c", &script]).env("RUST_BACKTRACE", "0").output().unwrap();
    assert!(o.status.success(), "exit {:?}: {}", o.status, stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
}

/// A scene whose one sphere is textured by the image `image` (relative to the scene's directory).
fn imagemap_scene(dir: &Path, image: &str) -> PathBuf {
    let scene = dir.join(format!("{image}.pbrt"));
    let text = format!(
        "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n\
         Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"{image}\"\n\
         Material \"diffuse\" \"texture reflectance\" \"t\"\nShape \"sphere\"\n"
    );
    std::fs::write(&scene, text).unwrap();
    scene
}

#[test]
fn a_corrupt_png_or_jpeg_texture_is_one_line_whatever_the_decoder_prints() {
    let d = tmpdir("corrupt-images");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz");
    let png = std::fs::read(data.join("png/rgb4x4.png")).unwrap();
    let jpeg = std::fs::read(data.join("jpeg/render8x6.jpg")).unwrap();
    // The IDAT chunk's type garbled (libpng prints "libpng error: ..." itself); a PNG cut inside
    // its pixel data; a JPEG cut in half (the Rust decoder's message ends in a newline); a JPEG
    // whose Huffman tables are overwritten.
    let mut bad_png = png.clone();
    bad_png[40] ^= 0xff;
    let mut bad_jpeg = jpeg.clone();
    bad_jpeg[200..260].iter_mut().step_by(3).for_each(|b| *b = 0xff);
    let cases = [
        ("idat.png", bad_png),
        ("cut.png", png[..50].to_vec()),
        ("cut.jpg", jpeg[..jpeg.len() / 2].to_vec()),
        ("huffman.jpg", bad_jpeg),
    ];
    let out = d.join("out.png");
    for (name, bytes) in cases {
        std::fs::write(d.join(name), bytes).unwrap();
        let scene = imagemap_scene(&d, name);
        let args =
            ["render", scene.to_str().unwrap(), "--spp", "1", "--resolution", "8x8", "-o", out.to_str().unwrap()];
        assert_clean_error(&args, "cannot decode image");
    }
    assert!(!out.exists(), "no image may be written on error");
}
