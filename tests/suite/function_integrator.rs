//! pbrt-v4's `function` integrator from the command line: the text file of "n mse" lines (its
//! name from the file's "filename", `-o`, or the function's), `skipbad`, the image of the
//! function, and the errors for what it cannot run.

use crate::common::{prism, stderr, tmpdir};
use std::path::Path;

/// A scene of `integrator` and `sampler` directives on a 16 × 8 film, written to `dir`.
fn scene(dir: &Path, integrator: &str, sampler: &str) -> std::path::PathBuf {
    let file = dir.join("function.pbrt");
    let text = format!(
        "{integrator}\n{sampler}\nFilm \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 8\n\
         Camera \"perspective\"\nWorldBegin\n"
    );
    std::fs::write(&file, text).unwrap();
    file
}

/// The (n, MSE) pairs of a text file, checking each line is "n mse".
fn lines(path: &Path) -> Vec<(u64, f64)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .map(|l| match l.split(' ').collect::<Vec<_>>()[..] {
            [n, mse] => (n.parse().unwrap(), mse.parse().unwrap()),
            _ => panic!("line {l:?} is not \"n mse\""),
        })
        .collect()
}

#[test]
fn the_default_file_holds_the_natural_counts_and_the_image_shows_the_function() {
    let dir = tmpdir("function-default");
    let integrator = "Integrator \"function\" \"string function\" \"step\" \"string imagefilename\" \"step.exr\"";
    let file = scene(&dir, integrator, "Sampler \"stratified\" \"integer xsamples\" 4 \"integer ysamples\" 4");
    let o = prism().current_dir(&dir).arg("render").arg(&file).arg("--strict").output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    // Squares only. One sample: f − 1 = ±1, MSE 1. A 2 × 2 or 4 × 4 grid splits the square at
    // x = ½: exact. A 3 × 3 grid does not, but errs less than independent samples (1/9).
    let curve = lines(&dir.join("step-mse.txt"));
    assert_eq!(curve.iter().map(|p| p.0).collect::<Vec<_>>(), [1, 4, 9, 16]);
    assert_eq!((curve[0].1, curve[1].1, curve[3].1), (1.0, 0.0, 0.0));
    assert!(curve[2].1 > 0.0 && curve[2].1 < 1.0 / 9.0, "{curve:?}");
    // The step over the film: 2 on the left half, 0 on the right.
    let image = prism::image::read(&dir.join("step.exr")).unwrap();
    assert_eq!((image.width, image.height), (16, 8));
    for y in 0..8 {
        for x in 0..16 {
            let want = if x < 8 { 2.0 } else { 0.0 };
            assert_eq!(image.pixel(x, y).unwrap()[0], want, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn filename_and_output_name_the_file_and_without_skipbad_every_count_is_reported() {
    let dir = tmpdir("function-names");
    let integrator =
        "Integrator \"function\" \"string function\" \"disk\" \"string filename\" \"curve.txt\" \"bool skipbad\" false";
    let file = scene(&dir, integrator, "Sampler \"paddedsobol\" \"integer pixelsamples\" 4");
    let o = prism().current_dir(&dir).arg("render").arg(&file).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let curve = lines(&dir.join("curve.txt"));
    assert_eq!(curve.iter().map(|p| p.0).collect::<Vec<_>>(), [1, 2, 3, 4]);
    // The disk is a = 4/π with probability p = π/4, else 0: one sample errs by d = a − 1 or −1,
    // E d² = Var f = a − 1, and the mean of d² over 128 pixels has relative standard error
    // √((κ − 1)/128) = 12 %, κ = E d⁴/(E d²)² = 2.93. 4σ allowed.
    let var = 4.0 / std::f64::consts::PI - 1.0;
    assert!((curve[0].1 / var - 1.0).abs() < 0.49, "{curve:?}");
    // -o names the text file instead (pbrt-v4's --outfile).
    let o =
        prism().current_dir(&dir).arg("render").arg(&file).args(["-o", "other.txt", "--spp", "2"]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(lines(&dir.join("other.txt")).len(), 2);
    assert_eq!(lines(&dir.join("curve.txt")).len(), 4, "the file's name was written again");
}

#[test]
fn an_unknown_function_the_global_sobol_sampler_and_image_options_are_errors() {
    let dir = tmpdir("function-errors");
    let run = |integrator: &str, sampler: &str, extra: &[&str]| {
        let file = scene(&dir, integrator, sampler);
        let o = prism().current_dir(&dir).arg("render").arg(&file).args(extra).output().unwrap();
        assert!(!o.status.success(), "{integrator} {sampler} {extra:?} succeeded");
        stderr(&o)
    };
    let independent = "Sampler \"independent\" \"integer pixelsamples\" 4";
    let e = run("Integrator \"function\" \"string function\" \"ramp\"", independent, &[]);
    assert!(e.contains("function.pbrt:1") && e.contains("unknown \"function\" \"ramp\""), "{e}");
    let e = run("Integrator \"function\"", "Sampler \"sobol\"", &[]);
    assert!(e.contains("\"paddedsobol\""), "{e}");
    let e = run("Integrator \"function\"", independent, &["--aov"]);
    assert!(e.contains("--aov is not available with integrator \"function\""), "{e}");
    let written: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(written, ["function.pbrt"], "an error wrote a file");
}
