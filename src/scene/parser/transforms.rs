//! Transform directives: the current transformation matrix (CTM), named coordinate systems,
//! ActiveTransform and ReverseOrientation (pbrt-v4: transforms post-multiply the CTM).

use glam::{Mat4, Vec3, Vec4};

use super::{Active, Parser};
use crate::scene::error::SceneError;
use crate::scene::source::Source;
use crate::scene::tokenizer::Token;

impl Parser<'_> {
    /// Applies `m` to the CTM (post-multiplied, as pbrt-v4 does) if the active transform allows.
    pub(super) fn concat(&mut self, tok: &Token, m: Mat4) {
        self.set_ctm(tok, self.gs.ctm * m);
    }

    pub(super) fn set_ctm(&mut self, tok: &Token, m: Mat4) {
        if self.gs.active == Active::End {
            if !self.warned_motion {
                self.warned_motion = true;
                self.unsupported(&tok.loc, "motion blur (ActiveTransform EndTime)", "uses the start transform");
            }
            return;
        }
        self.gs.ctm = m;
    }

    /// Identity, Translate, Scale, Rotate, LookAt, Transform, ConcatTransform, CoordinateSystem,
    /// CoordSysTransform, ActiveTransform, TransformTimes, ReverseOrientation. `Ok(false)` if
    /// `tok` is not one of them.
    pub(super) fn transform_directive(&mut self, tok: &Token, src: &mut Source) -> Result<bool, SceneError> {
        match tok.text.as_str() {
            "Identity" => self.set_ctm(tok, Mat4::IDENTITY),
            "Translate" => {
                let v = src.numbers(tok, 3)?;
                self.concat(tok, Mat4::from_translation(Vec3::new(v[0], v[1], v[2])));
            }
            "Scale" => {
                let v = src.numbers(tok, 3)?;
                self.concat(tok, Mat4::from_scale(Vec3::new(v[0], v[1], v[2])));
            }
            "Rotate" => {
                let v = src.numbers(tok, 4)?;
                let axis = Vec3::new(v[1], v[2], v[3]);
                if axis.length_squared() == 0.0 || !axis.length_squared().is_finite() {
                    return Err(SceneError::syntax(&tok.loc, &tok.text, "rotation axis has zero length"));
                }
                self.concat(tok, Mat4::from_axis_angle(axis.normalize(), v[0].to_radians()));
            }
            "LookAt" => {
                let v = src.numbers(tok, 9)?;
                let m = look_at(Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), Vec3::new(v[6], v[7], v[8]))
                    .ok_or_else(|| {
                        SceneError::syntax(
                            &tok.loc,
                            &tok.text,
                            "LookAt is degenerate: eye equals look, or up is parallel to the view direction",
                        )
                    })?;
                self.concat(tok, m);
            }
            "Transform" | "ConcatTransform" => {
                let v = src.numbers(tok, 16)?;
                let mut a = [0.0f32; 16];
                a.copy_from_slice(&v);
                // pbrt lists the matrix column by column (translation in elements 12–14),
                // which is glam's column-major order.
                let m = Mat4::from_cols_array(&a);
                if tok.text == "Transform" {
                    self.set_ctm(tok, m);
                } else {
                    self.concat(tok, m);
                }
            }
            "CoordinateSystem" => {
                let name = src.string(tok, "a coordinate system name")?;
                self.named_cs.insert(name.text, self.gs.ctm);
            }
            "CoordSysTransform" => {
                let name = src.string(tok, "a coordinate system name")?;
                match self.named_cs.get(&name.text) {
                    Some(&m) => self.set_ctm(tok, m),
                    None => self.warn(
                        &name.loc,
                        format!("unknown coordinate system \"{}\"; CoordSysTransform ignored", name.text),
                    ),
                }
            }
            "ActiveTransform" => {
                let t = src.expect(tok, "StartTime, EndTime or All")?;
                self.gs.active = match t.text.as_str() {
                    "StartTime" => Active::Start,
                    "EndTime" => Active::End,
                    "All" => Active::All,
                    _ => {
                        return Err(SceneError::syntax(
                            &t.loc,
                            &t.display(),
                            "ActiveTransform expects StartTime, EndTime or All",
                        ))
                    }
                };
            }
            "TransformTimes" => {
                let v = src.numbers(tok, 2)?;
                if v[1] < v[0] {
                    return Err(SceneError::syntax(&tok.loc, &tok.text, "TransformTimes end is before start"));
                }
            }
            "ReverseOrientation" => self.gs.reverse_orientation = !self.gs.reverse_orientation,
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// pbrt's LookAt: camera space from world space for a camera at `eye` looking at `look`, with
/// camera +x = up × dir, +y = the projected up vector, +z = the viewing direction (left-handed,
/// as in pbrt-v4 `LookAt`, src/pbrt/util/transform.cpp). `None` when degenerate.
pub fn look_at(eye: Vec3, look: Vec3, up: Vec3) -> Option<Mat4> {
    let dir = (look - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera =
        Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), Vec4::from((eye, 1.0)));
    Some(world_from_camera.inverse())
}
