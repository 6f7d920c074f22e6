//! The named definitions of a scene description indexed, so that resolving a reference costs
//! an index into a vector (or, for a name written before its definition, a hash lookup) and a
//! binary search among the definitions of that one name, instead of a scan over every
//! definition of the scene.

use crate::pbrt::desc::{MaterialDesc, MaterialRef, SceneDesc, TextureClass};
use rustc_hash::FxHashMap as HashMap;
use std::cell::OnceCell;

/// Which material a reference resolves to: its identity in the description, so that shapes
/// sharing a material share one built material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum MaterialKey {
    /// pbrt-v4's default material.
    Default,
    /// Index into [`SceneDesc::materials`].
    Anonymous(usize),
    /// Index into [`SceneDesc::named_materials`].
    Named(usize),
}

/// A value per [`MaterialKey`], kept in vectors indexed like the description's lists of
/// materials: a slot per definition instead of a hash map's entry.
pub(super) struct ByMaterial<T> {
    default: Option<T>,
    anonymous: Vec<Option<T>>,
    named: Vec<Option<T>>,
}

impl<T> Default for ByMaterial<T> {
    fn default() -> Self {
        Self { default: None, anonymous: Vec::new(), named: Vec::new() }
    }
}

impl<T: Copy> ByMaterial<T> {
    /// The value of `key`, if one was set.
    pub(super) fn get(&self, key: MaterialKey) -> Option<T> {
        match key {
            MaterialKey::Default => self.default,
            MaterialKey::Anonymous(i) => self.anonymous.get(i).copied().flatten(),
            MaterialKey::Named(i) => self.named.get(i).copied().flatten(),
        }
    }

    /// Sets the value of `key`.
    pub(super) fn set(&mut self, key: MaterialKey, value: T) {
        let slot = |list: &mut Vec<Option<T>>, i: usize| {
            if list.len() <= i {
                list.resize(i + 1, None);
            }
            list[i] = Some(value);
        };
        match key {
            MaterialKey::Default => self.default = Some(value),
            MaterialKey::Anonymous(i) => slot(&mut self.anonymous, i),
            MaterialKey::Named(i) => slot(&mut self.named, i),
        }
    }
}

/// Named materials and textures of one [`SceneDesc`] by name.
pub(super) struct Definitions<'d> {
    desc: &'d SceneDesc,
    /// Index into [`SceneDesc::named_materials`] by name (names are unique: the parser refuses
    /// a redefinition), made when a name is first looked up by its text.
    named_by_text: OnceCell<HashMap<&'d str, usize>>,
    /// For each texture name, by its id ([`crate::pbrt::TextureDesc::name_id`]), and class
    /// (float, spectrum), the indices into [`SceneDesc::textures`] of its definitions.
    textures: Vec<[TextureDefs; 2]>,
    /// Each texture name's id by its text, made when a name is first looked up by its text (a
    /// parameter written before every definition of its name has no id).
    texture_ids: OnceCell<HashMap<&'d str, u32>>,
}

/// The definitions of one texture name and class: indices into [`SceneDesc::textures`].
#[derive(Default)]
enum TextureDefs {
    /// Not defined with this class.
    #[default]
    None,
    /// Defined once (most names): no list to allocate.
    One(usize),
    /// Defined again: every definition in ascending order.
    Many(Vec<usize>),
}

impl<'d> Definitions<'d> {
    /// Indexes `desc`, in time linear in its number of definitions.
    pub(super) fn new(desc: &'d SceneDesc) -> Self {
        // Ids count the names in the order of their first definitions: each is at most the
        // number of definitions before it (a larger one is no parser's and finds nothing).
        let mut textures: Vec<[TextureDefs; 2]> = Vec::new();
        for (i, t) in desc.textures.iter().enumerate() {
            let id = t.name_id as usize;
            if id > i {
                continue;
            }
            if id >= textures.len() {
                textures.resize_with(id + 1, Default::default);
            }
            let defs = &mut textures[id][t.class as usize];
            *defs = match std::mem::take(defs) {
                TextureDefs::None => TextureDefs::One(i),
                TextureDefs::One(j) => TextureDefs::Many(vec![j, i]),
                TextureDefs::Many(mut v) => {
                    v.push(i);
                    TextureDefs::Many(v)
                }
            };
        }
        Self { desc, named_by_text: OnceCell::new(), textures, texture_ids: OnceCell::new() }
    }

    /// The named material `name`.
    pub(super) fn named_material(&self, name: &str) -> Option<(MaterialKey, &'d MaterialDesc)> {
        let by_text = self
            .named_by_text
            .get_or_init(|| self.desc.named_materials.iter().enumerate().map(|(i, m)| (&*m.name, i)).collect());
        let &i = by_text.get(name)?;
        Some((MaterialKey::Named(i), &self.desc.named_materials[i].material))
    }

    /// The material `r` refers to, with its key (`None` for the default material).
    pub(super) fn material(&self, r: &MaterialRef) -> (MaterialKey, Option<&'d MaterialDesc>) {
        match r {
            MaterialRef::Default => (MaterialKey::Default, None),
            MaterialRef::Anonymous(i) => (MaterialKey::Anonymous(*i), self.desc.materials.get(*i)),
            // The parser refuses undefined names; an index past the definitions is the default
            // material.
            MaterialRef::Named(_, i) => match self.desc.named_materials.get(*i) {
                Some(m) => (MaterialKey::Named(*i), Some(&m.material)),
                None => (MaterialKey::Default, None),
            },
        }
    }

    /// The index of the last definition of texture `name` (whose id is `id`, when known) of
    /// class `class` among the first `visible` texture directives.
    pub(super) fn texture_before(
        &self,
        name: &str,
        id: Option<u32>,
        class: TextureClass,
        visible: usize,
    ) -> Option<usize> {
        let id = match id {
            Some(id) => id,
            None => *self
                .texture_ids
                .get_or_init(|| self.desc.textures.iter().map(|t| (&*t.name, t.name_id)).collect())
                .get(name)?,
        };
        let defs = match &self.textures.get(id as usize)?[class as usize] {
            TextureDefs::None => return None,
            TextureDefs::One(i) => std::slice::from_ref(i),
            TextureDefs::Many(v) => v.as_slice(),
        };
        let n = defs.partition_point(|&i| i < visible);
        n.checked_sub(1).map(|k| defs[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::{parse_str, ParseOptions};

    /// Textures named from a small set, so that names are defined again and again.
    fn scene() -> SceneDesc {
        let mut text = String::from("WorldBegin\n");
        let mut state = 12345u32;
        for i in 0..200 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let class = if state >> 31 == 0 { "float" } else { "spectrum" };
            text += &format!("Texture \"t{}\" \"{class}\" \"constant\" \"float value\" {i}\n", (state >> 8) % 13);
        }
        for i in 0..20 {
            text += &format!("MakeNamedMaterial \"m{i}\" \"string type\" \"diffuse\"\n");
        }
        text += "Material \"conductor\"\n";
        parse_str(&text, &ParseOptions::default()).unwrap().0
    }

    #[test]
    fn texture_lookups_find_the_last_earlier_definition_as_a_scan_does() {
        let desc = scene();
        let defs = Definitions::new(&desc);
        for visible in 0..=desc.textures.len() {
            for name in (0..14).map(|k| format!("t{k}")) {
                for class in [TextureClass::Float, TextureClass::Spectrum] {
                    let scan = desc.textures[..visible].iter().rposition(|t| *t.name == *name && t.class == class);
                    // By the name's id (as a parameter written after a definition holds it), and
                    // by its text alone (as one written before every definition).
                    let id = desc.textures.iter().find(|t| *t.name == *name).map(|t| t.name_id);
                    for id in id.into_iter().map(Some).chain([None]) {
                        assert_eq!(
                            defs.texture_before(&name, id, class, visible),
                            scan,
                            "{name} {class:?} before {visible}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn material_references_resolve_to_their_definitions() {
        let desc = scene();
        let defs = Definitions::new(&desc);
        for (i, m) in desc.named_materials.iter().enumerate() {
            let (key, found) = defs.material(&MaterialRef::Named(m.name.clone(), i));
            assert_eq!(key, MaterialKey::Named(i));
            assert!(std::ptr::eq(found.unwrap(), &m.material));
        }
        assert_eq!(defs.material(&MaterialRef::Anonymous(0)).1.unwrap().kind, "conductor");
        assert!(matches!(defs.material(&MaterialRef::Default), (MaterialKey::Default, None)));
        assert!(defs.named_material("m20").is_none());
    }

    #[test]
    fn values_by_material_are_kept_per_key() {
        let mut ids = ByMaterial::default();
        let keys = [MaterialKey::Named(5), MaterialKey::Default, MaterialKey::Anonymous(0), MaterialKey::Named(2)];
        for (v, &k) in keys.iter().enumerate() {
            assert_eq!(ids.get(k), None);
            ids.set(k, v);
        }
        for (v, &k) in keys.iter().enumerate() {
            assert_eq!(ids.get(k), Some(v));
        }
        assert_eq!(ids.get(MaterialKey::Named(3)), None);
        assert_eq!(ids.get(MaterialKey::Anonymous(7)), None);
    }
}
