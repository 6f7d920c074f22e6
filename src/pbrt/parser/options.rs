//! Directives of the options block (camera, film, sampler, integrator, filter, accelerator)
//! and those allowed anywhere (Option, ColorSpace, media), WorldBegin/WorldEnd.

use glam::Mat4;

use super::Parser;
use crate::geometry::AnimatedTransform;
use crate::pbrt::desc::*;
use crate::pbrt::error::SceneError;
use crate::pbrt::names;
use crate::pbrt::source::Source;
use crate::pbrt::tokenizer::{Token, TokenKind};

impl Parser<'_> {
    /// Camera, Film, Integrator, Sampler, PixelFilter, Accelerator, Option, ColorSpace,
    /// MakeNamedMedium, MediumInterface, WorldBegin, WorldEnd. `Ok(false)` if `tok` is not one
    /// of them.
    pub(super) fn options_directive(
        &mut self,
        tok: &Token,
        src: &mut Source,
        cs: &'static str,
    ) -> Result<bool, SceneError> {
        match &*tok.text {
            "Option" => {
                let ps = src.params(cs)?;
                let mut merged = ps;
                merged.merge_defaults(&self.options);
                self.options = merged;
            }
            "ColorSpace" => {
                let name = src.string(tok, "a colour space name")?;
                let Some(&space) = names::COLOR_SPACES.iter().find(|&&c| c == name.text) else {
                    return Err(SceneError::UnknownType {
                        loc: name.loc(),
                        kind: "color space",
                        name: name.text.into_owned(),
                        valid: names::COLOR_SPACES.join(", "),
                    });
                };
                self.gs.color_space = space;
                if self.in_world.is_none() {
                    self.color_space = space;
                }
            }
            "Camera" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "a camera type")?;
                let params = src.params(cs)?;
                let kind = self.resolve_type(
                    &ty.text,
                    || ty.loc(),
                    "camera",
                    names::PRISM_CAMERAS,
                    names::PBRT_ONLY_CAMERAS,
                    false,
                )?;
                // pbrt-v4 animates the camera between the inverses of the two CTMs over the
                // current TransformTimes.
                let (ctm, ctm_end) = (self.gs.ctm, self.gs.ctm_end);
                for m in [ctm, ctm_end] {
                    let det = m.determinant();
                    if det == 0.0 || !det.is_finite() {
                        return Err(SceneError::syntax(
                            &tok.loc(),
                            &tok.text,
                            "the camera transform is not invertible",
                        ));
                    }
                }
                let (world_from_camera, world_from_camera_end) = (ctm.inverse(), ctm_end.inverse());
                let (t0, t1) = self.transform_times;
                let motion =
                    (ctm != ctm_end).then(|| AnimatedTransform::new(world_from_camera, t0, world_from_camera_end, t1));
                self.named_cs.insert("camera".into(), [world_from_camera, world_from_camera_end]);
                self.camera = Some(CameraDesc {
                    directive: Directive { kind: kind.unwrap_or_default().into(), params, loc: tok.loc() },
                    camera_from_world: ctm,
                    motion,
                    medium: self.gs.media.outside.clone(),
                });
            }
            "Film" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "a film type")?;
                let params = src.params(cs)?;
                let kind = self.resolve_type(
                    &ty.text,
                    || ty.loc(),
                    "film",
                    names::PRISM_FILMS,
                    names::PBRT_ONLY_FILMS,
                    false,
                )?;
                self.film = Some(Directive { kind: kind.unwrap_or_default().into(), params, loc: tok.loc() });
            }
            "Integrator" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "an integrator type")?;
                let params = src.params(cs)?;
                let kind = self.resolve_type(
                    &ty.text,
                    || ty.loc(),
                    "integrator",
                    names::PRISM_INTEGRATORS,
                    names::PBRT_ONLY_INTEGRATORS,
                    false,
                )?;
                self.integrator = Some(Directive { kind: kind.unwrap_or_default().into(), params, loc: tok.loc() });
            }
            "Sampler" | "PixelFilter" | "Accelerator" => {
                self.require_options(tok)?;
                let ty = src.string(tok, "a type name")?;
                let params = src.params(cs)?;
                let (kind, valid): (&'static str, &[&str]) = match &*tok.text {
                    "Sampler" => ("sampler", names::SAMPLERS),
                    "PixelFilter" => ("filter", names::FILTERS),
                    _ => ("accelerator", &["bvh", "kdtree"]),
                };
                if !valid.contains(&&*ty.text) {
                    return Err(SceneError::UnknownType {
                        loc: ty.loc(),
                        kind,
                        name: ty.text.into_owned(),
                        valid: valid.join(", "),
                    });
                }
                let d = Directive { kind: ty.text.into_owned(), params, loc: tok.loc() };
                match kind {
                    "sampler" => self.sampler = Some(d),
                    "filter" => self.filter = Some(d),
                    _ => self.accelerator = Some(d),
                }
            }
            "MakeNamedMedium" => {
                let name = src.string(tok, "a medium name")?;
                let params = src.params(cs)?;
                let kind = match params.string("type") {
                    Some(k) => k.to_string(),
                    None => {
                        return Err(SceneError::syntax(
                            &tok.loc(),
                            &name.text,
                            "MakeNamedMedium needs a \"string type\"",
                        ))
                    }
                };
                if !names::MEDIA.contains(&kind.as_str()) {
                    let feature = format!("medium type \"{kind}\" of \"{}\"", name.text);
                    self.unsupported(&tok.loc(), &feature, "renders vacuum in its place");
                }
                self.medium_index.insert(name.text.to_string(), self.media.len());
                let world_from_medium = self.start_ctm(tok, "medium");
                self.media.push(MediumDesc {
                    name: name.text.into_owned(),
                    kind,
                    params,
                    world_from_medium,
                    loc: tok.loc(),
                });
            }
            "MediumInterface" => {
                let inside = src.string(tok, "a medium name")?;
                // The outside name is optional (one name means both sides).
                let outside = match src.peek()? {
                    Some(t) if t.kind == TokenKind::Str && !t.text.contains(' ') => {
                        src.next()?.map(|t| t.text.into_owned())
                    }
                    _ => None,
                };
                let outside = outside.unwrap_or_else(|| inside.text.to_string());
                self.gs.media = MediumNames { inside: inside.text.into_owned(), outside };
            }
            "WorldBegin" => {
                self.require_options(tok)?;
                self.in_world = Some(tok.loc());
                (self.gs.ctm, self.gs.ctm_end) = (Mat4::IDENTITY, Mat4::IDENTITY);
                self.named_cs.insert("world".into(), [Mat4::IDENTITY; 2]);
            }
            "WorldEnd" => {
                self.require_world(tok)?;
                self.warn(&tok.loc(), "WorldEnd is a pbrt-v3 directive; ignored");
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}
