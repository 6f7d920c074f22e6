//! pbrt-v4's `Camera "realistic"` → [`RealisticLens`]: the lens file ("lensfile", relative to
//! the scene file), "aperturediameter" [mm] (default 1), "focusdistance" [m] (default 10), the
//! film's "diagonal" [mm] (default 35) and the shutter interval, as pbrt-v4's
//! `RealisticCamera::Create`.

use super::{param_error, Ctx};
use crate::camera::lens::parse_lens_file;
use crate::camera::RealisticLens;
use crate::scene::error::{Location, SceneError};
use std::path::Path;
use std::sync::Arc;

impl Ctx<'_> {
    /// The realistic camera's lens, focused, with its exit pupil bounded.
    pub(super) fn realistic_lens(&mut self) -> Result<Arc<RealisticLens>, SceneError> {
        let c = &self.desc.camera.directive;
        let p = &c.params;
        let Some(path) = p.filename("lensfile") else {
            return Err(SceneError::syntax(&c.loc, &c.kind, "a realistic camera needs a \"string lensfile\""));
        };
        let lens_loc = p.get("lensfile").map_or(&c.loc, |v| &v.loc).clone();
        let text = std::fs::read_to_string(&path).map_err(|e| SceneError::Io {
            loc: lens_loc.clone(),
            path: path.clone(),
            reason: e.to_string(),
        })?;
        let elements = parse_lens_file(&text).map_err(|e| {
            let (line, col) = e.position();
            let file: Arc<Path> = path.as_path().into();
            SceneError::syntax(&Location::new(file, line, col), "lensfile", e.to_string())
        })?;
        let positive = |params: &crate::scene::ParamSet, name: &str, default: f32, loc: &Location| {
            let v = params.float_or(name, default);
            if v > 0.0 && v.is_finite() {
                Ok(v)
            } else {
                Err(param_error(params, name, loc, format!("\"{name}\" must be positive, got {v}")))
            }
        };
        let aperture = positive(p, "aperturediameter", 1.0, &c.loc)?;
        let focus = positive(p, "focusdistance", 10.0, &c.loc)?;
        let film = &self.desc.film;
        let diagonal = positive(&film.params, "diagonal", 35.0, &film.loc)?;
        let shutter = p.float_or("shutterclose", 1.0) - p.float_or("shutteropen", 0.0);
        let (lens, clamped) = RealisticLens::new(elements, aperture * 1e-3, focus, diagonal * 1e-3, shutter)
            .map_err(|e| param_error(p, "focusdistance", &c.loc, e.to_string()))?;
        if let Some(s) = clamped {
            let message = format!(
                "\"aperturediameter\" {} mm is larger than the lens's stop ({} mm); the stop's is used",
                s.asked * 1e3,
                s.max * 1e3
            );
            self.warn(&c.loc, message);
        }
        Ok(Arc::new(lens))
    }
}
