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
//!   (the cost every other kind carries as well);
//! - `forest`: N `ObjectInstance`s of four tree prototypes (cones of 4,096 triangles each),
//!   each placed by its own `Translate`, `Rotate` and `Scale` on a square grid: object
//!   instancing at scale;
//! - `mesh`: one `plymesh` of N triangles, a binary little-endian PLY heightfield with
//!   positions only (19 bytes per triangle, like a scanned model). Its line adds the seconds of
//!   reading the file and of decoding the PLY alone (the first two parts of `parse`).
//! - `emissive-mesh`, `emissive-mesh-rgb`: the same PLY of N triangles as `mesh`, every triangle
//!   an area light (`AreaLightSource "diffuse"` with a 6500 K "blackbody L", or an "rgb L"), over
//!   a diffuse floor it lights: the cost of N lights sharing one spectrum. Their lines add the
//!   same parts as `mesh`'s, so `build` less the accelerator alone is the lights' share.
//!
//! (default: every kind at N = 1000, 10000, 100000). The stages: `parse` (`parse_file`),
//! `translate` (the description onto a scene builder), `report` (unused parameters and the
//! list of input files), `build` (accelerator and lights, Embree when built with it).
//! Each line gives the wall seconds of each stage, their sum per element in microseconds, and the
//! process CPU seconds (all threads) of each stage; a second line the resident memory after
//! each stage, in bytes per element (per triangle for `mesh`).

use cpu_time::ProcessTime;
use prism::accel::AccelKind;
use prism::bench::rss_bytes;
use prism::pbrt::mesh_io::ply;
use prism::pbrt::{build_moving_meshes, parse_file, ParseOptions};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Wall-clock and process CPU seconds since it was started: on a machine shared with other
/// work the CPU seconds (all threads) measure the work itself, the wall seconds what it took.
struct Clock(Instant, ProcessTime);

impl Clock {
    fn start() -> Self {
        Self(Instant::now(), ProcessTime::now())
    }
    fn stop(&self) -> [f64; 2] {
        [self.0.elapsed().as_secs_f64(), self.1.elapsed().as_secs_f64()]
    }
}

const KINDS: [&str; 8] =
    ["materials", "media", "objects", "shapes", "mesh", "forest", "emissive-mesh", "emissive-mesh-rgb"];

/// The kinds whose triangles are one PLY file, written beside the scene as `KIND-N.ply`.
const PLY_KINDS: [&str; 3] = ["mesh", "emissive-mesh", "emissive-mesh-rgb"];

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
        "forest" => {
            for k in 0..FOREST_PROTOTYPES {
                writeln!(s, "ObjectBegin \"tree{k}\"\n  {}\nObjectEnd", tree(k)).unwrap();
            }
            // A cheap hash of the index varies each tree's prototype, turn and size.
            for i in 0..n {
                let h = (i as u32).wrapping_mul(2_654_435_761);
                let (x, y) = ((i % side) as f32 * 1.5, (i / side) as f32 * 1.5);
                let (k, turn, size) =
                    (h as usize % FOREST_PROTOTYPES, (h >> 8) % 360, 0.7 + (h >> 20) as f32 / 4096.0 * 0.6);
                writeln!(
                    s,
                    "AttributeBegin\n  Translate {x} {y} 0\n  Rotate {turn} 0 0 1\n  Scale {size} {size} {size}\n  ObjectInstance \"tree{k}\"\nAttributeEnd"
                )
                .unwrap();
            }
        }
        "mesh" => {
            writeln!(s, "Shape \"plymesh\" \"string filename\" \"mesh-{n}.ply\"").unwrap();
        }
        "emissive-mesh" | "emissive-mesh-rgb" => {
            // The heightfield's triangles face +z, away from the camera, toward a floor 0.5 behind.
            let l = if kind == "emissive-mesh" { r#""blackbody L" [ 6500 ]"# } else { r#""rgb L" [ 1 0.6 0.3 ]"# };
            writeln!(
                s,
                "AttributeBegin\n  AreaLightSource \"diffuse\" {l}\n  Shape \"plymesh\" \"string filename\" \
                 \"{kind}-{n}.ply\"\nAttributeEnd\nMaterial \"diffuse\"\n\
                 Shape \"bilinearmesh\" \"point3 P\" [ -3 -3 0.5  3 -3 0.5  -3 3 0.5  3 3 0.5 ] \"integer indices\" [ 0 1 2 3 ]"
            )
            .unwrap();
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

/// Distinct prototypes of the `forest` scenes.
const FOREST_PROTOTYPES: usize = 4;

/// Tree prototype `k` as a `trianglemesh`: a (nearly closed) cone of 64 segments around and 32 rings up
/// (4,096 triangles), 0.5 wide and 1.5 + 0.25 k high, its axis +z, its base at the origin.
fn tree(k: usize) -> String {
    let (around, rings) = (64usize, 32usize);
    let height = 1.5 + 0.25 * k as f32;
    let mut p = String::new();
    for j in 0..=rings {
        let f = j as f32 / rings as f32;
        let r = 0.5 * (1.0 - 0.97 * f);
        for i in 0..around {
            let a = i as f32 / around as f32 * std::f32::consts::TAU;
            write!(p, "{} {} {} ", r * a.cos(), r * a.sin(), height * f).unwrap();
        }
    }
    let mut idx = String::new();
    for j in 0..rings {
        for i in 0..around {
            let v = |i: usize, j: usize| j * around + i % around;
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            write!(idx, "{a} {b} {c} {a} {c} {d} ").unwrap();
        }
    }
    format!(r#"Shape "trianglemesh" "point3 P" [ {p}] "integer indices" [ {idx}]"#)
}

/// Wall and CPU seconds of each stage of reading the scene file at `path` (parse, translate,
/// report, build), and the resident memory above the start after each stage (and at the peak)
/// [bytes].
fn time_stages(path: &Path) -> Result<([[f64; 2]; 4], [i64; 5]), String> {
    let opts = ParseOptions::default();
    let rss0 = rss_bytes().0 as i64;
    prism::bench::reset_peak_rss();
    let rss = || rss_bytes().0 as i64 - rss0;
    let t = Clock::start();
    let (mut desc, mut warnings) = parse_file(path, &opts).map_err(|e| e.to_string())?;
    let parse = t.stop();
    let m_parse = rss();
    let t = Clock::start();
    let (builder, _) = build_moving_meshes(&mut desc, &mut warnings, opts.quadrics).map_err(|e| e.to_string())?;
    let translate = t.stop();
    let m_translate = rss();
    let t = Clock::start();
    warnings.extend(desc.report_unused());
    let inputs = desc.input_files();
    let report = t.stop();
    if let Some(w) = warnings.first() {
        return Err(format!("{} warnings, the first: {w}", warnings.len()));
    }
    // The description is dropped here, as `prism render` drops it once the builder holds the scene.
    drop((desc, inputs));
    let m_report = rss();
    let t = Clock::start();
    let scene = builder.build(AccelKind::default_available()).map_err(|e| e.to_string())?;
    let build = t.stop();
    let m_build = rss();
    let peak = rss_bytes().1 as i64 - rss0;
    drop(scene);
    Ok(([parse, translate, report, build], [m_parse, m_translate, m_report, m_build, peak]))
}

/// A binary little-endian PLY of at least `n` triangles (a square heightfield) with positions
/// only; returns the triangle count.
fn write_ply(path: &Path, n: usize) -> Result<usize, String> {
    let side = ((n as f64 / 2.0).sqrt().ceil() as usize).max(1);
    let verts = (side + 1) * (side + 1);
    let tris = 2 * side * side;
    let mut out = Vec::with_capacity(200 + verts * 12 + tris * 13);
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {verts}\nproperty float x\nproperty float y\n\
         property float z\nelement face {tris}\nproperty list uchar int vertex_indices\nend_header\n"
    );
    out.extend_from_slice(header.as_bytes());
    let h = 1.0 / side as f32;
    for j in 0..=side {
        for i in 0..=side {
            let (x, y) = (i as f32 * h, j as f32 * h);
            let z = 0.05 * ((x * 40.0).sin() * (y * 37.0).cos());
            for v in [x - 0.5, y - 0.5, z] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    let id = |i: usize, j: usize| (j * (side + 1) + i) as u32;
    for j in 0..side {
        for i in 0..side {
            for t in [[id(i, j), id(i + 1, j), id(i + 1, j + 1)], [id(i, j), id(i + 1, j + 1), id(i, j + 1)]] {
                out.push(3);
                for v in t {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
    std::fs::write(path, out).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(tris)
}

/// Wall and CPU seconds to read the file at `path`, to decode it as PLY and to build the
/// accelerator over the mesh alone; the bytes the accelerator reports holding, and the resident
/// memory it adds after the build and at the peak of the build.
fn time_mesh_parts(path: &Path) -> Result<([[f64; 2]; 3], [i64; 3]), String> {
    let t = Clock::start();
    let bytes = prism::pbrt::input::read(path).map_err(|e| e.to_string())?;
    let read = t.stop();
    let t = Clock::start();
    let mesh = ply::parse(&bytes).map_err(|e| e.to_string())?;
    let decode = t.stop();
    drop(bytes);
    let rss0 = rss_bytes().0 as i64;
    prism::bench::reset_peak_rss();
    let t = Clock::start();
    let accel =
        prism::accel::build(AccelKind::default_available(), std::slice::from_ref(&mesh)).map_err(|e| e.to_string())?;
    let build = t.stop();
    let (rss, peak) = rss_bytes();
    let own = accel.memory_bytes() as i64;
    Ok(([read, decode, build], [own, rss as i64 - rss0, peak as i64 - rss0]))
}

fn list<T: std::str::FromStr + Clone>(arg: Option<String>, default: &[T]) -> Result<Vec<T>, String> {
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
    println!(
        "| kind | N | file MB | parse [s] | translate [s] | report [s] | build [s] | µs per element | CPU s: parse / \
         translate / report / build |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for kind in &kinds {
        for &n in &ns {
            let path = dir.join(format!("{kind}-{n}.pbrt"));
            let text = scene(kind, n);
            std::fs::write(&path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
            let (mut n, mut bytes) = (n, text.len());
            let mut mesh_note = String::new();
            if PLY_KINDS.contains(&kind.as_str()) {
                let ply_path = dir.join(format!("{kind}-{n}.ply"));
                let tris = write_ply(&ply_path, n)?;
                n = tris;
                bytes += std::fs::metadata(&ply_path).map_or(0, |m| m.len() as usize);
                let ([read, decode, accel], [own, resident, peak]) = time_mesh_parts(&ply_path)?;
                let per = |b: i64| b as f64 / tris as f64;
                mesh_note = format!(
                    "read {:.3} s ({:.3} CPU), PLY decode {:.3} s ({:.3} CPU), accelerator alone {:.3} s ({:.3} CPU; \
                     {:.1} B/triangle by its own count, {:.1} resident, {:.1} at its peak); ",
                    read[0],
                    read[1],
                    decode[0],
                    decode[1],
                    accel[0],
                    accel[1],
                    per(own),
                    per(resident),
                    per(peak)
                );
            }
            let (s, m) = time_stages(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let total: f64 = s.iter().map(|t| t[0]).sum();
            let cpu: Vec<String> = s.iter().map(|t| format!("{:.3}", t[1])).collect();
            println!(
                "| {kind} | {n} | {:.1} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} | {} |",
                bytes as f64 / 1e6,
                s[0][0],
                s[1][0],
                s[2][0],
                s[3][0],
                total / n as f64 * 1e6,
                cpu.join(" / ")
            );
            {
                let per = |b: i64| b as f64 / n as f64;
                let unit = if PLY_KINDS.contains(&kind.as_str()) { "triangle" } else { "element" };
                println!(
                    "  {mesh_note}resident B/{unit} after parse {:.1}, translate {:.1}, report (description \
                     dropped) {:.1}, build {:.1}; peak {:.1}",
                    per(m[0]),
                    per(m[1]),
                    per(m[2]),
                    per(m[3]),
                    per(m[4])
                );
            }
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
