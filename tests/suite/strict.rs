//! Strict mode: every feature prism does not render is a warning, and under `--strict` an error
//! at the directive that asked for it, wherever the warning arises (the parser, shape loading,
//! the scene builder's films, filters, spectra, textures, materials and lights).

use crate::common::{prism, stderr, tmpdir};
use prism::pbrt::error::WarningKind;
use prism::pbrt::load_file;
use prism::pbrt::{ParseOptions, SceneError};
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scene with a camera, a light and a sphere, plus `options` before WorldBegin and `world` after.
fn scene_text(options: &str, world: &str) -> String {
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n{options}\nWorldBegin\n\
         LightSource \"point\" \"rgb I\" [10 10 10] \"point3 from\" [0 3 3]\nShape \"sphere\"\n{world}\n"
    )
}

/// `file:line:col` of the first occurrence of `needle` in `text`.
fn location_of(file: &Path, text: &str, needle: &str) -> String {
    let (i, line) = text.lines().enumerate().find(|(_, l)| l.contains(needle)).expect("needle in the scene");
    let col = line[..line.find(needle).unwrap()].chars().count() + 1;
    format!("{}:{}:{col}", file.display(), i + 1)
}

/// A Ptex texture: prism renders the material's other parameters without it.
const PTEX: &str = "Texture \"t\" \"spectrum\" \"ptex\" \"string filename\" \"t.ptx\"\n\
                    Material \"diffuse\" \"texture reflectance\" \"t\"\nShape \"sphere\"";

#[test]
fn every_unsupported_feature_warns_and_is_an_error_in_strict_mode() {
    let d = tmpdir("strict");
    let ply = repo().join("scenes/meshes/icosphere.ply");
    // (where it goes, the directive, the text at the location the error names, the feature).
    let cases: Vec<(bool, String, &str, &str)> = vec![
        (
            false,
            format!(
                "Texture \"d\" \"float\" \"constant\" \"float value\" 0.1\n\
                 Shape \"plymesh\" \"string filename\" \"{}\" \"texture displacement\" \"d\"",
                ply.display()
            ),
            "Shape \"plymesh\"",
            "displacement mapping",
        ),
        (
            false,
            "AttributeBegin\nActiveTransform EndTime\nTranslate 0 0 1\nActiveTransform All\nLightSource \"distant\"\nAttributeEnd"
                .into(),
            "LightSource \"distant\"",
            "a moving light",
        ),
        (false, PTEX.into(), "Texture \"t\"", "ptex textures"),
    ];
    let strict = ParseOptions { strict: true, ..Default::default() };
    for (i, (in_options, directive, at, feature)) in cases.iter().enumerate() {
        let text = if *in_options { scene_text(directive, "") } else { scene_text("", directive) };
        let path = d.join(format!("case{i}.pbrt"));
        std::fs::write(&path, &text).unwrap();
        let loaded = load_file(&path, &Default::default()).unwrap_or_else(|e| panic!("{feature}: {e}"));
        let unsupported: Vec<_> =
            loaded.warnings.iter().filter(|w| matches!(w.kind, WarningKind::Unsupported { .. })).collect();
        assert_eq!(unsupported.len(), 1, "{feature}: {:?}", loaded.warnings);
        let loc = location_of(&path, &text, at);
        let w = unsupported[0].to_string();
        assert!(w.starts_with(&format!("{loc}: warning: unsupported feature: {feature}")), "{w}");
        let e = load_file(&path, &strict).err().unwrap_or_else(|| panic!("{feature}: strict mode loaded the scene"));
        assert!(matches!(e, SceneError::Unsupported { .. }), "{feature}: {e}");
        let e = e.to_string();
        assert!(e.starts_with(&format!("{loc}: unsupported feature: {feature}")), "{e}");
        assert!(e.contains("(strict mode; without --strict prism "), "{e}");
    }
    // What is only worth knowing stays a warning in strict mode.
    let notes = scene_text("", "TransformBegin\nTransformEnd\nShape \"sphere\" \"float radius\" 2");
    let path = d.join("notes.pbrt");
    std::fs::write(&path, notes).unwrap();
    let loaded = load_file(&path, &strict).unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings.iter().all(|w| w.kind == WarningKind::Note));
}

/// pbrt-v4 stops on a parameter nothing reads (a misspelling) and on several values given for
/// one: a warning by default, an error at the parameter in strict mode.
#[test]
fn unused_parameters_and_extra_values_are_errors_in_strict_mode() {
    let d = tmpdir("strict-unused");
    let strict = ParseOptions { strict: true, ..Default::default() };
    for (i, (shape, at, message)) in [
        (
            "Shape \"sphere\" \"float radisu\" 2",
            "\"float radisu\"",
            "parameter \"float radisu\" of Shape \"sphere\" was not used",
        ),
        ("Shape \"sphere\" \"float radius\" [1 2]", "\"float radius\"", "takes one value, but 2 were given"),
    ]
    .into_iter()
    .enumerate()
    {
        let text = scene_text("", shape);
        let path = d.join(format!("unused{i}.pbrt"));
        std::fs::write(&path, &text).unwrap();
        let loaded = load_file(&path, &Default::default()).unwrap();
        assert!(loaded.warnings.iter().any(|w| w.kind == WarningKind::Refused && w.message.contains(message)));
        let e = load_file(&path, &strict).err().unwrap_or_else(|| panic!("strict mode loaded {shape}"));
        assert!(matches!(e, SceneError::Refused { .. }), "{e}");
        let loc = location_of(&path, &text, at);
        let e = e.to_string();
        assert!(e.starts_with(&format!("{loc}: ")) && e.contains(message), "{e}");
    }
}

/// Without `--strict` a warning repeated at many places is one line, at the first place, saying
/// how many more there are.
#[test]
fn a_repeated_warning_is_one_line() {
    let d = tmpdir("strict-repeated");
    let typo = "Shape \"sphere\" \"float radisu\" 2\n";
    let text = scene_text("", &typo.repeat(3));
    let scene = d.join("typos.pbrt");
    std::fs::write(&scene, &text).unwrap();
    let out = d.join("x.png");
    let o = prism()
        .args(["render", scene.to_str().unwrap(), "--spp", "1", "--resolution", "8x8", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    let loc = location_of(&scene, &text, "\"float radisu\"");
    let warnings: Vec<&str> = e.lines().filter(|l| l.starts_with("prism: warning: ")).collect();
    assert_eq!(
        warnings,
        [format!(
            "prism: warning: {loc}: parameter \"float radisu\" of Shape \"sphere\" was not used (2 more like it)"
        )]
    );
}

/// `--strict` exits non-zero with one line naming the file, line and column.
fn assert_strict_refuses(scene: &Path, out: &Path, feature: &str) {
    let o = prism()
        .args(["render", scene.to_str().unwrap(), "--strict", "--spp", "1", "--resolution", "8x8", "-o"])
        .arg(out)
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(!o.status.success(), "--strict rendered {}: {e}", scene.display());
    assert_eq!(e.lines().count(), 1, "{e}");
    let prefix = format!("prism: error: {}:", scene.display());
    assert!(e.starts_with(&prefix) && e.contains(&format!(": unsupported feature: {feature}")), "{e}");
    assert!(!out.exists(), "no image may be written");
}

#[test]
fn render_strict_refuses_ptex_and_renders_without_it() {
    let d = tmpdir("strict-cli");
    let scene = d.join("ptex.pbrt");
    std::fs::write(&scene, scene_text("", PTEX)).unwrap();
    let out = d.join("x.png");
    assert_strict_refuses(&scene, &out, "ptex textures");
    let o =
        prism().args(["render", scene.to_str().unwrap(), "--spp", "1", "--resolution", "8x8", "-o"]).arg(&out).output();
    let o = o.unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    let prefix = format!("prism: warning: {}:", scene.display());
    assert!(e.lines().any(|l| l.starts_with(&prefix) && l.contains(": unsupported feature: ptex textures")), "{e}");
}

/// pbrt-v4's own killeroo scene (`loopsubdiv` surfaces), where it is available beside the
/// repository: nothing in it is unsupported.
#[test]
fn render_strict_accepts_pbrt_v4s_killeroo_scene() {
    let scene = repo().join("../shared/scenes/pbrt-v4-scenes/killeroos/killeroo-simple.pbrt");
    if !scene.exists() {
        eprintln!("skipped: {} is not available", scene.display());
        return;
    }
    let d = tmpdir("strict-killeroo");
    let out = d.join("k.png");
    let o = prism()
        .args(["render", scene.to_str().unwrap(), "--strict", "--spp", "1", "--resolution", "8x8", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let e = stderr(&o);
    // No warning: its "halton" sampler is rendered as pbrt-v4's Halton sampler.
    let warnings: Vec<&str> = e.lines().filter(|l| l.starts_with("prism: warning: ")).collect();
    assert!(o.status.success() && warnings.is_empty(), "{e}");
    assert!(out.exists());
}

#[test]
fn named_spectra_resolve_and_unknown_names_are_errors() {
    let d = tmpdir("named-spectra");
    // pbrt-v4's brass (its last named spectrum prism lacked): its own data, no warning.
    let text =
        scene_text("", "Material \"conductor\" \"spectrum k\" \"metal-CuZn-k\"\nShape \"sphere\" \"float radius\" 0.5");
    let path = d.join("cuzn.pbrt");
    std::fs::write(&path, &text).unwrap();
    let loaded = load_file(&path, &Default::default()).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    // A name neither pbrt-v4 nor prism knows, and no file of that name: an error at the
    // parameter naming the valid names.
    let text = scene_text("", "LightSource \"point\" \"float scale\" 1\n  \"spectrum I\" \"stdillum-D66\"");
    let path = d.join("d66.pbrt");
    std::fs::write(&path, &text).unwrap();
    let e = load_file(&path, &Default::default()).err().expect("an error").to_string();
    let loc = location_of(&path, &text, "\"spectrum I\"");
    assert!(e.starts_with(&format!("{loc}: ")) && e.contains("stdillum-D66") && e.contains("stdillum-D65"), "{e}");
}

#[test]
fn a_camera_sensor_loads_without_warning_and_an_unknown_one_is_an_error_at_the_parameter() {
    let d = tmpdir("sensor-names");
    let text = scene_text("Film \"rgb\" \"string sensor\" \"nikon_d850\"", "");
    let path = d.join("d850.pbrt");
    std::fs::write(&path, &text).unwrap();
    let loaded = load_file(&path, &ParseOptions { strict: true, ..Default::default() }).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let text = scene_text("Film \"rgb\" \"string sensor\" \"nikon_d1\"", "");
    let path = d.join("d1.pbrt");
    std::fs::write(&path, &text).unwrap();
    let e = load_file(&path, &Default::default()).err().expect("an error").to_string();
    let loc = location_of(&path, &text, "\"string sensor\"");
    assert!(e.starts_with(&format!("{loc}: ")) && e.contains("nikon_d1") && e.contains("canon_eos_5d"), "{e}");
}
