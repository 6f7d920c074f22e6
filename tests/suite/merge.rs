//! What `prism merge` and `--resume` combine: only samples of the same render (every input that
//! changes the image is in the fingerprint), and the merged image is the one `prism render`
//! writes, crop window and colour space included.

use crate::common::{prism, stderr, tmpdir};
use std::path::{Path, PathBuf};

/// Runs `prism ARGS`, asserting success.
fn ok(args: &[&str]) {
    let o = prism().args(args).output().unwrap();
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
}

/// `prism merge A B -o OUT`: `Ok(())` or the error line.
fn merge(a: &Path, b: &Path, out: &Path) -> Result<(), String> {
    let o = prism().arg("merge").args([a, b]).arg("-o").arg(out).output().unwrap();
    if o.status.success() {
        Ok(())
    } else {
        Err(stderr(&o))
    }
}

/// A scene reading an included file, a mesh, an image texture and a spectrum file, with a
/// subsurface sphere (so `--sss` changes the image).
fn write_scene(d: &Path) -> PathBuf {
    let scene = d.join("s.pbrt");
    std::fs::write(
        &scene,
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\nWorldBegin\n\
         Include \"light.pbrt\"\n\
         Texture \"tex\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\"\n\
         AttributeBegin\nMaterial \"diffuse\" \"texture reflectance\" \"tex\"\n\
         Shape \"objmesh\" \"string filename\" \"tri.obj\"\nAttributeEnd\n\
         Material \"subsurface\" \"rgb mfp\" [0.5 0.5 0.5] \"rgb reflectance\" [0.8 0.6 0.4]\n\
         Shape \"sphere\" \"float radius\" 0.7\n",
    )
    .unwrap();
    std::fs::write(d.join("light.pbrt"), "LightSource \"point\" \"spectrum I\" \"lamp.spd\" \"point3 from\" [0 3 3]\n")
        .unwrap();
    std::fs::write(d.join("lamp.spd"), "400 10\n700 10\n").unwrap();
    std::fs::write(d.join("tri.obj"), "v -2 -2 -1\nv 2 -2 -1\nv 0 2 -1\nf 1 2 3\n").unwrap();
    let tex = prism::image::Image { width: 2, height: 2, channels: 3, data: [0.2, 0.4, 0.6].repeat(4) };
    prism::image::write(&d.join("tex.png"), &tex).unwrap();
    scene
}

#[test]
fn merge_refuses_parts_of_renders_that_differ_in_any_input() {
    let d = tmpdir("merge-fingerprint");
    let scene = write_scene(&d);
    let scene_s = scene.to_str().unwrap();
    // `prism render` of part i/2 with these flags (flag, value pairs), each replacing the default.
    let part = |name: &str, i: u32, extra: &[&str]| {
        let mut flags = vec![["--spp", "2"], ["--resolution", "8x8"], ["--accel", "obvhs"]];
        for kv in extra.chunks_exact(2) {
            match flags.iter_mut().find(|f| f[0] == kv[0]) {
                Some(f) => f[1] = kv[1],
                None => flags.push([kv[0], kv[1]]),
            }
        }
        let out = d.join(name);
        let p = format!("{i}/2");
        let mut args = vec!["render", scene_s, "--part", &p, "-o", out.to_str().unwrap()];
        args.extend(flags.iter().flatten());
        ok(&args);
        out
    };
    let first = part("first.film", 1, &[]);
    let merged = d.join("m.exr");
    // The control: the second part of the same render merges.
    merge(&first, &part("same.film", 2, &[]), &merged).unwrap();
    // Each setting that changes the image (in both parts, then in the second), and the field the
    // refusal names.
    let settings: [(&[&str], &[&str], &str); 11] = [
        (&[], &["--sss", "randomwalk"], "integrator"),
        (&[], &["--max-depth", "3"], "integrator"),
        (&[], &["--seed", "9"], "seed"),
        (&[], &["--spp", "4"], "spp"),
        (&[], &["--sampler", "independent"], "sampler"),
        (&[], &["--filter", "box"], "filter"),
        (&[], &["--color-space", "rec2020"], "color space"),
        (&[], &["--accel", "embree-watertight"], "accel"),
        (&[], &["--resolution", "8x9"], "size"),
        (&[], &["--cropwindow", "0.5,1,0,1"], "size"),
        // Crops of one size at different places.
        (&["--cropwindow", "0,0.5,0,1"], &["--cropwindow", "0.5,1,0,1"], "film"),
    ];
    for (both, extra, field) in settings {
        if extra.contains(&"embree-watertight") && !cfg!(embree) {
            continue;
        }
        let first = if both.is_empty() { first.clone() } else { part("first-other.film", 1, both) };
        let mut args = both.to_vec();
        args.extend_from_slice(extra);
        let second = part("other.film", 2, &args);
        let e = merge(&first, &second, &merged).expect_err(&format!("{extra:?} merged"));
        assert!(e.contains("differ") && e.contains(field), "{extra:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
    // Each file the scene reads, edited between the parts (and restored after).
    for file in ["s.pbrt", "light.pbrt", "lamp.spd", "tri.obj", "tex.png"] {
        let path = d.join(file);
        let original = std::fs::read(&path).unwrap();
        let edited = match file {
            "tex.png" => {
                let tex = prism::image::Image { width: 2, height: 2, channels: 3, data: vec![0.7; 12] };
                prism::image::write(&path, &tex).unwrap();
                std::fs::read(&path).unwrap()
            }
            "lamp.spd" => b"400 20\n700 20\n".to_vec(),
            _ => [&original[..], b"\n# edited\n"].concat(),
        };
        assert_ne!(edited, original);
        std::fs::write(&path, &edited).unwrap();
        let second = part("other.film", 2, &[]);
        std::fs::write(&path, &original).unwrap();
        let e = merge(&first, &second, &merged).expect_err(&format!("{file} edited, merged"));
        assert!(e.contains(&format!("different scenes or settings: input {file} (")), "{file}: {e}");
    }
    // A different time limit or thread count is the same render.
    merge(&first, &part("same.film", 2, &["--threads", "1", "--time-limit", "1h"]), &merged).unwrap();
}

#[test]
fn resume_refuses_a_checkpoint_of_another_render() {
    let d = tmpdir("resume-fingerprint");
    let scene = write_scene(&d);
    let out = d.join("r.exr");
    let args = ["render", scene.to_str().unwrap(), "--spp", "4", "--resolution", "8x8", "--accel", "obvhs"];
    // A checkpoint is a film file beside the output.
    let ckpt = PathBuf::from(format!("{}.ckpt", out.display()));
    let film = d.join("whole.film");
    ok(&[&args[..], &["-o", film.to_str().unwrap()]].concat());
    let written = std::fs::read(&film).unwrap();
    for (extra, field) in [(&["--sss", "randomwalk"][..], "integrator"), (&["--seed", "5"][..], "seed")] {
        std::fs::write(&ckpt, &written).unwrap();
        let o = prism().args(args).args(extra).args(["--resume", "-o", out.to_str().unwrap()]).output().unwrap();
        let e = stderr(&o);
        assert!(!o.status.success(), "{extra:?} resumed: {e}");
        assert!(e.contains("written by a different scene or settings") && e.contains(field), "{e}");
        assert!(!out.exists());
    }
    // The control: the same render resumes (and has nothing left to do).
    std::fs::write(&ckpt, &written).unwrap();
    ok(&[&args[..], &["--resume", "-o", out.to_str().unwrap()]].concat());
    assert!(out.exists());
}

/// The header of an EXR file: (data window x, y, width, height), (display width, height).
fn exr_windows(path: &Path) -> ((i32, i32, usize, usize), (usize, usize)) {
    let meta = exr::meta::MetaData::read_from_file(path, false).unwrap();
    let h = &meta.headers[0];
    let (data, display) = (h.data_window(), h.shared_attributes.display_window);
    ((data.position.x(), data.position.y(), data.size.x(), data.size.y()), (display.size.x(), display.size.y()))
}

#[test]
fn merge_writes_the_crop_window_and_colour_space_of_the_render() {
    let d = tmpdir("merge-crop");
    let common = [
        "render",
        "--spp",
        "4",
        "--resolution",
        "40x30",
        "--accel",
        "obvhs",
        "--cropwindow",
        "0.25,0.6,0.1,0.5",
        "--color-space",
        "rec2020",
    ];
    let direct = d.join("direct.exr");
    ok(&[&common[..], &["-o", direct.to_str().unwrap()]].concat());
    let parts: Vec<PathBuf> = (1..=2).map(|i| d.join(format!("p{i}.film"))).collect();
    for (i, p) in parts.iter().enumerate() {
        ok(&[&common[..], &["--part", &format!("{}/2", i + 1), "-o", p.to_str().unwrap()]].concat());
    }
    let merged = d.join("merged.exr");
    merge(&parts[0], &parts[1], &merged).unwrap();
    // pbrt-v4's rounding: x ∈ [⌈40·0.25⌉, ⌈40·0.6⌉) = [10, 24), y ∈ [⌈30·0.1⌉, ⌈30·0.5⌉) = [3, 15).
    assert_eq!(exr_windows(&direct), ((10, 3, 14, 12), (40, 30)));
    assert_eq!(exr_windows(&merged), exr_windows(&direct));
    let (a, b) = (prism::image::read(&direct).unwrap(), prism::image::read(&merged).unwrap());
    assert_eq!((a.width, a.height), (b.width, b.height));
    assert!(a.data.iter().any(|&v| v > 0.01), "black image");
    // The same samples summed in another grouping, both stored as half floats (11-bit
    // significands): equal to within one half-float step.
    for (x, y) in a.data.iter().zip(&b.data) {
        assert!((x - y).abs() <= 1e-3 * x.abs().max(1e-2), "{x} vs {y}");
    }
    // Told another colour space, merge writes that one: the render's own in that space.
    let srgb = d.join("srgb.exr");
    let o = prism().arg("merge").args(&parts).args(["--color-space", "srgb", "-o", srgb.to_str().unwrap()]).output();
    assert!(o.unwrap().status.success());
    let direct_srgb = d.join("direct-srgb.exr");
    let mut srgb_args = common.to_vec();
    *srgb_args.last_mut().unwrap() = "srgb";
    ok(&[&srgb_args[..], &["-o", direct_srgb.to_str().unwrap()]].concat());
    let (c, e) = (prism::image::read(&srgb).unwrap(), prism::image::read(&direct_srgb).unwrap());
    // The largest difference relative to the value (values below 0.01 count as 0.01).
    let max_rel = |p: &prism::image::Image, q: &prism::image::Image| {
        p.data.iter().zip(&q.data).map(|(x, y)| (x - y).abs() / x.abs().max(1e-2)).fold(0.0f32, f32::max)
    };
    assert!(max_rel(&c, &e) <= 1e-3, "merged sRGB vs rendered sRGB: {}", max_rel(&c, &e));
    assert!(max_rel(&a, &c) > 2e-2, "the rec2020 and sRGB images agree: {}", max_rel(&a, &c));
}

/// The sample type of each channel of an OpenEXR file.
fn exr_sample_types(path: &Path) -> Vec<exr::meta::attribute::SampleType> {
    let meta = exr::meta::MetaData::read_from_file(path, false).unwrap();
    meta.headers[0].channels.list.iter().map(|c| c.sample_type).collect()
}

#[test]
fn merge_keeps_the_scene_s_float_exr_output() {
    use exr::meta::attribute::SampleType;
    let d = tmpdir("merge-fp32");
    let scene = d.join("fp32.pbrt");
    std::fs::write(
        &scene,
        "Film \"rgb\" \"bool savefp16\" [ false ]\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n\
         WorldBegin\nLightSource \"point\" \"point3 from\" [0 3 3]\nShape \"sphere\"\n",
    )
    .unwrap();
    let common = ["render", scene.to_str().unwrap(), "--spp", "2", "--resolution", "12x8", "--accel", "obvhs"];
    let direct = d.join("direct.exr");
    ok(&[&common[..], &["-o", direct.to_str().unwrap()]].concat());
    let parts: Vec<PathBuf> = (1..=2).map(|i| d.join(format!("p{i}.film"))).collect();
    for (i, p) in parts.iter().enumerate() {
        ok(&[&common[..], &["--part", &format!("{}/2", i + 1), "-o", p.to_str().unwrap()]].concat());
    }
    let merged = d.join("merged.exr");
    merge(&parts[0], &parts[1], &merged).unwrap();
    assert_eq!(exr_sample_types(&direct), vec![SampleType::F32; 3]);
    assert_eq!(exr_sample_types(&merged), exr_sample_types(&direct));
}
