//! Transform directives: the current transformation matrices (CTMs), named coordinate systems,
//! ActiveTransform, TransformTimes and ReverseOrientation. As in pbrt-v4, transforms
//! post-multiply the CTM, and there are two of them, at the start and at the end time of
//! `TransformTimes`: `ActiveTransform StartTime|EndTime|All` picks which ones the directives
//! change, and a shape or instance placed while the two differ moves between them.

use glam::{Mat4, Vec3, Vec4};

use super::{Active, Parser};
use crate::geometry::AnimatedTransform;
use crate::pbrt::error::SceneError;
use crate::pbrt::source::Source;
use crate::pbrt::tokenizer::Token;

impl Parser<'_> {
    /// Replaces each CTM the active transform selects by `f` of it.
    fn update_ctm(&mut self, f: impl Fn(Mat4) -> Mat4) {
        if self.gs.active != Active::End {
            self.gs.ctm = f(self.gs.ctm);
        }
        if self.gs.active != Active::Start {
            self.gs.ctm_end = f(self.gs.ctm_end);
        }
    }

    /// Applies `m` to the active CTMs (post-multiplied, as pbrt-v4 does).
    pub(super) fn concat(&mut self, m: Mat4) {
        self.update_ctm(|c| c * m);
    }

    /// Sets the active CTMs to `m`.
    pub(super) fn set_ctm(&mut self, m: Mat4) {
        self.update_ctm(|_| m);
    }

    /// The motion between the two CTMs over `TransformTimes`, when they differ.
    pub(super) fn motion(&self) -> Option<AnimatedTransform> {
        let (t0, t1) = self.transform_times;
        (self.gs.ctm != self.gs.ctm_end).then(|| AnimatedTransform::new(self.gs.ctm, t0, self.gs.ctm_end, t1))
    }

    /// The start CTM for something that cannot move (`what`: "camera", "light", ...); a
    /// differing end CTM is reported once and ignored, as pbrt-v4 does for lights and media.
    pub(super) fn start_ctm(&mut self, tok: &Token, what: &str) -> Mat4 {
        if self.gs.ctm != self.gs.ctm_end && !self.warned_motion {
            self.warned_motion = true;
            self.unsupported(
                &tok.loc(),
                &format!("a moving {what} (ActiveTransform EndTime)"),
                "uses the start transform",
            );
        }
        self.gs.ctm
    }

    /// Identity, Translate, Scale, Rotate, LookAt, Transform, ConcatTransform, CoordinateSystem,
    /// CoordSysTransform, ActiveTransform, TransformTimes, ReverseOrientation. `Ok(false)` if
    /// `tok` is not one of them.
    pub(super) fn transform_directive(&mut self, tok: &Token, src: &mut Source) -> Result<bool, SceneError> {
        match &*tok.text {
            "Identity" => self.set_ctm(Mat4::IDENTITY),
            "Translate" => {
                let v = src.numbers::<3>(tok)?;
                self.concat(Mat4::from_translation(Vec3::new(v[0], v[1], v[2])));
            }
            "Scale" => {
                let v = src.numbers::<3>(tok)?;
                self.concat(Mat4::from_scale(Vec3::new(v[0], v[1], v[2])));
            }
            "Rotate" => {
                let v = src.numbers::<4>(tok)?;
                let axis = Vec3::new(v[1], v[2], v[3]);
                if axis.length_squared() == 0.0 || !axis.length_squared().is_finite() {
                    return Err(SceneError::syntax(&tok.loc(), &tok.text, "rotation axis has zero length"));
                }
                self.concat(Mat4::from_axis_angle(axis.normalize(), v[0].to_radians()));
            }
            "LookAt" => {
                let v = src.numbers::<9>(tok)?;
                let m = look_at(Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), Vec3::new(v[6], v[7], v[8]))
                    .ok_or_else(|| {
                        SceneError::syntax(
                            &tok.loc(),
                            &tok.text,
                            "LookAt is degenerate: eye equals look, or up is parallel to the view direction",
                        )
                    })?;
                self.concat(m);
            }
            "Transform" | "ConcatTransform" => {
                let a = src.numbers::<16>(tok)?;
                // pbrt lists the matrix column by column (translation in elements 12–14),
                // which is glam's column-major order.
                let m = Mat4::from_cols_array(&a);
                if tok.text == "Transform" {
                    self.set_ctm(m);
                } else {
                    self.concat(m);
                }
            }
            "CoordinateSystem" => {
                let name = src.string(tok, "a coordinate system name")?;
                self.named_cs.insert(name.text.into_owned(), [self.gs.ctm, self.gs.ctm_end]);
            }
            "CoordSysTransform" => {
                let name = src.string(tok, "a coordinate system name")?;
                match self.named_cs.get(&*name.text) {
                    Some(&[start, end]) => (self.gs.ctm, self.gs.ctm_end) = (start, end),
                    None => self.warn(
                        &name.loc(),
                        format!("unknown coordinate system \"{}\"; CoordSysTransform ignored", name.text),
                    ),
                }
            }
            "ActiveTransform" => {
                let t = src.expect(tok, "StartTime, EndTime or All")?;
                self.gs.active = match &*t.text {
                    "StartTime" => Active::Start,
                    "EndTime" => Active::End,
                    "All" => Active::All,
                    _ => {
                        return Err(SceneError::syntax(
                            &t.loc(),
                            &t.display(),
                            "ActiveTransform expects StartTime, EndTime or All",
                        ))
                    }
                };
            }
            "TransformTimes" => {
                let v = src.numbers::<2>(tok)?;
                if v[1] < v[0] {
                    return Err(SceneError::syntax(&tok.loc(), &tok.text, "TransformTimes end is before start"));
                }
                self.transform_times = (v[0], v[1]);
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
