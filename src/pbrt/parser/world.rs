//! Directives of the world block: attribute and object blocks, materials, textures, lights,
//! shapes.

use super::{Parser, Pushed};
use crate::pbrt::desc::*;
use crate::pbrt::error::{Location, SceneError};
use crate::pbrt::names;
use crate::pbrt::params::{Param, ParamSet, ParamValue};
use crate::pbrt::shapes;
use crate::pbrt::source::Source;
use crate::pbrt::tokenizer::Token;
use std::sync::Arc;

impl Parser<'_> {
    /// AttributeBegin/End, TransformBegin/End, Attribute, ObjectBegin/End, ObjectInstance,
    /// Material, MakeNamedMaterial, NamedMaterial, Texture, LightSource, AreaLightSource, Shape.
    /// `Ok(false)` if `tok` is not one of them.
    pub(super) fn world_directive(
        &mut self,
        tok: &Token,
        src: &mut Source,
        cs: &'static str,
    ) -> Result<bool, SceneError> {
        match &*tok.text {
            "AttributeBegin" | "TransformBegin" => {
                self.require_world(tok)?;
                let kind = if tok.text == "AttributeBegin" { Pushed::Attribute } else { Pushed::Transform };
                if kind == Pushed::Transform {
                    self.warn(&tok.loc(), "TransformBegin is deprecated in pbrt-v4; use AttributeBegin");
                }
                self.stack.push((self.gs.clone(), kind, tok.loc()));
            }
            "AttributeEnd" | "TransformEnd" => {
                self.require_world(tok)?;
                let want = if tok.text == "AttributeEnd" { Pushed::Attribute } else { Pushed::Transform };
                self.pop(tok, want)?;
            }
            "Attribute" => {
                self.require_world(tok)?;
                let target = src.string(tok, "a target (shape, light, material, medium, texture)")?;
                let key: &'static str = match &*target.text {
                    "shape" => "shape",
                    "light" => "light",
                    "material" => "material",
                    "medium" => "medium",
                    "texture" => "texture",
                    _ => {
                        return Err(SceneError::syntax(
                            &target.loc(),
                            &target.display(),
                            "Attribute target must be one of shape, light, material, medium, texture",
                        ))
                    }
                };
                let ps = src.params(cs)?;
                let entry = self.gs.defaults.entry(key).or_insert_with(|| ParamSet::new(cs));
                // Later Attribute values override earlier ones.
                let mut merged = ps;
                merged.merge_defaults(entry);
                *entry = merged;
            }
            "ObjectBegin" => {
                self.require_world(tok)?;
                let name = src.string(tok, "an object name")?;
                self.require_outside_object(tok)?;
                if let Some(&i) = self.object_index.get(&*name.text) {
                    let o = &self.objects[i];
                    return Err(SceneError::syntax(
                        &name.loc(),
                        &name.display(),
                        format!("object \"{}\" redefined (first defined at {})", o.name, o.loc),
                    ));
                }
                self.stack.push((self.gs.clone(), Pushed::Object, tok.loc()));
                self.current_object =
                    Some(ObjectDesc { name: name.text.into_owned(), shapes: Vec::new(), loc: tok.loc() });
            }
            "ObjectEnd" => {
                self.require_world(tok)?;
                self.pop(tok, Pushed::Object)?;
            }
            "ObjectInstance" => {
                self.require_world(tok)?;
                let name = src.string(tok, "an object name")?;
                self.require_outside_object(tok)?;
                let motion = self.motion();
                self.instances.push((name.text.into_owned(), self.gs.ctm, motion, tok.loc()));
            }
            "Material" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "a material type")?;
                let params = src.params(cs)?;
                let m = self.material(&ty.text, ty.loc(), params)?;
                self.materials.push(m);
                self.gs.material = MaterialRef::Anonymous(self.materials.len() - 1);
            }
            "MakeNamedMaterial" => {
                self.require_world(tok)?;
                let name = src.string(tok, "a material name")?;
                let params = src.params(cs)?;
                if let Some(&i) = self.named_material_index.get(&*name.text) {
                    let m = &self.named_materials[i];
                    return Err(SceneError::syntax(
                        &name.loc(),
                        &name.display(),
                        format!("named material \"{}\" redefined (first defined at {})", m.name, m.material.loc),
                    ));
                }
                let (ty, ty_loc) = match params.get("type") {
                    Some(Param { value: ParamValue::String(s), loc, .. }) if s.len() == 1 => {
                        (s[0].clone(), loc.clone())
                    }
                    _ => {
                        return Err(SceneError::syntax(
                            &name.loc(),
                            &name.display(),
                            format!("MakeNamedMaterial \"{}\" needs a \"string type\" parameter", name.text),
                        ))
                    }
                };
                let mut m = self.material(&ty, ty_loc, params)?;
                m.loc = tok.loc();
                let name: Arc<str> = Arc::from(&*name.text);
                self.named_material_index.insert(name.clone(), self.named_materials.len());
                self.named_materials.push(NamedMaterial { name, material: m });
            }
            "NamedMaterial" => {
                self.require_world(tok)?;
                let name = src.string(tok, "a material name")?;
                // A material defined by now shares its name; one that is not must be by the end,
                // which finds its index.
                self.gs.material = match self.named_material_index.get_key_value(&*name.text) {
                    Some((defined, &i)) => MaterialRef::Named(defined.clone(), i),
                    None => {
                        let undefined: Arc<str> = Arc::from(&*name.text);
                        self.named_material_uses.push((undefined.clone(), name.loc()));
                        MaterialRef::Named(undefined, super::DEFINED_LATER)
                    }
                };
            }
            "Texture" => {
                self.require_world(tok)?;
                let name = src.string(tok, "a texture name")?;
                let class = src.string(tok, "a texture class (\"float\" or \"spectrum\")")?;
                let ty = src.string(tok, "a texture type")?;
                let mut params = src.params(cs)?;
                let class = match &*class.text {
                    "float" => TextureClass::Float,
                    "spectrum" | "color" => TextureClass::Spectrum,
                    _ => {
                        return Err(SceneError::syntax(
                            &class.loc(),
                            &class.display(),
                            "texture class must be \"float\" or \"spectrum\"",
                        ))
                    }
                };
                let Some(&kind) = names::TEXTURES.iter().find(|k| **k == ty.text) else {
                    return Err(SceneError::UnknownType {
                        loc: ty.loc(),
                        kind: "texture",
                        name: ty.text.into_owned(),
                        valid: names::TEXTURES.join(", "),
                    });
                };
                if let Some(d) = self.gs.defaults.get("texture") {
                    params.merge_defaults(d);
                }
                self.share_texture_names(&mut params);
                let (shared, name_id, redefined) = match self.texture_names.get_key_value(&*name.text) {
                    Some((n, &(id, defined))) => {
                        let (n, redefined) = (n.clone(), defined[class as usize]);
                        self.texture_names.get_mut(&n).expect("just found").1[class as usize] = true;
                        (n, id, redefined)
                    }
                    None => {
                        let Ok(id) = u32::try_from(self.texture_names.len()) else {
                            return Err(SceneError::syntax(
                                &name.loc(),
                                &name.display(),
                                "more than 2³² texture names",
                            ));
                        };
                        let n: Arc<str> = Arc::from(&*name.text);
                        let mut defined = [false; 2];
                        defined[class as usize] = true;
                        self.texture_names.insert(n.clone(), (id, defined));
                        (n, id, false)
                    }
                };
                if redefined {
                    self.warn(&name.loc(), format!("texture \"{shared}\" redefined; the later definition is used"));
                }
                let world_from_texture = self.start_ctm(tok, "texture");
                self.textures.push(TextureDesc {
                    name: shared,
                    name_id,
                    class,
                    kind,
                    params,
                    world_from_texture,
                    loc: tok.loc(),
                });
            }
            "LightSource" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "a light type")?;
                let mut params = src.params(cs)?;
                if let Some(kind) = self.resolve_type(
                    &ty.text,
                    || ty.loc(),
                    "light",
                    names::PRISM_LIGHTS,
                    names::PBRT_ONLY_LIGHTS,
                    true,
                )? {
                    if let Some(d) = self.gs.defaults.get("light") {
                        params.merge_defaults(d);
                    }
                    if self.current_object.is_some() {
                        self.warn(&tok.loc(), "LightSource inside ObjectBegin is not instanced; it is added once");
                    }
                    let world_from_light = self.start_ctm(tok, "light");
                    let medium = self.gs.media.outside.clone();
                    self.lights.push(LightDesc { kind, params, world_from_light, medium, loc: tok.loc() });
                }
            }
            "AreaLightSource" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "an area light type")?;
                let mut params = src.params(cs)?;
                if let Some(kind) =
                    self.resolve_type(&ty.text, || ty.loc(), "area light", names::PRISM_AREA_LIGHTS, &[], true)?
                {
                    if let Some(d) = self.gs.defaults.get("light") {
                        params.merge_defaults(d);
                    }
                    self.gs.area_light = Some(AreaLightDesc { kind, params, loc: tok.loc() });
                }
            }
            "Shape" => {
                self.require_world(tok)?;
                let ty = src.string(tok, "a shape type")?;
                let params = src.params(cs)?;
                self.shape(tok, &ty, params)?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    pub(super) fn pop(&mut self, tok: &Token, want: Pushed) -> Result<(), SceneError> {
        let begin = match want {
            Pushed::Attribute => "AttributeBegin",
            Pushed::Transform => "TransformBegin",
            Pushed::Object => "ObjectBegin",
        };
        match self.stack.last().filter(|_| self.stack.len() > self.stack_floor) {
            None => Err(SceneError::syntax(&tok.loc(), &tok.text, format!("{} without a matching {begin}", tok.text))),
            Some((_, got, loc)) if *got != want => Err(SceneError::syntax(
                &tok.loc(),
                &tok.text,
                format!("{} does not match the open {:?}Begin at {loc}", tok.text, got),
            )),
            Some(_) => {
                let (gs, _, _) = self.stack.pop().expect("checked non-empty");
                if want == Pushed::Transform {
                    (self.gs.ctm, self.gs.ctm_end) = (gs.ctm, gs.ctm_end);
                } else {
                    self.gs = gs;
                }
                if want == Pushed::Object {
                    self.end_object();
                }
                Ok(())
            }
        }
    }

    pub(super) fn material(
        &mut self,
        ty: &str,
        loc: Location,
        mut params: ParamSet,
    ) -> Result<MaterialDesc, SceneError> {
        if ty.is_empty() || ty == "none" {
            // pbrt-v4 reads both as "interface", with a deprecation warning.
            self.warn(&loc, format!("material \"{ty}\" is deprecated; read as \"interface\""));
            self.share_texture_names(&mut params);
            return Ok(MaterialDesc { kind: "interface", params, loc });
        }
        let kind = self
            .resolve_type(ty, || loc.clone(), "material", names::PRISM_MATERIALS, names::PBRT_ONLY_MATERIALS, false)?
            .unwrap_or_default();
        if kind != ty {
            // The replacement's parameters mean something else: start from its defaults.
            params = ParamSet::new(params.color_space);
        } else if let Some(d) = self.gs.defaults.get("material") {
            params.merge_defaults(d);
        }
        self.share_texture_names(&mut params);
        Ok(MaterialDesc { kind, params, loc })
    }

    pub(super) fn shape(&mut self, tok: &Token, ty: &Token, mut params: ParamSet) -> Result<(), SceneError> {
        let Some(kind) =
            self.resolve_type(&ty.text, || ty.loc(), "shape", names::PRISM_SHAPES, names::PBRT_ONLY_SHAPES, true)?
        else {
            return Ok(());
        };
        if let Some(d) = self.gs.defaults.get("shape") {
            params.merge_defaults(d);
        }
        self.share_texture_names(&mut params);
        let loc = tok.loc();
        let geometry = match kind {
            "plymesh" | "objmesh" => {
                let path = shapes::mesh_file_path(kind, &params, &loc, &mut self.warnings)?;
                self.defer_mesh_file(kind, path, &loc)
            }
            _ => shapes::load(kind, &params, &loc, &mut self.warnings)?,
        };
        if matches!(kind, "trianglemesh" | "bilinearmesh" | "loopsubdiv") {
            // The mesh holds the values now.
            params.drop_consumed();
        }
        let mut area_light = self.gs.area_light.clone().map(Box::new);
        if self.current_object.is_some() && area_light.is_some() {
            self.unsupported(&loc, "area light on a shape inside ObjectBegin", "makes the shape non-emissive");
            area_light = None;
        }
        let motion = self.motion().map(Box::new);
        let s = ShapeDesc {
            kind,
            params,
            geometry,
            world_from_object: self.gs.ctm,
            motion,
            reverse_orientation: self.gs.reverse_orientation,
            material: self.gs.material.clone(),
            area_light,
            media: self.gs.media.clone(),
            loc,
        };
        match &mut self.current_object {
            Some(o) => o.shapes.push(s),
            None => self.shapes.push(s),
        }
        Ok(())
    }
}
