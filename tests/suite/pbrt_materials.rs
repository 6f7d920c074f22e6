//! pbrt-v4's conductor `reflectance`, `coateddiffuse`, `coatedconductor` and `mix` parameters
//! become the materials pbrt-v4 builds from them, with its defaults and its errors.

use prism::accel::AccelKind;
use prism::material::{ConductorIor, FloatTexture, Ior, Material};
use prism::pbrt::{self, *};

const TRI: &str = r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]"#;

/// The materials of the scene `s` (a `Material` line, or named materials and a `NamedMaterial`
/// line, followed by a triangle) and the warnings of building it.
fn build(s: &str) -> (Vec<Material>, Vec<String>) {
    let (d, mut w) =
        parse_str(&format!("WorldBegin\n{s}\n{TRI}"), &ParseOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let (b, _) = pbrt::build(&d, &mut w).unwrap_or_else(|e| panic!("{e}"));
    w.extend(d.report_unused());
    let scene = b.build(AccelKind::Obvhs).unwrap();
    (scene.materials().to_vec(), w.iter().map(|w| w.to_string()).collect())
}

fn build_err(s: &str) -> String {
    let (d, _) = parse_str(&format!("WorldBegin\n{s}\n{TRI}"), &ParseOptions::default()).unwrap();
    pbrt::build(&d, &mut Vec::new()).err().expect("must not build").to_string()
}

fn constant(t: &FloatTexture) -> f32 {
    match t {
        FloatTexture::Constant(v) => *v,
        other => panic!("not a constant: {other:?}"),
    }
}

#[test]
fn coated_materials_take_every_pbrt_v4_parameter_and_its_defaults() {
    let (m, w) = build(
        r#"Material "coateddiffuse" "rgb reflectance" [0.2 0.3 0.4] "float uroughness" 0.1 "float vroughness" 0.2
  "float thickness" 0.15 "float eta" 1.33 "rgb albedo" [0.9 0.4 0.1] "float g" 0.5
  "integer maxdepth" 6 "integer nsamples" 4 "bool remaproughness" false"#,
    );
    assert!(w.is_empty(), "{w:?}");
    let Material::CoatedDiffuse(c) = &m[0] else { panic!("{:?}", m[0]) };
    assert!(!c.analytic && !c.roughness.remap);
    assert_eq!((constant(&c.roughness.u), constant(&c.roughness.v)), (0.1, 0.2));
    assert!(matches!(c.eta, Ior::Constant(e) if e == 1.33));
    assert_eq!((constant(&c.layer.thickness), constant(&c.layer.g)), (0.15, 0.5));
    assert_eq!((c.layer.max_depth, c.layer.n_samples), (6, 4));

    // pbrt-v4's defaults: thickness 0.01, η 1.5, albedo 0, g 0, maxdepth 10, nsamples 1.
    let (m, _) = build(r#"Material "coateddiffuse""#);
    let Material::CoatedDiffuse(c) = &m[0] else { panic!() };
    assert!(c.roughness.remap && matches!(c.eta, Ior::Constant(e) if e == 1.5));
    assert_eq!((constant(&c.layer.thickness), c.layer.max_depth, c.layer.n_samples), (0.01, 10, 1));

    let (m, w) = build(
        r#"Material "coatedconductor" "float interface.roughness" 0.02 "float interface.eta" 1.7
  "spectrum conductor.eta" "metal-Au-eta" "spectrum conductor.k" "metal-Au-k"
  "float conductor.uroughness" 0.25 "float conductor.vroughness" 0.3 "float thickness" 0.02
  "rgb albedo" [0.5 0.5 0.5] "float g" -0.2 "integer maxdepth" 3 "integer nsamples" 2"#,
    );
    assert!(w.is_empty(), "{w:?}");
    let Material::CoatedConductor(c) = &m[0] else { panic!("{:?}", m[0]) };
    assert_eq!((constant(&c.interface_roughness.u), constant(&c.interface_roughness.v)), (0.02, 0.02));
    assert_eq!((constant(&c.conductor_roughness.u), constant(&c.conductor_roughness.v)), (0.25, 0.3));
    assert!(matches!(c.interface_eta, Ior::Constant(e) if e == 1.7));
    assert!(matches!(c.conductor, ConductorIor::EtaK { .. }));
    assert_eq!((constant(&c.layer.thickness), c.layer.max_depth, c.layer.n_samples), (0.02, 3, 2));

    // The reflectance form of the metal.
    let (m, _) = build(r#"Material "coatedconductor" "rgb reflectance" [0.15 0.45 0.85]"#);
    let Material::CoatedConductor(c) = &m[0] else { panic!() };
    assert!(matches!(c.conductor, ConductorIor::Reflectance(_)));
    assert!(matches!(c.interface_eta, Ior::Constant(e) if e == 1.5));
}

#[test]
fn conductor_reflectance_and_the_analytic_coat() {
    let (m, w) = build(r#"Material "conductor" "rgb reflectance" [0.95 0.6 0.35] "float roughness" 0.08"#);
    assert!(w.is_empty(), "{w:?}");
    assert!(matches!(&m[0], Material::Conductor { ior: ConductorIor::Reflectance(_), .. }), "{:?}", m[0]);
    let (m, _) = build(r#"Material "conductor""#);
    assert!(matches!(&m[0], Material::Conductor { ior: ConductorIor::EtaK { .. }, .. }));
    let (m, w) = build(r#"Material "coateddiffuse" "string model" "analytic""#);
    assert!(w.is_empty(), "{w:?}");
    assert!(matches!(&m[0], Material::CoatedDiffuse(c) if c.analytic));
}

#[test]
fn mixes_resolve_named_materials_and_nest() {
    let (m, w) = build(
        r#"MakeNamedMaterial "red" "string type" "diffuse" "rgb reflectance" [0.7 0.1 0.1]
MakeNamedMaterial "metal" "string type" "conductor" "float roughness" 0.05
MakeNamedMaterial "inner" "string type" "mix" "string materials" ["red" "metal"] "float amount" 0.3
Texture "check" "float" "checkerboard" "float tex1" 1 "float tex2" 0
MakeNamedMaterial "outer" "string type" "mix" "string materials" ["inner" "red"] "texture amount" "check"
NamedMaterial "outer""#,
    );
    assert!(w.is_empty(), "{w:?}");
    let Material::Mix(outer) = &m[0] else { panic!("{:?}", m[0]) };
    assert!(matches!(outer.amount, FloatTexture::Checkerboard { .. }));
    let Material::Mix(inner) = &outer.materials[0] else { panic!("{:?}", outer.materials[0]) };
    assert_eq!(constant(&inner.amount), 0.3);
    assert!(matches!(inner.materials[0], Material::Diffuse { .. }));
    assert!(matches!(inner.materials[1], Material::Conductor { .. }));
    assert!(matches!(outer.materials[1], Material::Diffuse { .. }));
    // The default amount is 0.5.
    let (m, _) = build(
        r#"MakeNamedMaterial "a" "string type" "diffuse"
Material "mix" "string materials" ["a" "a"]"#,
    );
    assert!(matches!(&m[0], Material::Mix(x) if constant(&x.amount) == 0.5));
}

#[test]
fn bad_coated_and_mix_parameters_are_errors_at_their_parameter() {
    assert_eq!(
        build_err(r#"Material "conductor" "rgb reflectance" [0.5 0.5 0.5] "spectrum eta" "metal-Au-eta""#),
        "<string>:2:22: give either \"reflectance\" or \"eta\" and \"k\", not both (at \"reflectance\")"
    );
    assert_eq!(
        build_err(r#"Material "coatedconductor" "rgb reflectance" [0.5 0.5 0.5] "float conductor.k" 3"#),
        "<string>:2:28: give either \"reflectance\" or \"conductor.eta\" and \"conductor.k\", not both (at \"reflectance\")"
    );
    assert_eq!(
        build_err(r#"Material "coateddiffuse" "integer nsamples" 0"#),
        "<string>:2:26: \"nsamples\" must be at least 1, got 0 (at \"nsamples\")"
    );
    assert_eq!(
        build_err(r#"Material "coateddiffuse" "string model" "plastic""#),
        "<string>:2:26: unknown coateddiffuse model \"plastic\"; valid models: analytic, layered (at \"model\")"
    );
    assert_eq!(
        build_err(r#"Material "mix" "string materials" ["a"]"#),
        "<string>:2:16: a mix needs two \"string materials\", got 1 (at \"materials\")"
    );
    assert_eq!(
        build_err(r#"Material "mix" "string materials" ["a" "b"]"#),
        "<string>:2:16: no named material \"a\" (at \"materials\")"
    );
    // A mix that names itself is a cycle, not a stack overflow.
    let e = build_err(
        r#"MakeNamedMaterial "loop" "string type" "mix" "string materials" ["loop" "loop"]
NamedMaterial "loop""#,
    );
    assert!(e.contains("nest more than 32 deep"), "{e}");
    // Twenty links of a chain naming the previous link twice would be 2²⁰ copies.
    let mut chain = String::from("MakeNamedMaterial \"m0\" \"string type\" \"diffuse\"\n");
    for i in 1..=20 {
        chain += &format!(
            "MakeNamedMaterial \"m{i}\" \"string type\" \"mix\" \"string materials\" [\"m{0}\" \"m{0}\"]\n",
            i - 1
        );
    }
    chain += "NamedMaterial \"m20\"";
    let e = build_err(&chain);
    assert!(e.contains("a mix tree of more than 4096 materials"), "{e}");
}
