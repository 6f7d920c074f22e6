//! `sppm` (stochastic progressive photon mapping): a closed emitting box against its closed
//! form (a wrong photon normalisation is far outside the tolerance), a closed box lit by a
//! small light against `path`, bit-identical images for any thread count, and the options it
//! refuses.

use crate::common::{film, film_difference, prism, stderr, tmpdir};
use prism::film::Film;
use std::path::Path;

/// Renders `text` (its `INTEGRATOR` replaced by `integrator`) to a .film with `args`.
fn render(dir: &Path, name: &str, text: &str, integrator: &str, args: &[&str]) -> Film {
    let file = dir.join(format!("{name}.pbrt"));
    std::fs::write(&file, text.replace("INTEGRATOR", integrator)).unwrap();
    let out = dir.join(format!("{name}.film"));
    let o = prism().arg("render").arg(&file).args(["--strict", "-o"]).arg(&out).args(args).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    film(&out)
}

/// Mean of the pixels' Y.
fn mean_y(f: &Film) -> f64 {
    f.pixels.iter().map(|p| p.xyz_sum.y / p.weight_sum).sum::<f64>() / f.pixels.len() as f64
}

/// The six walls of the unit cube, every one emitting L = 1 (Y = 1) from both sides and
/// reflecting diffusely with albedo ρ; the camera at the centre sees the middle of one wall
/// (no edge within the gathering radius of what it sees). The default (Gaussian) filter, whose
/// weights average ∫f ≠ 1.
const FURNACE: &str = "LookAt 0.5 0.5 0.5  0.5 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
    Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
    Sampler \"independent\" \"integer pixelsamples\" 64\nINTEGRATOR\nWorldBegin\n\
    AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n\
    Material \"diffuse\" \"rgb reflectance\" [RHO RHO RHO]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0] \"integer indices\" [0 2 1 0 3 2]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 1  1 0 1  1 1 1  0 1 1] \"integer indices\" [0 1 2 0 2 3]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 0  0 0 1  0 1 1  0 1 0] \"integer indices\" [0 1 2 0 2 3]\n\
    Shape \"trianglemesh\" \"point3 P\" [1 0 0  1 0 1  1 1 1  1 1 0] \"integer indices\" [0 2 1 0 3 2]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 0 1  0 0 1] \"integer indices\" [0 1 2 0 2 3]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 1 0  1 1 0  1 1 1  0 1 1] \"integer indices\" [0 2 1 0 3 2]\n";

#[test]
fn a_closed_emitting_box_has_radiance_le_over_one_minus_albedo() {
    // Every wall emits L_e and reflects ρ of what arrives, so L = L_e / (1 − ρ) everywhere: Y =
    // 2 for ρ = ½. Of it the camera path gathers L_e + ρ L_e (emission, direct light) and the
    // photons the remaining ρ²/(1 − ρ) L_e = ½: a photon count off by 2 is off by ¼ or ½, a
    // missing π by a factor 3; radiance is uniform, so the radius adds no bias. The image mean
    // over six seeds had a standard deviation of 0.0055 (16×16, 64 iterations of 20 000
    // photons, radius 0.05): the tolerance is 4σ ≈ 0.022 (1.1 %).
    let dir = tmpdir("sppm-furnace");
    let sppm =
        "Integrator \"sppm\" \"integer maxdepth\" -1 \"float radius\" 0.05 \"integer photonsperiteration\" 20000";
    let y = mean_y(&render(&dir, "furnace", &FURNACE.replace("RHO", "0.5"), sppm, &[]));
    assert!((y - 2.0).abs() < 0.022, "Y = {y}, want 2");
    // Without reflection only the emission is seen: Y = 1 exactly but for wavelength noise.
    let y = mean_y(&render(&dir, "black", &FURNACE.replace("RHO", "0"), sppm, &[]));
    assert!((y - 1.0).abs() < 0.01, "Y = {y}, want 1");
}

/// A closed diffuse box (1 × 1 × 1.5, coloured side walls, a grey panel) lit by a small
/// downward-facing light under the ceiling: the camera sees direct and indirect light.
const BOX: &str = "LookAt 0.5 0.5 1.4  0.5 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n\
    Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
    Sampler \"independent\" \"integer pixelsamples\" SPP\nPixelFilter \"box\"\nINTEGRATOR\nWorldBegin\n\
    AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [8 8 8]\n\
    Shape \"trianglemesh\" \"point3 P\" [0.4 0.99 0.4  0.6 0.99 0.4  0.6 0.99 0.6  0.4 0.99 0.6] \"integer indices\" [0 1 2 0 2 3]\n\
    AttributeEnd\nMaterial \"diffuse\" \"rgb reflectance\" [0.7 0.7 0.7]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0] \"integer indices\" [0 2 1 0 3 2]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 0 1.5  0 0 1.5] \"integer indices\" [0 1 2 0 2 3]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 1 0  1 1 0  1 1 1.5  0 1 1.5] \"integer indices\" [0 2 1 0 3 2]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 1.5  1 0 1.5  1 1 1.5  0 1 1.5] \"integer indices\" [0 1 2 0 2 3]\n\
    Material \"diffuse\" \"rgb reflectance\" [0.7 0.2 0.2]\n\
    Shape \"trianglemesh\" \"point3 P\" [0 0 0  0 0 1.5  0 1 1.5  0 1 0] \"integer indices\" [0 1 2 0 2 3]\n\
    Material \"diffuse\" \"rgb reflectance\" [0.2 0.7 0.2]\n\
    Shape \"trianglemesh\" \"point3 P\" [1 0 0  1 0 1.5  1 1 1.5  1 1 0] \"integer indices\" [0 2 1 0 3 2]\n\
    Material \"diffuse\" \"rgb reflectance\" [0.6 0.6 0.6]\n\
    Shape \"trianglemesh\" \"point3 P\" [0.2 0 0.2  0.45 0 0.2  0.45 0.5 0.2  0.2 0.5 0.2] \"integer indices\" [0 1 2 0 2 3]\n";

#[test]
fn sppm_agrees_with_path_on_a_closed_diffuse_box() {
    // The image means agree within 4 standard errors of the per-pixel differences plus the
    // radius bias: photons gathered across an edge from the adjacent wall brighten the pixels
    // within r of it, and the blur moves light across shading gradients. At r = 0.03 (3 % of
    // the box) that bias measured 0.4 % of the mean (64 iterations at 24×24); 2 % bounds it.
    // About half of the image's light is indirect, which only the photons bring: a photon
    // normalisation off by 2 is off by 25 % or more.
    let dir = tmpdir("sppm-box");
    let path = render(&dir, "path", &BOX.replace("SPP", "512"), "Integrator \"path\" \"integer maxdepth\" 5", &[]);
    let sppm = "Integrator \"sppm\" \"integer maxdepth\" 5 \"float radius\" 0.03 \"integer photonsperiteration\" 20000";
    let sppm = render(&dir, "sppm", &BOX.replace("SPP", "48"), sppm, &[]);
    let (d, se, y) = film_difference(&sppm, &path);
    assert!(y > 0.05, "black image: {y}");
    assert!(d.abs() < 4.0 * se + 0.02 * y, "sppm − path = {d} ± {se} (sppm mean {y})");
}

#[test]
fn sppm_images_are_the_same_for_any_thread_count() {
    // 40 000 photons per iteration: ten chunks (whose deposits reach shared pixels), in groups
    // of 4 on one thread and of 8 on two.
    let dir = tmpdir("sppm-threads");
    let sppm = "Integrator \"sppm\" \"float radius\" 0.05 \"integer photonsperiteration\" 40000";
    let text = BOX.replace("SPP", "4");
    let one = render(&dir, "one", &text, sppm, &["--threads", "1"]);
    let two = render(&dir, "two", &text, sppm, &["--threads", "2"]);
    assert!(mean_y(&one) > 0.05);
    assert!(one.pixels.iter().zip(&two.pixels).all(|(a, b)| a.xyz_sum == b.xyz_sum), "images differ");
}

#[test]
fn sppm_refuses_what_its_state_cannot_do() {
    let dir = tmpdir("sppm-refusals");
    let file = dir.join("box.pbrt");
    std::fs::write(&file, BOX.replace("SPP", "2").replace("INTEGRATOR", "Integrator \"sppm\"")).unwrap();
    for (flag, out) in [
        (&["--part", "1/2"][..], "out.film"),
        (&["--checkpoint-every", "10s"], "out.exr"),
        (&["--target-error", "0.01"], "out.exr"),
        (&["--aov"], "out.exr"),
    ] {
        let o = prism().arg("render").arg(&file).args(flag).arg("-o").arg(dir.join(out)).output().unwrap();
        let e = stderr(&o);
        assert!(!o.status.success(), "{flag:?} accepted");
        assert!(e.contains(&format!("{} is not available with integrator \"sppm\"", flag[0])), "{flag:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

#[test]
fn sppm_ignores_media_with_a_warning_and_fails_under_strict() {
    let dir = tmpdir("sppm-media");
    let file = dir.join("fog.pbrt");
    let text = BOX.replace("SPP", "2").replace("INTEGRATOR", "Integrator \"sppm\" \"float radius\" 0.05").replace(
        "WorldBegin\n",
        "WorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMediumInterface \"\" \"fog\"\n",
    );
    std::fs::write(&file, text).unwrap();
    let run = |strict: bool| {
        let mut c = prism();
        c.arg("render").arg(&file).arg("-o").arg(dir.join("out.exr"));
        if strict {
            c.arg("--strict");
        }
        c.output().unwrap()
    };
    let o = run(false);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("integrator \"sppm\": it ignores participating media"), "{}", stderr(&o));
    let o = run(true);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("unsupported feature: integrator \"sppm\" for this scene: it ignores participating media"),
        "{e}"
    );
}
