//! Property test standing in for cargo-fuzz (which needs nightly): random token soups and
//! mutations of valid scene, PLY and OBJ files must produce `Ok` or `Err`, never a panic.
//! Fixed seeds; each loop stops after a case budget or ~1.5 s, whichever comes first.

use std::path::Path;
use std::time::{Duration, Instant};

use prism::pbrt::mesh_io::{obj, ply};
use prism::pbrt::{parse_str, ParseOptions};
use prism::sampling::Rng;

const BUDGET: Duration = Duration::from_millis(1500);

const VOCAB: &[&str] = &[
    "WorldBegin",
    "AttributeBegin",
    "AttributeEnd",
    "TransformBegin",
    "TransformEnd",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "Shape",
    "Material",
    "MakeNamedMaterial",
    "NamedMaterial",
    "Texture",
    "LightSource",
    "AreaLightSource",
    "Translate",
    "Scale",
    "Rotate",
    "LookAt",
    "Transform",
    "ConcatTransform",
    "Identity",
    "CoordinateSystem",
    "CoordSysTransform",
    "ReverseOrientation",
    "Camera",
    "Film",
    "Sampler",
    "Integrator",
    "PixelFilter",
    "ColorSpace",
    "Option",
    "Attribute",
    "ActiveTransform",
    "TransformTimes",
    "MediumInterface",
    "MakeNamedMedium",
    "Include",
    "Import",
    "WorldEnd",
    "[",
    "]",
    "[",
    "]",
    "0",
    "1",
    "-1",
    "2.5",
    "1e30",
    "1e40",
    "nan",
    "inf",
    "-0",
    "3",
    "7",
    "true",
    "false",
    "StartTime",
    "EndTime",
    "\"sphere\"",
    "\"trianglemesh\"",
    "\"bilinearmesh\"",
    "\"loopsubdiv\"",
    "\"plymesh\"",
    "\"diffuse\"",
    "\"conductor\"",
    "\"point\"",
    "\"a\"",
    "\"perspective\"",
    "\"float radius\"",
    "\"point3 P\"",
    "\"integer indices\"",
    "\"normal N\"",
    "\"point2 uv\"",
    "\"rgb L\"",
    "\"spectrum eta\"",
    "\"blackbody L\"",
    "\"string type\"",
    "\"texture reflectance\"",
    "\"bool x\"",
    "\"string filename\"",
    "\"float\"",
    "\"spectrum\"",
    "\"checkerboard\"",
    "\"shape\"",
    "\"light\"",
    "\"metal-Cu-eta\"",
    "\"\"",
    "\"a b c\"",
    "#",
    "\n",
    "\"",
    "\\",
    "\"x\\q\"",
];

const VALID: &str = r#"LookAt 0 3 -8  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
Film "rgb" "integer xresolution" 32 "integer yresolution" 24 "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" 4
Integrator "path" "integer maxdepth" 5
WorldBegin
LightSource "infinite" "rgb L" [0.2 0.2 0.3]
AttributeBegin
  Translate 0 4 0
  LightSource "point" "blackbody I" 3000 "float scale" 10
AttributeEnd
Texture "c" "spectrum" "checkerboard" "rgb tex1" [1 1 1] "rgb tex2" [0 0 0]
MakeNamedMaterial "floor" "string type" "diffuse" "texture reflectance" "c"
MakeNamedMaterial "gold" "string type" "conductor" "spectrum eta" "metal-Au-eta" "spectrum k" [400 1 700 2]
ObjectBegin "tri"
  NamedMaterial "gold"
  Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2] "normal N" [0 0 1 0 0 1 0 0 1]
ObjectEnd
AttributeBegin
  Rotate 30 0 1 0
  ObjectInstance "tri"
  Scale 2 2 2
  ObjectInstance "tri"
AttributeEnd
AttributeBegin
  NamedMaterial "floor"
  ReverseOrientation
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  Shape "bilinearmesh" "point3 P" [-5 0 -5 5 0 -5 -5 0 5 5 0 5] "point2 uv" [0 0 1 0 0 1 1 1]
  Shape "sphere" "float radius" 0.5 "float zmin" -0.2
AttributeEnd
"#;

fn opts(strict: bool) -> ParseOptions {
    // Includes in fuzz input resolve inside an empty directory: they fail cleanly.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("scene_fuzz_empty");
    std::fs::create_dir_all(&dir).unwrap();
    ParseOptions { strict, base_dir: Some(dir), ..Default::default() }
}

fn pick<T: Copy>(rng: &mut Rng, v: &[T]) -> T {
    v[rng.next_u32() as usize % v.len()]
}

/// Applies 1–4 random edits at char boundaries.
fn mutate(rng: &mut Rng, s: &str) -> String {
    let mut c: Vec<char> = s.chars().collect();
    for _ in 0..1 + rng.next_u32() % 4 {
        let n = c.len().max(1);
        let i = rng.next_u32() as usize % n;
        let j = (i + 1 + rng.next_u32() as usize % 16).min(c.len());
        match rng.next_u32() % 5 {
            0 if i < c.len() => {
                c.drain(i..j);
            }
            1 => c.splice(i.min(c.len())..i.min(c.len()), format!(" {} ", pick(rng, VOCAB)).chars()).for_each(drop),
            2 if i < c.len() => c[i] = char::from_u32(rng.next_u32() % 128).unwrap_or('x'),
            3 if j <= c.len() && i < j => {
                let dup: Vec<char> = c[i..j].to_vec();
                c.splice(j..j, dup).for_each(drop)
            }
            _ => {
                // Replace a number-looking word with an extreme value.
                let k = rng.next_u32() as usize % n;
                if k < c.len() && c[k].is_ascii_digit() {
                    c.splice(
                        k..k + 1,
                        pick(rng, &["-1", "1e39", "nan", "99999999999", "4294967295", "0.5"][..]).chars(),
                    )
                    .for_each(drop);
                }
            }
        }
    }
    c.into_iter().collect()
}

#[test]
fn random_token_soups_never_panic() {
    let mut rng = Rng::new(7, 1);
    let (start, mut cases, mut oks) = (Instant::now(), 0, 0);
    while cases < 20_000 && start.elapsed() < BUDGET {
        let n = 1 + rng.next_u32() % 60;
        let mut s = String::new();
        for _ in 0..n {
            s += pick(&mut rng, VOCAB);
            s.push(' ');
        }
        for strict in [false, true] {
            oks += parse_str(&s, &opts(strict)).is_ok() as u32;
        }
        cases += 1;
    }
    assert!(cases > 100, "only {cases} cases ran");
    eprintln!("token soups: {cases} cases, {oks} parsed");
}

#[test]
fn mutated_valid_scenes_never_panic() {
    // The unmutated scene parses: the mutations start from valid input.
    let (d, _) = parse_str(VALID, &opts(false)).unwrap();
    assert_eq!((d.instances.len(), d.shapes.len(), d.lights.len()), (2, 2, 2));
    let mut rng = Rng::new(11, 2);
    let (start, mut cases, mut oks) = (Instant::now(), 0u32, 0u32);
    while cases < 20_000 && start.elapsed() < BUDGET {
        let s = mutate(&mut rng, VALID);
        oks += parse_str(&s, &opts(cases.is_multiple_of(2))).is_ok() as u32;
        cases += 1;
    }
    assert!(cases > 100 && oks > 0, "{cases} cases, {oks} ok");
    eprintln!("scene mutations: {cases} cases, {oks} parsed");
}

#[test]
fn mutated_ply_and_obj_never_panic() {
    use glam::{Vec2, Vec3};
    let mut m = prism::geometry::Mesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(1., 1., 0.), Vec3::Y, Vec3::new(0.5, 0.5, 1.)],
        vec![],
    );
    m.normals = Some(vec![Vec3::Z; 5]);
    m.uvs = Some(vec![Vec2::ZERO; 5]);
    let faces = [vec![0, 1, 2, 3], vec![0, 1, 4], vec![1, 2, 4]];
    let seeds = [ply::write(&m, &faces, true), ply::write(&m, &faces, false)];
    let obj_src =
        b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -1 -2 -3\n".to_vec();
    let mut rng = Rng::new(13, 3);
    let (start, mut cases, mut oks) = (Instant::now(), 0, 0);
    while cases < 50_000 && start.elapsed() < BUDGET {
        let base = if cases % 3 == 2 { &obj_src } else { &seeds[cases % 2] };
        let mut b = base.clone();
        for _ in 0..1 + rng.next_u32() % 4 {
            let i = rng.next_u32() as usize % b.len();
            match rng.next_u32() % 4 {
                0 => b[i] = rng.next_u32() as u8,
                1 => b.truncate(i),
                2 => {
                    let j = (i + rng.next_u32() as usize % 8).min(b.len());
                    b.drain(i..j);
                }
                _ => {
                    let t = b[i..].to_vec();
                    b.truncate(i);
                    let ins: [&[u8]; 5] = [b"9", b"99999999999 ", b"-", b"\xff\xff\xff\x7f", b"element x 3\n"];
                    b.extend_from_slice(pick(&mut rng, &ins[..]));
                    b.extend(t);
                }
            }
            if b.is_empty() {
                b.push(b'p');
            }
        }
        let ok = if cases % 3 == 2 { obj::parse(&b).is_ok() } else { ply::parse(&b).is_ok() };
        oks += ok as u32;
        cases += 1;
    }
    assert!(cases > 100, "only {cases} cases");
    eprintln!("mesh mutations: {cases} cases, {oks} parsed");
}
