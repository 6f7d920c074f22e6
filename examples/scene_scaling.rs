//! Writes pbrt-v4 scenes with N named elements of one kind and times how prism reads them, stage
//! by stage, so that a cost that grows faster than the scene shows as a rising time per element:
//!
//!     cargo run --release --example scene_scaling -- DIR [KIND[,KIND...]] [N[,N...]]
//!
//! KIND is one of
//! - `materials`: N `Texture`s, N `MakeNamedMaterial`s each reading one, and N one-triangle
//!   shapes each under its own `NamedMaterial` (so every material and texture is built);
//! - `media`: N `MakeNamedMedium`s and N one-triangle shapes each inside its own medium;
//! - `objects`: N `ObjectBegin` blocks of one triangle each and N `ObjectInstance`s;
//! - `shapes`: N one-triangle shapes, each in its own `AttributeBegin` with a `Translate`
//!   (the cost every other kind carries as well).
//!
//! (default: all four at N = 1000, 10000, 100000). The stages: `parse` (`parse_file`),
//! `translate` (the description onto a scene builder), `report` (unused parameters and the
//! list of input files), `build` (accelerator and lights, Embree when built with it).
//! Each line gives the seconds of each stage and their sum per element in microseconds.

use prism::accel::AccelKind;
use prism::pbrt::{build_with, parse_file, ParseOptions};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

const KINDS: [&str; 4] = ["materials", "media", "objects", "shapes"];

/// Camera, film and one light: what every generated scene starts with.
const HEADER: &str = r#"LookAt 0 0 -10  0 0 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "scaling.exr"
WorldBegin
LightSource "distant" "point3 from" [ 0 0 -1 ] "point3 to" [ 0 0 0 ]
"#;

/// One triangle of side ~1 at the origin.
const TRIANGLE: &str = r#"Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  0 1 0 ] "integer indices" [ 0 1 2 ]"#;

/// The scene text of `kind` with `n` elements.
fn scene(kind: &str, n: usize) -> String {
    let mut s = String::from(HEADER);
    // Shapes spread over a square so the BVH has real work.
    let side = (n as f64).sqrt().ceil() as usize;
    let place = |i: usize| format!("Translate {} {} 0", (i % side) as f32 * 1.5, (i / side) as f32 * 1.5);
    match kind {
        "materials" => {
            for i in 0..n {
                let g = (i % 97) as f32 / 97.0;
                writeln!(s, r#"Texture "tex{i}" "spectrum" "checkerboard" "rgb tex1" [ {g} 0.5 0.5 ] "rgb tex2" [ 0.1 0.1 {g} ]"#).unwrap();
                writeln!(s, r#"MakeNamedMaterial "mat{i}" "string type" "diffuse" "texture reflectance" "tex{i}""#)
                    .unwrap();
            }
            for i in 0..n {
                writeln!(s, "AttributeBegin\n  {}\n  NamedMaterial \"mat{i}\"\n  {TRIANGLE}\nAttributeEnd", place(i))
                    .unwrap();
            }
        }
        "media" => {
            for i in 0..n {
                let d = 0.1 + (i % 89) as f32 / 89.0;
                writeln!(s, r#"MakeNamedMedium "med{i}" "string type" "homogeneous" "rgb sigma_a" [ {d} {d} {d} ] "rgb sigma_s" [ 0.5 0.5 0.5 ]"#).unwrap();
            }
            for i in 0..n {
                writeln!(
                    s,
                    "AttributeBegin\n  {}\n  MediumInterface \"med{i}\" \"\"\n  {TRIANGLE}\nAttributeEnd",
                    place(i)
                )
                .unwrap();
            }
        }
        "objects" => {
            for i in 0..n {
                writeln!(s, "ObjectBegin \"obj{i}\"\n  {TRIANGLE}\nObjectEnd").unwrap();
            }
            for i in 0..n {
                writeln!(s, "AttributeBegin\n  {}\n  ObjectInstance \"obj{i}\"\nAttributeEnd", place(i)).unwrap();
            }
        }
        "shapes" => {
            for i in 0..n {
                writeln!(s, "AttributeBegin\n  {}\n  {TRIANGLE}\nAttributeEnd", place(i)).unwrap();
            }
        }
        _ => unreachable!("kinds are checked"),
    }
    s
}

/// Seconds of each stage of reading the scene file at `path`.
fn time_stages(path: &Path) -> Result<[f64; 4], String> {
    let opts = ParseOptions::default();
    let t = Instant::now();
    let (desc, mut warnings) = parse_file(path, &opts).map_err(|e| e.to_string())?;
    let parse = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let (builder, _) = build_with(&desc, &mut warnings, opts.quadrics).map_err(|e| e.to_string())?;
    let translate = t.elapsed().as_secs_f64();
    let t = Instant::now();
    warnings.extend(desc.report_unused());
    let inputs = desc.input_files();
    let report = t.elapsed().as_secs_f64();
    if let Some(w) = warnings.first() {
        return Err(format!("{} warnings, the first: {w}", warnings.len()));
    }
    let t = Instant::now();
    let scene = builder.build(AccelKind::default_available()).map_err(|e| e.to_string())?;
    let build = t.elapsed().as_secs_f64();
    drop((scene, desc, inputs));
    Ok([parse, translate, report, build])
}

fn list<T: std::str::FromStr>(arg: Option<String>, default: &[T]) -> Result<Vec<T>, String>
where
    T: Clone,
{
    match arg {
        None => Ok(default.to_vec()),
        Some(a) => a.split(',').map(|x| x.trim().parse().map_err(|_| format!("cannot read '{x}'"))).collect(),
    }
}

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().ok_or("usage: scene_scaling DIR [KIND,...] [N,...]")?);
    let kinds: Vec<String> = list(args.next(), &KINDS.map(String::from))?;
    let ns: Vec<usize> = list(args.next(), &[1000, 10_000, 100_000])?;
    if let Some(k) = kinds.iter().find(|k| !KINDS.contains(&k.as_str())) {
        return Err(format!("unknown kind '{k}' (valid: {})", KINDS.join(", ")));
    }
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    println!("| kind | N | file MB | parse [s] | translate [s] | report [s] | build [s] | µs per element |");
    println!("|---|---|---|---|---|---|---|---|");
    for kind in &kinds {
        for &n in &ns {
            let path = dir.join(format!("{kind}-{n}.pbrt"));
            let text = scene(kind, n);
            std::fs::write(&path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
            let s = time_stages(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let total: f64 = s.iter().sum();
            println!(
                "| {kind} | {n} | {:.1} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} |",
                text.len() as f64 / 1e6,
                s[0],
                s[1],
                s[2],
                s[3],
                total / n as f64 * 1e6
            );
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("scene_scaling: {e}");
            ExitCode::FAILURE
        }
    }
}
