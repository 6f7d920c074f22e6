//! Parser tests: one per directive group, and exact error-message text.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3};
use prism::geometry::Quadric;
use prism::pbrt::{self, *};

fn parse(s: &str) -> (SceneDesc, Vec<Warning>) {
    parse_str(s, &ParseOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn err(s: &str) -> String {
    parse_str(s, &ParseOptions::default()).unwrap_err().to_string()
}

fn close(a: Mat4, b: Mat4) -> bool {
    a.abs_diff_eq(b, 1e-5)
}

/// A fresh directory under cargo's per-test temp dir.
fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("scene_parser").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const TRI: &str = r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]"#;

#[test]
fn transforms_post_multiply_the_ctm() {
    let (d, _) = parse(&format!(
        "WorldBegin\nTranslate 1 2 3\nScale 2 2 2\nRotate 90 0 0 1\n{TRI}\nIdentity\nConcatTransform [1 0 0 0 0 1 0 0 0 0 1 0 5 6 7 1]\n{TRI}\nTransform [2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1]\n{TRI}"
    ));
    let want = Mat4::from_translation(Vec3::new(1., 2., 3.))
        * Mat4::from_scale(Vec3::splat(2.))
        * Mat4::from_axis_angle(Vec3::Z, 90f32.to_radians());
    assert!(close(d.shapes[0].world_from_object, want));
    // Rotate 90 about z maps +x to +y: the shape's (1,0,0) lands at translate + 2·(0,1,0).
    let p = d.shapes[0].world_from_object.transform_point3(Vec3::X);
    assert!(p.abs_diff_eq(Vec3::new(1., 4., 3.), 1e-5), "{p}");
    assert_eq!(d.shapes[1].world_from_object.w_axis.truncate(), Vec3::new(5., 6., 7.));
    assert_eq!(d.shapes[2].world_from_object, Mat4::from_scale(Vec3::splat(2.)));
}

/// A transform's plain numbers, bracketed or bare, are read from the text, ones with a comment
/// among them through the tokens: both give the same matrix to the bit, and the same errors.
#[test]
fn transform_numbers_read_from_the_text_equal_the_tokens() {
    let words = ["1", "-0", "+2.", ".5", "1e-3", "-3.25E+2", "0.1234567", "16777217", "7", "-1", "0", "2.5e-7"];
    for k in 0..words.len() {
        let m: Vec<&str> = (0..16).map(|i| words[(i * 5 + k) % words.len()]).collect();
        let list = m.join("\t");
        let (text, _) = parse(&format!("WorldBegin\nTransform [ {list} ]\n{TRI}"));
        let (tokens, _) = parse(&format!("WorldBegin\nTransform [ {list} # a comment\n ]\n{TRI}"));
        let bits = |d: &SceneDesc| d.shapes[0].world_from_object.to_cols_array().map(f32::to_bits);
        assert_eq!(bits(&text), bits(&tokens), "{list}");
        let want: Vec<u32> = m.iter().map(|w| w.parse::<f32>().unwrap().to_bits()).collect();
        assert_eq!(bits(&text).to_vec(), want, "{list}");
    }
    // Bare numbers likewise, on one line or several.
    for k in 0..words.len() {
        let w: Vec<&str> = (0..3).map(|i| words[(i * 7 + k) % words.len()]).collect();
        let scale = format!("{}\n {}\t{}", w[0], w[1], w[2]);
        let (text, _) = parse(&format!("WorldBegin\nScale {scale}\n{TRI}"));
        let (tokens, _) = parse(&format!("WorldBegin\nScale {} # a comment\n {} {}\n{TRI}", w[0], w[1], w[2]));
        let bits = |d: &SceneDesc| d.shapes[0].world_from_object.to_cols_array().map(f32::to_bits);
        assert_eq!(bits(&text), bits(&tokens), "{scale}");
        let diagonal = [0, 5, 10].map(|i| bits(&text)[i]);
        // The CTM's product with the scale adds +0, which turns −0 into +0.
        let want: Vec<u32> = w.iter().map(|w| (w.parse::<f32>().unwrap() + 0.0).to_bits()).collect();
        assert_eq!(diagonal.to_vec(), want, "{scale}");
    }
    assert_eq!(err("Translate 1 2 x"), "<string>:1:15: expected a number (at \"x\")");
    assert_eq!(err("Translate [ 1 2 ]"), "<string>:1:17: Translate expects 3 numbers, found 2 (at \"]\")");
    assert_eq!(err("Translate [ 1 2 3 4 ]"), "<string>:1:19: Translate expects exactly 3 numbers (at \"4\")");
    assert_eq!(err("Translate [ 1 nan 3 ]"), "<string>:1:15: number is not finite (at \"nan\")");
    assert_eq!(err("Translate [ 1 2 \"3\" ]"), "<string>:1:17: Translate expects 3 numbers, found 2 (at \"\"3\"\")");
    assert_eq!(
        err("Translate [ 1 2"),
        "<string>:1:1: unexpected end of file: Translate expects 3 numbers (at \"Translate\")"
    );
}

#[test]
fn lookat_camera_transform_matches_pbrt_convention() {
    let (d, _) = parse("LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\nWorldBegin");
    let c = &d.camera;
    assert_eq!(c.directive.kind, "perspective");
    assert_eq!(c.directive.params.float("fov"), Some(45.0));
    // The eye maps to the camera origin; the look point lies on camera +z at distance 5.
    assert!(c.camera_from_world.transform_point3(Vec3::new(0., 0., -5.)).abs_diff_eq(Vec3::ZERO, 1e-6));
    assert!(c.camera_from_world.transform_point3(Vec3::ZERO).abs_diff_eq(Vec3::new(0., 0., 5.), 1e-6));
    // pbrt's camera space: +y is up, +x = up × dir = ŷ × ẑ = x̂ here.
    assert!(c.camera_from_world.transform_vector3(Vec3::Y).abs_diff_eq(Vec3::Y, 1e-6));
    assert!(c.camera_from_world.transform_vector3(Vec3::X).abs_diff_eq(Vec3::X, 1e-6));
    // Looking down −z instead flips camera +x to world −x.
    let (d, _) = parse("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin");
    assert!(d.camera.camera_from_world.transform_vector3(Vec3::NEG_X).abs_diff_eq(Vec3::X, 1e-6));
    assert_eq!(
        err("LookAt 0 0 0  0 0 0  0 1 0"),
        "<string>:1:1: LookAt is degenerate: eye equals look, or up is parallel to the view direction (at \"LookAt\")"
    );
}

#[test]
fn options_block_directives_and_defaults() {
    let (d, _) = parse(
        r#"Film "rgb" "integer xresolution" 64 "integer yresolution" [32] "string filename" "out.exr"
Sampler "halton" "integer pixelsamples" 16
Integrator "path" "integer maxdepth" 5
PixelFilter "box"
ColorSpace "rec2020"
Option "bool disablepixeljitter" true
Option "integer seed" 7
WorldBegin"#,
    );
    assert_eq!(d.film.params.int("xresolution"), Some(64));
    assert_eq!(d.film.params.string("filename"), Some("out.exr"));
    assert_eq!((d.sampler.kind.as_str(), d.sampler.params.int("pixelsamples")), ("halton", Some(16)));
    assert_eq!(d.integrator.params.int("maxdepth"), Some(5));
    assert_eq!(d.filter.kind, "box");
    assert_eq!(d.color_space, "rec2020");
    assert_eq!(d.options.bool("disablepixeljitter"), Some(true));
    assert_eq!(d.options.int("seed"), Some(7));
    let (d, _) = parse("WorldBegin");
    assert_eq!(
        [&d.camera.directive.kind, &d.film.kind, &d.sampler.kind, &d.integrator.kind, &d.filter.kind],
        ["perspective", "rgb", "zsobol", "path", "gaussian"]
    );
    assert_eq!(d.film.loc.line(), 1);
}

#[test]
fn attribute_stack_saves_transform_material_area_light_and_orientation() {
    let (d, _) = parse(&format!(
        r#"WorldBegin
Material "conductor"
AttributeBegin
  Translate 1 0 0
  ReverseOrientation
  Material "dielectric"
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  {TRI}
AttributeEnd
{TRI}"#
    ));
    let (a, b) = (&d.shapes[0], &d.shapes[1]);
    assert!(a.reverse_orientation && !b.reverse_orientation);
    assert!(a.area_light.is_some() && b.area_light.is_none());
    assert_eq!(d.material(&a.material).unwrap().kind, "dielectric");
    assert_eq!(d.material(&b.material).unwrap().kind, "conductor");
    assert_eq!(a.world_from_object.w_axis.x, 1.0);
    assert_eq!(b.world_from_object, Mat4::IDENTITY);
    assert_eq!(a.area_light.as_ref().unwrap().loc.line(), 7);
    assert_eq!(
        err("WorldBegin\nAttributeEnd"),
        "<string>:2:1: AttributeEnd without a matching AttributeBegin (at \"AttributeEnd\")"
    );
    let (_, w) = parse("WorldBegin\nAttributeBegin");
    assert_eq!(w[0].to_string(), "<string>:2:1: warning: AttributeBegin without a matching End");
}

#[test]
fn named_coordinate_systems() {
    let (d, _) = parse(&format!(
        "Translate 0 0 3\nCamera \"perspective\"\nWorldBegin\nTranslate 5 0 0\nCoordinateSystem \"mine\"\nIdentity\nCoordSysTransform \"camera\"\n{TRI}\nCoordSysTransform \"mine\"\n{TRI}"
    ));
    assert!(close(d.shapes[0].world_from_object, Mat4::from_translation(Vec3::new(0., 0., -3.))));
    assert!(close(d.shapes[1].world_from_object, Mat4::from_translation(Vec3::new(5., 0., 0.))));
    let (_, w) = parse("WorldBegin\nCoordSysTransform \"nope\"");
    assert_eq!(
        w[0].to_string(),
        "<string>:2:19: warning: unknown coordinate system \"nope\"; CoordSysTransform ignored"
    );
}

#[test]
fn named_materials_and_textures() {
    let (d, _) = parse(&format!(
        r#"WorldBegin
Texture "checks" "spectrum" "checkerboard" "rgb tex1" [1 0 0] "rgb tex2" [0 0 1]
MakeNamedMaterial "red" "string type" "diffuse" "texture reflectance" "checks"
NamedMaterial "red"
{TRI}
NamedMaterial "later"
{TRI}
MakeNamedMaterial "later" "string type" "coateddiffuse" "float roughness" 0.1"#
    ));
    assert_eq!(d.shapes[0].material, MaterialRef::Named("red".into(), 0));
    let red = d.named_material("red").unwrap();
    assert_eq!(red.kind, "diffuse");
    assert_eq!(red.params.spectrum_or_texture("reflectance"), Some(SpectrumOrTexture::Texture("checks")));
    assert_eq!(d.material(&d.shapes[1].material).unwrap().kind, "coateddiffuse");
    let t = d.texture("checks", TextureClass::Spectrum).unwrap();
    assert_eq!((t.kind, t.params.spectrum("tex1")), ("checkerboard", Some(&SpectrumParam::Rgb([1., 0., 0.]))));
    assert_eq!(
        err("WorldBegin\nNamedMaterial \"ghost\""),
        "<string>:2:15: named material \"ghost\" is not defined (at \"ghost\")"
    );
    assert_eq!(
        err("WorldBegin\nMakeNamedMaterial \"m\" \"rgb reflectance\" [1 1 1]"),
        "<string>:2:19: MakeNamedMaterial \"m\" needs a \"string type\" parameter (at \"\"m\"\")"
    );
    assert_eq!(
        err("WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\""),
        "<string>:3:19: named material \"m\" redefined (first defined at <string>:2:1) (at \"\"m\"\")"
    );
    assert_eq!(
        err("WorldBegin\nMaterial \"diffuse\" \"texture reflectance\" \"nope\""),
        "<string>:2:20: texture \"nope\" is not defined (at \"nope\")"
    );
}

#[test]
fn names_are_shared_and_a_mesh_holds_its_values_once() {
    let (d, _) = parse(&format!(
        r#"WorldBegin
MakeNamedMaterial "ahead" "string type" "diffuse" "texture reflectance" "checks"
Texture "checks" "spectrum" "checkerboard"
Texture "checks" "float" "constant"
MakeNamedMaterial "after" "string type" "diffuse" "texture reflectance" "checks"
NamedMaterial "after"
Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2] "float foo" 1
NamedMaterial "later"
{TRI}
MakeNamedMaterial "later" "string type" "diffuse""#
    ));
    let reflectance = |m: usize| match &d.named_materials[m].material.params.get("reflectance").unwrap().value {
        ParamValue::Texture(t, id) => (t.clone(), *id),
        v => panic!("{v:?}"),
    };
    // One text and one id per texture name, whatever its class; a parameter written after a
    // definition
    // shares it and its id, one written before every definition holds its own text and no id.
    assert!(Arc::ptr_eq(&d.textures[0].name, &d.textures[1].name));
    assert_eq!((d.textures[0].name_id, d.textures[1].name_id), (0, 0));
    let (after, id) = reflectance(1);
    assert!(Arc::ptr_eq(&after, &d.textures[0].name) && id == Some(0));
    let (ahead, id) = reflectance(0);
    assert!(!Arc::ptr_eq(&ahead, &d.textures[0].name) && *ahead == *"checks" && id.is_none());
    // A named material's users hold its index, also when the definition comes after them.
    assert_eq!(d.shapes[0].material, MaterialRef::Named("after".into(), 1));
    assert_eq!(d.shapes[1].material, MaterialRef::Named("later".into(), 2));
    assert_eq!(d.material(&d.shapes[1].material).unwrap().loc.line(), 10);
    // The mesh has taken "P" and "indices": the shape keeps only the parameter it did not read,
    // which is still reported.
    let kept: Vec<&str> = d.shapes[0].params.iter().map(|p| &*p.name).collect();
    assert_eq!(kept, ["foo"]);
    assert!(d.shapes[1].params.is_empty());
    let w: Vec<String> = d.report_unused().iter().map(|w| w.to_string()).collect();
    assert!(
        w.contains(&"<string>:7:79: warning: parameter \"float foo\" of Shape \"trianglemesh\" was not used".into()),
        "{w:?}"
    );
}

#[test]
fn object_instancing() {
    let (d, _) = parse(&format!(
        r#"WorldBegin
ObjectBegin "tri"
  Translate 0 0 1
  {TRI}
ObjectEnd
Translate 10 0 0
ObjectInstance "tri"
Translate 10 0 0
ObjectInstance "tri""#
    ));
    assert!(d.shapes.is_empty());
    assert_eq!(d.objects.len(), 1);
    assert_eq!(d.objects[0].shapes[0].world_from_object.w_axis.z, 1.0);
    assert_eq!(d.instances.len(), 2);
    assert_eq!(d.instances[1].world_from_instance.w_axis.x, 20.0);
    assert_eq!(d.instances[1].object_index, 0);
    // The object's Translate does not leak out of ObjectBegin/End.
    assert_eq!(d.instances[0].world_from_instance.w_axis.z, 0.0);
    assert_eq!(err("WorldBegin\nObjectInstance \"x\""), "<string>:2:1: object \"x\" is not defined (at \"x\")");
    assert_eq!(
        err("WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\""),
        "<string>:3:1: ObjectBegin inside the definition of object \"a\" (<string>:2:1) (at \"ObjectBegin\")"
    );
    assert_eq!(
        err("WorldBegin\nObjectBegin \"a\"\nObjectInstance \"a\""),
        "<string>:3:1: ObjectInstance inside the definition of object \"a\" (<string>:2:1) (at \"ObjectInstance\")"
    );
    assert_eq!(
        err("WorldBegin\nObjectBegin \"a\"\nAttributeEnd"),
        "<string>:3:1: AttributeEnd does not match the open ObjectBegin at <string>:2:1 (at \"AttributeEnd\")"
    );
    let (d, w) = parse(&format!("WorldBegin\nAreaLightSource \"diffuse\"\nObjectBegin \"a\"\n{TRI}\nObjectEnd"));
    assert!(d.objects[0].shapes[0].area_light.is_none());
    assert!(w[0].message.contains("area light on a shape inside ObjectBegin"), "{}", w[0]);
}

#[test]
fn lights_and_attribute_defaults() {
    let (d, _) = parse(
        r#"WorldBegin
Attribute "light" "float scale" 2
Translate 0 1 0
LightSource "point" "rgb I" [1 2 3] "float scale" 5
LightSource "infinite" "blackbody L" 5500
LightSource "goniometric""#,
    );
    assert_eq!(d.lights.len(), 3);
    assert_eq!(d.lights[2].kind, "goniometric");
    assert_eq!(d.lights[0].params.float("scale"), Some(5.0));
    assert_eq!(d.lights[1].params.float("scale"), Some(2.0));
    assert_eq!(d.lights[1].params.spectrum("L"), Some(&SpectrumParam::Blackbody(5500.)));
    assert_eq!(d.lights[0].world_from_light.w_axis.y, 1.0);
}

#[test]
fn spheres_meshes_and_index_errors() {
    let (d, _) = parse("WorldBegin\nShape \"sphere\" \"float radius\" 2 \"float zmax\" 1");
    match d.shapes[0].geometry {
        ShapeGeometry::Quadric(Quadric::Sphere { radius, z_min, z_max, phi_max }) => {
            assert_eq!((radius, z_min, z_max, phi_max), (2., -2., 1., 360.))
        }
        _ => panic!("not a sphere"),
    }
    let (d, _) = parse(
        "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"point2 uv\" [0 0 1 0 0 1 1 1]",
    );
    let ShapeGeometry::Mesh(m) = &d.shapes[0].geometry else { panic!() };
    assert_eq!((m.len(), m.area()), (2, 1.0));
    assert_eq!(
        err("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]"),
        "<string>:2:53: index 3 is out of range: the mesh has 3 vertices (at \"integer indices\")"
    );
    assert_eq!(
        err("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1]"),
        "<string>:2:22: parameter \"point3 P\" has 8 values; a multiple of 3 is required (at \"\"point3 P\"\")"
    );
    assert_eq!(
        err("WorldBegin\nShape \"sphere\" \"float radius\" -1"),
        "<string>:2:1: sphere radius must be positive, got -1 (at \"Shape \"sphere\"\")"
    );
}

/// The error of building (not just parsing) the scene `s`.
fn build_err(s: &str) -> String {
    pbrt::build(&parse(s).0, &mut Vec::new()).err().expect("must not build").to_string()
}

#[test]
fn render_settings_out_of_range_are_errors_at_their_parameter() {
    // prism used to clamp these silently (0 spp to 1, depth -2 to 0, a 0-pixel side to 1).
    assert_eq!(
        build_err("Film \"rgb\" \"integer xresolution\" 0\nWorldBegin"),
        "<string>:1:12: \"xresolution\" must be at least 1, got 0 (at \"xresolution\")"
    );
    assert_eq!(
        build_err("Sampler \"sobol\"\n  \"integer pixelsamples\" -4\nWorldBegin"),
        "<string>:2:3: \"pixelsamples\" must be at least 1, got -4 (at \"pixelsamples\")"
    );
    assert_eq!(
        build_err("Integrator \"path\" \"integer maxdepth\" -2\nWorldBegin"),
        "<string>:1:19: \"maxdepth\" must be at least 0, or -1 for no limit, got -2 (at \"maxdepth\")"
    );
    // -1 is no limit, as in Mitsuba 3 (and pbrt-v4, whose depth never reaches it).
    let (_, settings) =
        pbrt::build(&parse("Integrator \"path\" \"integer maxdepth\" -1\nWorldBegin").0, &mut Vec::new()).unwrap();
    assert_eq!(settings.max_depth, Some(prism::integrator::UNBOUNDED_DEPTH));
    for fov in ["0", "180", "-30"] {
        assert_eq!(
            build_err(&format!("Camera \"perspective\" \"float fov\" {fov}\nWorldBegin")),
            format!("<string>:1:22: \"fov\" must be between 0 and 180 degrees, got {fov} (at \"fov\")")
        );
    }
    // The edges of what is allowed still build.
    let ok = "Film \"rgb\" \"integer xresolution\" 1 \"integer yresolution\" 1\nSampler \"sobol\" \"integer pixelsamples\" 1\n\
              Integrator \"path\" \"integer maxdepth\" 0\nCamera \"perspective\" \"float fov\" 179\nWorldBegin";
    let (_, settings) = pbrt::build(&parse(ok).0, &mut Vec::new()).unwrap();
    assert_eq!((settings.resolution, settings.spp, settings.max_depth), (Some((1, 1)), Some(1), Some(0)));
}

#[test]
fn spotlight_angles_out_of_range_are_errors_and_a_delta_wider_than_the_cone_is_clamped() {
    let spot = |params: &str| format!("WorldBegin\nLightSource \"spot\" {params}");
    for (param, value, rule) in [
        ("coneangle", "-20", "must be in (0, 180] degrees"),
        ("coneangle", "200", "must be in (0, 180] degrees"),
        ("conedeltaangle", "-1", "must be ≥ 0 degrees"),
        ("exponent", "-2", "must be a finite number ≥ 0"),
    ] {
        assert_eq!(
            build_err(&spot(&format!("\"float {param}\" {value}"))),
            format!("<string>:2:20: \"{param}\" {rule}, got {value} (at \"{param}\")")
        );
    }
    // A delta wider than the cone (given, or pbrt-v4's default of 5° under a narrower cone) is
    // taken as the whole cone, with a warning at the parameter or the directive.
    let warnings = |s: &str| {
        let mut w = Vec::new();
        pbrt::build(&parse(s).0, &mut w).expect("builds");
        w.iter().map(|w| w.to_string()).collect::<Vec<_>>()
    };
    assert_eq!(
        warnings(&spot("\"float coneangle\" 10 \"float conedelta\" 30")),
        ["<string>:2:41: warning: \"conedelta\" 30 is larger than \"coneangle\" 10; the falloff spans the whole cone"]
    );
    assert_eq!(
        warnings(&spot("\"float coneangle\" 2")),
        ["<string>:2:1: warning: \"conedeltaangle\" 5 (the default) is larger than \"coneangle\" 2; the falloff spans the whole cone"]
    );
    assert!(warnings(&spot("\"float coneangle\" 180 \"float conedeltaangle\" 180")).is_empty());
}

#[test]
fn unknown_types_list_valid_names() {
    assert_eq!(
        err("WorldBegin\nShape \"cube\""),
        "<string>:2:7: unknown shape type \"cube\"; valid shape types: bilinearmesh, curve, cylinder, disk, loopsubdiv, objmesh, plymesh, sphere, trianglemesh"
    );
    assert_eq!(
        err("WorldBegin\nMaterial \"plastic\""),
        "<string>:2:10: unknown material type \"plastic\"; valid material types: coatedconductor, coateddiffuse, conductor, dielectric, diffuse, diffusetransmission, hair, interface, measured, mix, subsurface, thindielectric"
    );
    assert_eq!(
        err("WorldBegin\nLightSource \"sun\""),
        "<string>:2:13: unknown light type \"sun\"; valid light types: distant, goniometric, infinite, point, projection, spot"
    );
    assert_eq!(
        err("Camera \"fisheye\""),
        "<string>:1:8: unknown camera type \"fisheye\"; valid camera types: orthographic, perspective, realistic, spherical"
    );
    assert_eq!(err("Frobnicate"), "<string>:1:1: unknown directive \"Frobnicate\" (at \"Frobnicate\")");
}

#[test]
fn every_pbrt_v4_integrator_and_film_is_read_as_itself() {
    for name in ["path", "volpath", "bdpt", "lightpath", "mlt", "sppm", "simplevolpath", "ambientocclusion"] {
        let (d, w) = parse(&format!("Integrator \"{name}\" \"integer maxdepth\" 3\nWorldBegin"));
        assert!(w.is_empty(), "{name}: {w:?}");
        assert_eq!((d.integrator.kind.as_str(), d.integrator.params.int("maxdepth")), (name, Some(3)));
    }
    // An unknown one is an error at its name.
    assert!(
        err("Integrator \"photonmap\"").starts_with("<string>:1:12: unknown integrator"),
        "{}",
        err("Integrator \"photonmap\"")
    );
    // Every pbrt-v4 film is written as itself.
    let (d_film, w) = parse("Film \"gbuffer\"\nWorldBegin");
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(d_film.film.kind, "gbuffer");
}

#[test]
fn block_placement_and_syntax_errors() {
    assert_eq!(err("Shape \"sphere\""), "<string>:1:1: Shape is not allowed before WorldBegin (at \"Shape\")");
    assert_eq!(
        err("WorldBegin\nCamera \"perspective\""),
        "<string>:2:1: Camera is not allowed after WorldBegin (at \"Camera\")"
    );
    assert_eq!(
        err("Translate 1 2"),
        "<string>:1:1: unexpected end of file: Translate expects 3 numbers (at \"Translate\")"
    );
    assert_eq!(err("Translate 1 nan 2"), "<string>:1:13: number is not finite (at \"nan\")");
    assert_eq!(err("Translate 1 \"a\" 2"), "<string>:1:13: Translate expects 3 numbers, found 1 (at \"\"a\"\")");
    assert_eq!(err("\"float x\" 1"), "<string>:1:1: expected a directive (at \"\"float x\"\")");
    assert_eq!(
        err("WorldBegin\nShape \"sphere\" \"float radius\" [ 1"),
        "<string>:2:31: unterminated [ for parameter \"float radius\" (at \"[\")"
    );
    // A byte-order mark and CRLF line ends are accepted; columns count from after the BOM.
    let (d, _) = parse("\u{feff}WorldBegin\r\nShape \"sphere\"\r\n");
    assert_eq!(d.shapes[0].loc.line_col(), (2, 1));
    assert_eq!(err("Rotate 30 0 0 0"), "<string>:1:1: rotation axis has zero length (at \"Rotate\")");
    // A parameter given twice: pbrt-v4 reads the last one.
    let (d, _) = parse("WorldBegin\nShape \"sphere\" \"float radius\" 1 \"float radius\" 2");
    assert_eq!(d.shapes[0].params.float("radius"), Some(2.0));
}

#[test]
fn unused_parameters_are_reported_after_building() {
    let (d, _) = parse(
        "WorldBegin\nShape \"sphere\" \"float radius\" 2 \"float radisu\" 3\nLightSource \"point\" \"rgb I\" [1 1 1]",
    );
    let _ = d.lights[0].params.spectrum("I");
    let w: Vec<String> = d.report_unused().iter().map(|w| w.to_string()).collect();
    assert_eq!(w, ["<string>:2:33: warning: parameter \"float radisu\" of Shape \"sphere\" was not used"]);
    // Unreferenced named materials are not reported; referenced ones are.
    let (d, _) = parse(&format!(
        r#"WorldBegin
MakeNamedMaterial "a" "string type" "diffuse" "float x" 1
MakeNamedMaterial "b" "string type" "diffuse" "float y" 1
NamedMaterial "b"
{TRI}"#
    ));
    let w: Vec<String> = d.report_unused().iter().map(|w| w.message.clone()).collect();
    assert_eq!(w, ["parameter \"float y\" of MakeNamedMaterial \"b\" was not used"]);
    // Likewise an anonymous Material replaced before any shape uses it.
    let (d, _) =
        parse(&format!("WorldBegin\nMaterial \"diffuse\" \"float x\" 1\nMaterial \"diffuse\" \"float y\" 1\n{TRI}"));
    let w: Vec<String> = d.report_unused().iter().map(|w| w.message.clone()).collect();
    assert_eq!(w, ["parameter \"float y\" of Material \"diffuse\" was not used"]);
    // A single-valued parameter given several values: the first is used and the rest reported
    // (pbrt-v4 stops with an error here).
    let (d, _) = parse("WorldBegin\nShape \"sphere\" \"float radius\" [2 5]");
    let w: Vec<String> = d.report_unused().iter().map(|w| w.to_string()).collect();
    assert_eq!(
        w,
        ["<string>:2:16: warning: parameter \"float radius\" of Shape \"sphere\" takes one value, but 2 were given; \
          the rest were ignored"]
    );
    // Negative RGB components are taken as 0, and said to be.
    let (d, _) = parse("WorldBegin\nLightSource \"point\" \"rgb I\" [1 -2 0.5]");
    let _ = d.lights[0].params.spectrum("I");
    let w: Vec<String> = d.report_unused().iter().map(|w| w.to_string()).collect();
    assert_eq!(
        w,
        ["<string>:2:21: warning: parameter \"rgb I\" of LightSource \"point\" has negative components \
          [1.0, -2.0, 0.5]; they are taken as 0"]
    );
}

#[test]
fn include_is_relative_to_the_including_file_and_shares_state() {
    let d = tmp("include");
    std::fs::create_dir_all(d.join("sub/deeper")).unwrap();
    std::fs::write(d.join("main.pbrt"), "WorldBegin\nInclude \"sub/a.pbrt\"\nShape \"sphere\"\n").unwrap();
    std::fs::write(d.join("sub/a.pbrt"), "Material \"conductor\"\nInclude \"deeper/b.pbrt\"\n").unwrap();
    std::fs::write(d.join("sub/deeper/b.pbrt"), "Translate 0 0 4\nShape \"sphere\"\n").unwrap();
    let (s, _) = parse_file(&d.join("main.pbrt"), &ParseOptions::default()).unwrap();
    assert_eq!(s.shapes.len(), 2);
    assert!(s.shapes[0].loc.file().ends_with("sub/deeper/b.pbrt"));
    assert_eq!(s.shapes[0].loc.line(), 2);
    // Include shares the graphics state: the included Translate and Material persist.
    assert_eq!(s.shapes[1].world_from_object.w_axis.z, 4.0);
    assert_eq!(s.material(&s.shapes[1].material).unwrap().kind, "conductor");
}

#[test]
fn relative_names_in_included_files_resolve_against_the_main_scene_files_directory() {
    // pbrt-v4 resolves every relative file name against the directory of the scene file it was
    // started with, whichever file names it.
    let d = tmp("search_dir");
    std::fs::create_dir_all(d.join("geometry")).unwrap();
    std::fs::create_dir_all(d.join("spds")).unwrap();
    std::fs::write(d.join("main.pbrt"), "WorldBegin\nInclude \"geometry/g.pbrt\"\n").unwrap();
    std::fs::write(
        d.join("geometry/g.pbrt"),
        "Include \"geometry/h.pbrt\"\nMaterial \"diffuse\" \"spectrum reflectance\" \"spds/r.spd\"\n\
         Shape \"objmesh\" \"string filename\" \"geometry/q.obj\"\n",
    )
    .unwrap();
    std::fs::write(d.join("geometry/h.pbrt"), "Translate 0 0 4\n").unwrap();
    std::fs::write(d.join("geometry/q.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(d.join("spds/r.spd"), "400 0.5 700 0.5\n").unwrap();
    let (s, _) = parse_file(&d.join("main.pbrt"), &ParseOptions::default()).unwrap();
    assert_eq!(s.shapes[0].world_from_object.w_axis.z, 4.0);
    assert_eq!(s.shapes[0].params.filename("filename").unwrap(), d.join("geometry/q.obj"));
    let files = s.input_files();
    for f in ["geometry/h.pbrt", "spds/r.spd", "geometry/q.obj"] {
        assert!(files.contains(&d.join(f)), "{f} missing from {files:?}");
    }
    // When both exist, the main file's directory wins; a name found only next to the including
    // file still resolves there.
    std::fs::create_dir_all(d.join("geometry/geometry")).unwrap();
    std::fs::write(d.join("geometry/geometry/h.pbrt"), "Translate 0 0 9\n").unwrap();
    let (s, _) = parse_file(&d.join("main.pbrt"), &ParseOptions::default()).unwrap();
    assert_eq!(s.shapes[0].world_from_object.w_axis.z, 4.0);
    // Absolute names are taken as they are.
    let abs = d.join("geometry/q.obj");
    std::fs::write(
        d.join("abs.pbrt"),
        format!("WorldBegin\nShape \"objmesh\" \"string filename\" \"{}\"\n", abs.display()),
    )
    .unwrap();
    std::fs::write(d.join("geometry/i.pbrt"), "Include \"abs.pbrt\"\n").unwrap();
    std::fs::write(d.join("top.pbrt"), "Include \"geometry/i.pbrt\"\n").unwrap();
    let (s, _) = parse_file(&d.join("top.pbrt"), &ParseOptions::default()).unwrap();
    assert_eq!(s.shapes[0].params.filename("filename").unwrap(), abs);
}

#[test]
fn an_include_splices_its_tokens_into_the_stream() {
    // pbrt-v4 reads an included file's tokens in place of the Include: a directive it leaves
    // unfinished goes on in the including file.
    let d = tmp("splice");
    std::fs::write(
        d.join("medium.pbrt"),
        "MakeNamedMedium \"smoke\" \"string type\" \"homogeneous\"\n  \"float scale\" 2\n",
    )
    .unwrap();
    std::fs::write(
        d.join("main.pbrt"),
        "WorldBegin\nInclude \"medium.pbrt\"\n  \"rgb sigma_a\" [1 2 3]\nShape \"sphere\"\n",
    )
    .unwrap();
    let (s, _) = parse_file(&d.join("main.pbrt"), &ParseOptions::default()).unwrap();
    assert_eq!((s.media.len(), s.shapes.len()), (1, 1));
    let at = |name: &str| {
        let l = &s.media[0].params.get(name).unwrap().loc;
        format!("{}:{}:{}", l.file().file_name().unwrap().to_string_lossy(), l.line(), l.col())
    };
    assert_eq!(at("scale"), "medium.pbrt:2:3");
    assert_eq!(at("sigma_a"), "main.pbrt:3:3");
    // Errors in the continued list point into the file that has them.
    std::fs::write(d.join("main2.pbrt"), "WorldBegin\nInclude \"medium.pbrt\"\n  \"float g\" [ oops ]\n").unwrap();
    let e = parse_file(&d.join("main2.pbrt"), &ParseOptions::default()).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}:3:15:", d.join("main2.pbrt").display())), "{e}");
}

#[test]
fn locations_are_exact_across_files_lines_and_directives_sharing_a_line() {
    // Locations are counted from byte offsets when asked for, in whatever order the parser asks
    // (a directive's after its parameters', an included file's between the includer's): each
    // must be the line and the column in characters where the token starts.
    let d = tmp("locations");
    std::fs::write(d.join("a.pbrt"), "# λλλ\n  Shape \"sphere\"   \"float radius\" 0.5 # é\n").unwrap();
    std::fs::write(
        d.join("main.pbrt"),
        "WorldBegin # ü\nInclude \"a.pbrt\"\nShape \"sphere\" \"float radius\" 1 Shape \"sphere\"\n  \"float radius\"\n\t2 \"float ünused\" 3\n",
    )
    .unwrap();
    let (s, _) = parse_file(&d.join("main.pbrt"), &ParseOptions::default()).unwrap();
    let at = |l: &prism::pbrt::Location| {
        format!("{}:{}:{}", l.file().file_name().unwrap().to_string_lossy(), l.line(), l.col())
    };
    let shapes: Vec<String> = s.shapes.iter().map(|s| at(&s.loc)).collect();
    assert_eq!(shapes, ["a.pbrt:2:3", "main.pbrt:3:1", "main.pbrt:3:33"]);
    let radii: Vec<String> = s.shapes.iter().map(|s| at(&s.params.get("radius").unwrap().loc)).collect();
    assert_eq!(radii, ["a.pbrt:2:20", "main.pbrt:3:16", "main.pbrt:4:3"]);
    let w: Vec<String> = s.report_unused().iter().map(|w| w.to_string()).filter(|w| w.contains("ünused")).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with(&format!("{}:5:4: warning: parameter \"float ünused\"", d.join("main.pbrt").display())),
        "{w:?}"
    );
}

#[test]
fn input_files_are_every_file_the_scene_reads_and_not_the_output() {
    let d = tmp("inputs");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    std::fs::write(
        d.join("main.pbrt"),
        "Film \"rgb\" \"string filename\" \"out.exr\"\nWorldBegin\nInclude \"sub/a.pbrt\"\n\
         Shape \"objmesh\" \"string filename\" \"sub/tri.obj\"\n",
    )
    .unwrap();
    // The included file names its data relative to itself, and names the mesh a second time.
    std::fs::write(
        d.join("sub/a.pbrt"),
        "Material \"diffuse\" \"spectrum reflectance\" \"r.spd\"\nShape \"objmesh\" \"string filename\" \"tri.obj\"\n",
    )
    .unwrap();
    std::fs::write(d.join("sub/tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    // (A name that exists only relative to the including file resolves there.)
    std::fs::write(d.join("sub/r.spd"), "400 0.5 700 0.5\n").unwrap();
    let (s, _) = parse_file(&d.join("main.pbrt"), &ParseOptions::default()).unwrap();
    let files: Vec<PathBuf> = s.input_files().iter().map(|f| f.strip_prefix(&d).unwrap().to_path_buf()).collect();
    let expect: Vec<PathBuf> = ["main.pbrt", "sub/a.pbrt", "sub/tri.obj", "sub/r.spd"].map(PathBuf::from).into();
    assert_eq!(files.len(), expect.len(), "{files:?}");
    for f in &expect {
        assert!(files.iter().any(|g| g.components().eq(f.components())), "{f:?} missing from {files:?}");
    }
}

#[test]
fn import_does_not_change_the_importers_state() {
    let d = tmp("import");
    std::fs::write(d.join("main.pbrt"), "WorldBegin\nImport \"part.pbrt\"\nShape \"sphere\"\n").unwrap();
    std::fs::write(
        d.join("part.pbrt"),
        "Translate 0 0 4\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"\nShape \"sphere\"\n",
    )
    .unwrap();
    let (s, _) = parse_file(&d.join("main.pbrt"), &ParseOptions::default()).unwrap();
    assert_eq!(s.shapes[0].world_from_object.w_axis.z, 4.0);
    assert_eq!(s.shapes[1].world_from_object.w_axis.z, 0.0);
    assert!(s.named_material("m").is_some());
}

#[test]
fn import_follows_pbrt_v4_semantics() {
    let d = tmp("import_v4");
    let write = |name: &str, text: &str| std::fs::write(d.join(name), text).unwrap();
    let parse_main = |name: &str| parse_file(&d.join(name), &ParseOptions::default());
    // The imported file changes every part of the graphics state and defines named things.
    write(
        "part.pbrt",
        r#"Translate 0 0 4
ReverseOrientation
Material "conductor"
AreaLightSource "diffuse" "rgb L" [1 1 1]
CoordinateSystem "inner"
MakeNamedMaterial "m" "string type" "diffuse"
Texture "t" "float" "constant" "float value" 0.5
ObjectBegin "o"
Shape "sphere"
ObjectEnd
AttributeBegin
Shape "sphere"
AttributeEnd
"#,
    );
    write(
        "main.pbrt",
        "WorldBegin\nAttributeBegin\nTranslate 1 0 0\nImport \"part.pbrt\"\nShape \"sphere\"\nAttributeEnd\n\
         NamedMaterial \"m\"\nObjectInstance \"o\"\nShape \"sphere\"\n",
    );
    let (s, _) = parse_main("main.pbrt").unwrap();
    // Inside the import: the importer's transform, then its own.
    assert_eq!(s.shapes[0].world_from_object.w_axis.x, 1.0);
    assert_eq!(s.shapes[0].world_from_object.w_axis.z, 4.0);
    assert!(s.shapes[0].reverse_orientation && s.shapes[0].area_light.is_some());
    // After it: the importer's state as it was (transform, orientation, material, area light).
    let after = &s.shapes[1];
    assert_eq!(after.world_from_object.w_axis.z, 0.0);
    assert_eq!(after.world_from_object.w_axis.x, 1.0);
    assert!(!after.reverse_orientation && after.area_light.is_none());
    assert_eq!(after.material, MaterialRef::Default);
    // Named materials, textures and objects it defines are the scene's.
    assert_eq!(s.shapes[2].material, MaterialRef::Named("m".into(), 0));
    assert!(s.texture("t", TextureClass::Float).is_some());
    assert_eq!(s.instances.len(), 1);
    // Coordinate-system names it defines stay in it.
    write("use_cs.pbrt", "WorldBegin\nImport \"part.pbrt\"\nCoordSysTransform \"inner\"\n");
    let (_, w) = parse_main("use_cs.pbrt").unwrap();
    assert!(w.iter().any(|w| w.message.contains("unknown coordinate system \"inner\"")), "{w:?}");
    // An imported file may not close the importer's blocks, nor leave its own open.
    write("closes.pbrt", "AttributeEnd\nAttributeBegin\n");
    write("m2.pbrt", "WorldBegin\nAttributeBegin\nImport \"closes.pbrt\"\nAttributeEnd\n");
    assert_eq!(
        parse_main("m2.pbrt").unwrap_err().to_string(),
        format!(
            "{}:1:1: AttributeEnd without a matching AttributeBegin (at \"AttributeEnd\")",
            d.join("closes.pbrt").display()
        )
    );
    write("opens.pbrt", "AttributeBegin\n");
    write("m3.pbrt", "WorldBegin\nImport \"opens.pbrt\"\n");
    let e = parse_main("m3.pbrt").unwrap_err().to_string();
    assert!(e.contains("leaves the AttributeBegin at") && e.contains("opens.pbrt:1:1"), "{e}");
    // Include, by contrast, may close blocks its includer opened; Import needs the world block.
    write("m4.pbrt", "WorldBegin\nAttributeBegin\nInclude \"closes.pbrt\"\nAttributeEnd\n");
    assert!(parse_main("m4.pbrt").is_ok());
    write("m5.pbrt", "Import \"part.pbrt\"\nWorldBegin\n");
    let e = parse_main("m5.pbrt").unwrap_err().to_string();
    assert!(e.contains("Import is not allowed before WorldBegin"), "{e}");
    // Inside an object definition, imported shapes belong to the object.
    write("shape.pbrt", "Shape \"sphere\"\n");
    write("m6.pbrt", "WorldBegin\nObjectBegin \"p\"\nImport \"shape.pbrt\"\nObjectEnd\n");
    let (s, _) = parse_main("m6.pbrt").unwrap();
    assert!(s.shapes.is_empty());
    assert_eq!(s.objects[0].shapes.len(), 1);
}

#[test]
fn area_light_parameters_unused_are_reported_once_per_directive() {
    let (d, _) = parse(&format!(
        "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"float typo\" 1\n{TRI}\n{TRI}\n{TRI}\n\
         AttributeBegin\nAreaLightSource \"diffuse\" \"float other\" 2\n{TRI}\n{TRI}\nAttributeEnd"
    ));
    let mut warnings = Vec::new();
    let _ = prism::pbrt::build(&d, &mut warnings).unwrap();
    let w: Vec<String> = d.report_unused().iter().map(|w| w.to_string()).collect();
    assert_eq!(
        w,
        [
            "<string>:2:43: warning: parameter \"float typo\" of AreaLightSource \"diffuse\" was not used",
            "<string>:7:27: warning: parameter \"float other\" of AreaLightSource \"diffuse\" was not used",
        ]
    );
}

#[test]
fn include_cycles_and_missing_files_are_errors() {
    let d = tmp("cycle");
    std::fs::write(d.join("a.pbrt"), "WorldBegin\nInclude \"b.pbrt\"\n").unwrap();
    std::fs::write(d.join("b.pbrt"), "\n  Include \"a.pbrt\"\n").unwrap();
    let e = parse_file(&d.join("a.pbrt"), &ParseOptions::default()).unwrap_err();
    let (a, b) = (std::fs::canonicalize(d.join("a.pbrt")).unwrap(), std::fs::canonicalize(d.join("b.pbrt")).unwrap());
    assert_eq!(
        e.to_string(),
        format!(
            "{}:2:3: include cycle: {} -> {} -> {}",
            d.join("b.pbrt").display(),
            a.display(),
            b.display(),
            a.display()
        )
    );
    std::fs::write(d.join("m.pbrt"), "Include \"missing.pbrt\"\n").unwrap();
    let e = parse_file(&d.join("m.pbrt"), &ParseOptions::default()).unwrap_err().to_string();
    let prefix = format!("{}:1:9: cannot read \"{}\": ", d.join("m.pbrt").display(), d.join("missing.pbrt").display());
    assert!(e.starts_with(&prefix), "{e}");
    let e = parse_file(&d.join("nope.pbrt"), &ParseOptions::default()).unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }));
}

#[test]
fn plymesh_and_objmesh_load_relative_to_the_scene() {
    let d = tmp("meshes");
    let mut quad = prism::geometry::Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::new(1., 1., 0.), Vec3::Y], vec![]);
    quad.normals = Some(vec![Vec3::Z; 4]);
    std::fs::create_dir_all(d.join("geo")).unwrap();
    std::fs::write(d.join("geo/q.ply"), prism::pbrt::mesh_io::ply::write(&quad, &[vec![0, 1, 2, 3]], true)).unwrap();
    std::fs::write(d.join("geo/t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        d.join("s.pbrt"),
        "WorldBegin\nShape \"plymesh\" \"string filename\" \"geo/q.ply\"\nShape \"objmesh\" \"string filename\" \"geo/t.obj\"\nShape \"plymesh\" \"string filename\" \"geo/t.obj\"\n",
    )
    .unwrap();
    let e = parse_file(&d.join("s.pbrt"), &ParseOptions::default()).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}:4:1: mesh file \"{}\": missing end_header",
            d.join("s.pbrt").display(),
            d.join("geo/t.obj").display()
        )
    );
    std::fs::write(
        d.join("s.pbrt"),
        "WorldBegin\nShape \"plymesh\" \"string filename\" \"geo/q.ply\"\nShape \"objmesh\" \"string filename\" \"geo/t.obj\"\n",
    )
    .unwrap();
    let (s, _) = parse_file(&d.join("s.pbrt"), &ParseOptions::default()).unwrap();
    let areas: Vec<f32> = s
        .shapes
        .iter()
        .map(|sh| match &sh.geometry {
            ShapeGeometry::Mesh(m) => m.area(),
            _ => -1.0,
        })
        .collect();
    assert_eq!(areas, [1.0, 0.5]);
    // OBJ skips unknown statements, so a file that is not OBJ at all parses to no triangles: say so.
    std::fs::write(d.join("geo/x.obj"), "not an obj file\n").unwrap();
    std::fs::write(d.join("s.pbrt"), "WorldBegin\nShape \"objmesh\" \"string filename\" \"geo/x.obj\"\n").unwrap();
    let (_, w) = parse_file(&d.join("s.pbrt"), &ParseOptions::default()).unwrap();
    let w: Vec<String> = w.iter().map(|w| w.to_string()).collect();
    assert!(w.len() == 1 && w[0].contains("2:1:") && w[0].contains("x.obj\" holds no triangles"), "{w:?}");
}

/// Mesh files are read when the parse ends, all at once: what a scene gets is what reading each
/// where its shape stands gives — meshes in their shapes (objects included, one left open too),
/// notes in order among the warnings, and the first failing file, in the scene's order, as the
/// error, even when a syntax error comes after it.
#[test]
fn mesh_files_read_together_behave_as_read_in_order() {
    let d = tmp("mesh_files_in_order");
    std::fs::write(d.join("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(d.join("q.obj"), "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4\n").unwrap();
    std::fs::write(d.join("x.obj"), "not an obj file\n").unwrap();
    let obj = |f: &str| format!("Shape \"objmesh\" \"string filename\" \"{f}\"\n");
    let scene = format!(
        "WorldBegin\n{}ObjectBegin \"o\"\n{}{}ObjectEnd\n{}WorldEnd\n{}ObjectBegin \"p\"\n{}",
        obj("t.obj"),
        obj("q.obj"),
        obj("x.obj"),
        obj("q.obj"),
        obj("x.obj"),
        obj("t.obj")
    );
    std::fs::write(d.join("s.pbrt"), &scene).unwrap();
    let (s, w) = parse_file(&d.join("s.pbrt"), &ParseOptions::default()).unwrap();
    let area = |g: &ShapeGeometry| match g {
        ShapeGeometry::Mesh(m) => m.area(),
        _ => -1.0,
    };
    let world: Vec<f32> = s.shapes.iter().map(|sh| area(&sh.geometry)).collect();
    assert_eq!(world, [0.5, 4.0, 0.0]);
    let objects: Vec<Vec<f32>> =
        s.objects.iter().map(|o| o.shapes.iter().map(|sh| area(&sh.geometry)).collect()).collect();
    assert_eq!(objects, [vec![4.0, 0.0], vec![0.5]]);
    // The notes of the two empty meshes, each where its shape stands: before the WorldEnd
    // warning and after it, then the unclosed ObjectBegin's.
    let w: Vec<String> = w.iter().map(|w| w.to_string()).collect();
    let line = |k: usize| w.get(k).map_or("", |s| s.as_str());
    assert_eq!(w.len(), 4, "{w:?}");
    assert!(line(0).contains("s.pbrt:5:1:") && line(0).contains("holds no triangles"), "{w:?}");
    assert!(line(1).contains("WorldEnd"), "{w:?}");
    assert!(line(2).contains("s.pbrt:9:1:") && line(2).contains("holds no triangles"), "{w:?}");
    assert!(line(3).contains("ObjectBegin"), "{w:?}");
    // A file that cannot be read is the error, though a later directive is wrong too.
    std::fs::write(d.join("s.pbrt"), format!("WorldBegin\n{}{}Shape \"cube\"\n", obj("t.obj"), obj("none.obj")))
        .unwrap();
    let e = parse_file(&d.join("s.pbrt"), &ParseOptions::default()).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!("{}:3:1: cannot read \"{}\"", d.join("s.pbrt").display(), d.join("none.obj").display())),
        "{e}"
    );
    std::fs::write(d.join("s.pbrt"), format!("WorldBegin\n{}Shape \"cube\"\n", obj("t.obj"))).unwrap();
    let e = parse_file(&d.join("s.pbrt"), &ParseOptions::default()).unwrap_err().to_string();
    assert!(e.contains("unknown shape type \"cube\""), "{e}");
}

#[test]
fn large_inline_mesh_parses() {
    // A 100k-vertex strip: 300k floats and ~100k triangles of text (about 3 MB).
    let n = 100_000u32;
    let mut s = String::from("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [");
    for i in 0..n {
        s += &format!(" {} {} 0", i / 2, i % 2);
    }
    s += " ] \"integer indices\" [";
    for i in 0..n - 2 {
        s += &format!(" {} {} {}", i, i + 1, i + 2);
    }
    s += " ]\n";
    let t = std::time::Instant::now();
    let (d, _) = parse(&s);
    let ShapeGeometry::Mesh(m) = &d.shapes[0].geometry else { panic!() };
    assert_eq!((m.positions.len(), m.len()), (n as usize, n as usize - 2));
    eprintln!("parsed {} bytes in {:?}", s.len(), t.elapsed());
}

#[test]
fn bspline_curves_become_bezier_segments_with_widths_linear_along_the_curve() {
    let (d, w) = parse(
        "WorldBegin\nShape \"curve\" \"string basis\" \"bspline\" \"point3 P\" [0 0 0 1 0 0 3 0 0 6 0 0 10 0 0]\n  \"float width0\" 0.3 \"float width1\" 0.1 \"integer splitdepth\" 2",
    );
    assert!(w.is_empty(), "{w:?}");
    let prism::pbrt::desc::ShapeGeometry::Curves(c) = &d.shapes[0].geometry else { panic!("not curves") };
    assert_eq!((c.segments.len(), c.split_depth), (2, 2));
    // The first four B-spline points 0, 1, 3, 6 give the Bézier points (p0 + 4p1 + p2)/6,
    // (2p1 + p2)/3, (p1 + 2p2)/3, (p1 + 4p2 + p3)/6.
    let xs = c.segments[0].cp.map(|p| p.x);
    for (x, want) in xs.iter().zip([7.0 / 6.0, 5.0 / 3.0, 7.0 / 3.0, 19.0 / 6.0]) {
        assert!((x - want).abs() < 1e-6, "{xs:?}");
    }
    assert_eq!(c.segments[1].cp[0], c.segments[0].cp[3]);
    let widths: Vec<[f32; 2]> = c.segments.iter().map(|s| s.width).collect();
    assert!(
        (widths[0][0] - 0.3).abs() < 1e-6 && (widths[0][1] - 0.2).abs() < 1e-6 && (widths[1][1] - 0.1).abs() < 1e-6
    );
    assert_eq!(
        err("WorldBegin\nShape \"curve\" \"string type\" \"ribbon\" \"point3 P\" [0 0 0 1 0 0 2 0 0 3 0 0]"),
        "<string>:2:1: a ribbon curve of 1 segment(s) needs 2 normals \"N\" (one per segment end), got 0 (at \"Shape \"curve\"\")"
    );
}

/// The Integrator's "rrthreshold" reaches the integrator (and is not reported unused); prism's
/// default, 1, is where roulette starts in pbrt-v4.
#[test]
fn the_integrators_rrthreshold_is_read() {
    for (text, expected) in [("Integrator \"volpath\" \"float rrthreshold\" 0\n", 0.0), ("", 1.0)] {
        let (d, mut warnings) = parse(&format!("{text}WorldBegin\n{TRI}"));
        let (_, settings) = prism::pbrt::build(&d, &mut warnings).unwrap();
        assert!(d.report_unused().is_empty(), "{:?}", d.report_unused());
        assert_eq!(prism::integrator::Integrator::from_file(&settings).rr_threshold, expected);
    }
}

/// Samples per pixel as pbrt-v4 takes them for each sampler, the sampler the file names with
/// its parameters, and a warning, not silence, where prism renders something else.
#[test]
fn samplers_take_pbrt_v4s_sample_counts_and_say_what_stands_in() {
    use prism::sampling::{Randomize, SamplerKind};
    for (sampler, spp, kind, warned) in [
        (
            "Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 3 \"bool jitter\" false",
            6,
            SamplerKind::Stratified { x: 2, y: 3, jitter: false },
            None,
        ),
        ("Sampler \"stratified\"", 16, SamplerKind::Stratified { x: 4, y: 4, jitter: true }, None),
        ("Sampler \"independent\"", 4, SamplerKind::Independent, None),
        ("Sampler \"independent\" \"integer pixelsamples\" 7", 7, SamplerKind::Independent, None),
        ("Sampler \"halton\" \"string randomization\" \"owen\"", 16, SamplerKind::Halton(Randomize::Owen), None),
        ("Sampler \"zsobol\" \"integer pixelsamples\" 32", 32, SamplerKind::ZSobol(Randomize::FastOwen), None),
        (
            "Sampler \"zsobol\" \"integer pixelsamples\" 24",
            24,
            SamplerKind::ZSobol(Randomize::FastOwen),
            Some("takes 16"),
        ),
        (
            "Sampler \"paddedsobol\" \"string randomization\" \"none\"",
            16,
            SamplerKind::PaddedSobol(Randomize::None),
            None,
        ),
        ("Sampler \"pmj02bn\"", 16, SamplerKind::Pmj02bn, None),
        ("Sampler \"sobol\"", 16, SamplerKind::GlobalSobol(Randomize::FastOwen), None),
        (
            "Sampler \"sobol\" \"string randomization\" \"owen\" \"integer pixelsamples\" 12",
            12,
            SamplerKind::GlobalSobol(Randomize::Owen),
            None,
        ),
        ("", 16, SamplerKind::ZSobol(Randomize::FastOwen), None),
    ] {
        let (d, mut warnings) = parse(&format!("{sampler}\nWorldBegin\n{TRI}"));
        let (_, settings) = prism::pbrt::build(&d, &mut warnings).unwrap();
        assert!(d.report_unused().is_empty(), "{sampler}: {:?}", d.report_unused());
        assert_eq!(settings.spp, Some(spp), "{sampler}");
        assert_eq!(settings.sampler, Some(kind), "{sampler}");
        let said: Vec<_> = warnings.iter().filter(|w| w.message.contains("sampler")).collect();
        match warned {
            None => assert!(said.is_empty(), "{sampler}: {warnings:?}"),
            Some(text) => assert!(said.len() == 1 && said[0].message.contains(text), "{sampler}: {warnings:?}"),
        }
    }
    // A randomisation the sampler does not take is an error, as in pbrt-v4.
    for bad in [
        "Sampler \"halton\" \"string randomization\" \"fastowen\"",
        "Sampler \"zsobol\" \"string randomization\" \"scramble\"",
    ] {
        let (d, mut warnings) = parse(&format!("{bad}\nWorldBegin\n{TRI}"));
        let e = prism::pbrt::build(&d, &mut warnings).err().unwrap_or_else(|| panic!("{bad} accepted"));
        assert!(e.to_string().contains("randomization"), "{e}");
    }
}

#[test]
fn skipped_degenerate_triangles_are_reported_at_their_shape() {
    // One sound triangle and one of zero area (a repeated vertex), plain and emitting.
    let mesh = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2 0 0 1]";
    let (d, _) =
        parse(&format!("WorldBegin\n{mesh}\nAttributeBegin\nAreaLightSource \"diffuse\"\n  {mesh}\nAttributeEnd"));
    let mut warnings = Vec::new();
    let (builder, _) = pbrt::build(&d, &mut warnings).expect("builds");
    let w: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    let what = "skipped 1 degenerate triangle(s) (zero or overflowing area, or vertices not finite or beyond ±1e18)";
    assert_eq!(w, [format!("<string>:2:1: warning: mesh 0: {what}"), format!("<string>:5:3: warning: mesh 1: {what}")]);
    assert!(builder.warnings.is_empty(), "{:?}", builder.warnings);
}
