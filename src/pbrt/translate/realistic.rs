//! pbrt-v4's `Camera "realistic"` → [`RealisticLens`]: the lens file ("lensfile", relative to
//! the scene file), "aperturediameter" [mm] (default 1), "focusdistance" [m] (default 10), the
//! film's "diagonal" [mm] (default 35) and the shutter interval, as pbrt-v4's
//! `RealisticCamera::Create`.

use super::{param_error, Ctx};
use crate::camera::lens::parse_lens_file;
use crate::camera::RealisticLens;
use crate::pbrt::error::{Location, SceneError};
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
        let positive = |params: &crate::pbrt::ParamSet, name: &str, default: f32, loc: &Location| {
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

#[cfg(test)]
mod tests {
    use crate::pbrt::{parse_str, ParseOptions};
    use std::path::PathBuf;

    /// The error text of building a scene whose camera is `camera`, read from `dir`.
    fn build_error(camera: &str, dir: PathBuf) -> String {
        let text = format!("{camera}\nWorldBegin\nShape \"sphere\"\n");
        let opts = ParseOptions { base_dir: Some(dir), ..ParseOptions::default() };
        let (desc, mut w) = parse_str(&text, &opts).unwrap();
        match super::super::build(&desc, &mut w) {
            Ok(_) => String::new(),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn the_lens_file_is_found_beside_the_scene_and_its_errors_name_file_and_line() {
        let data = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/compat"));
        let ok = "Camera \"realistic\" \"string lensfile\" \"cameras-dgauss.50mm.dat\" \"float aperturediameter\" 14";
        assert_eq!(build_error(ok, data.clone()), "", "relative to the scene's directory");
        let opts = ParseOptions { base_dir: Some(data.clone()), ..ParseOptions::default() };
        let (desc, _) = parse_str(&format!("{ok}\nWorldBegin\n"), &opts).unwrap();
        assert!(desc.input_files().contains(&data.join("cameras-dgauss.50mm.dat")), "the lens file is an input");
        let missing = build_error("Camera \"realistic\"", data.clone());
        assert!(missing.contains("needs a \"string lensfile\""), "{missing}");
        let absent = build_error("Camera \"realistic\" \"string lensfile\" \"no-such.dat\"", data.clone());
        assert!(absent.contains("cannot read") && absent.contains("no-such.dat"), "{absent}");
        let near = "Camera \"realistic\" \"string lensfile\" \"cameras-dgauss.50mm.dat\" \"float focusdistance\" 0.1";
        assert!(build_error(near, data).contains("too short"), "a focus inside the lens's reach");

        let dir = std::env::temp_dir().join(format!("prism-lens-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("bad.dat"), "# r t n a\n29.5 3.8 1.67 25\n12 5.7 one 18\n").unwrap();
        let bad = build_error("Camera \"realistic\" \"string lensfile\" \"bad.dat\"", dir.clone());
        std::fs::remove_dir_all(&dir).ok();
        assert!(bad.contains("bad.dat:3:8:") && bad.contains("\"one\" is not a number"), "{bad}");
    }
}
