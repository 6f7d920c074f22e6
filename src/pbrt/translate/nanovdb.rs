//! pbrt-v4's "nanovdb" medium (`NanoVDBMedium::Create`): `filename` (required), the file's
//! "density" grid and optional "temperature" grid, `sigma_a`/`sigma_s` (1), `scale` (1), `g`
//! (0), `Lescale` (1), `temperatureoffset` (or `temperaturecutoff`, 0) and `temperaturescale`
//! (1). Grids must be fog volumes or of unknown class, as pbrt-v4 requires.

use super::media::{check_densities, temperature_offset};
use super::{param_error, Ctx};
use crate::media::nanovdb::grid::Node;
use crate::media::nanovdb::{read_float_grids, FloatGrid};
use crate::media::{Homogeneous, Medium, NanoVdbMedium, TemperatureEmission};
use crate::pbrt::desc::MediumDesc;
use crate::pbrt::error::SceneError;
use crate::spectrum::Spectrum;

impl Ctx<'_> {
    /// The NanoVDB medium `m` with the coefficients already read from it.
    pub(super) fn nanovdb_medium(
        &mut self,
        m: &MediumDesc,
        (sigma_a, sigma_s): (Spectrum, Spectrum),
        scale: f32,
        g: f32,
    ) -> Result<Medium, SceneError> {
        let p = &m.params;
        let Some(path) = p.filename("filename") else {
            return Err(param_error(p, "filename", &m.loc, "a \"nanovdb\" medium needs a \"string filename\"".into()));
        };
        let file_error = |message: String| param_error(p, "filename", &m.loc, format!("{}: {message}", path.display()));
        let mut grids = read_float_grids(&path, &["density", "temperature"]).map_err(|e| file_error(e.to_string()))?;
        let temperature = grids.pop().flatten();
        let density = grids.pop().flatten().ok_or_else(|| file_error("no \"density\" grid".into()))?;
        for grid in std::iter::once(&density).chain(&temperature) {
            check_class(grid).map_err(|e| file_error(e.to_string()))?;
        }
        let sigma_t = (sigma_a.max_value() + sigma_s.max_value()) * f64::from(scale);
        let mut checked = check_densities([density.background], sigma_t);
        density.visit(|_, _, node| {
            if checked.is_ok() {
                checked = match node {
                    Node::Tile(v) => check_densities([v], sigma_t),
                    Node::Leaf(leaf) => check_densities(leaf.iter().copied(), sigma_t),
                };
            }
        });
        checked.map_err(|e| file_error(format!("grid \"density\": {e}")))?;
        // pbrt-v4 read this medium's scale as "LeScale" before it named it "Lescale" as the
        // other media do; scenes of both ages exist (its own explosion scene says "LeScale").
        let le_scale = p.float("Lescale").or_else(|| p.float("LeScale")).unwrap_or(1.0);
        let offset = temperature_offset(p);
        let temperature_scale = p.float_or("temperaturescale", 1.0);
        // pbrt-v4 emits only with a temperature grid and a positive Lescale.
        let emission = temperature.filter(|_| le_scale > 0.0).map(|grid| TemperatureEmission {
            grid,
            le_scale,
            offset,
            scale: temperature_scale,
        });
        let coefficients = Homogeneous { sigma_a, sigma_s, scale, le: Spectrum::constant(0.0), g };
        let medium = NanoVdbMedium::new(m.world_from_medium, density, coefficients, emission)
            .ok_or_else(|| file_error("the grids' bounds are empty or the medium's transform singular".into()))?;
        Ok(Medium::NanoVdb(Box::new(medium)))
    }
}

/// A grid of a class pbrt-v4 does not read as a medium.
#[derive(Debug, thiserror::Error)]
#[error("grid \"{name}\" is a {class} grid, not a fog volume")]
struct GridClassError {
    name: String,
    class: &'static str,
}

/// pbrt-v4 reads fog volumes (class 2) and grids of unknown class (0) only.
fn check_class(grid: &FloatGrid) -> Result<(), GridClassError> {
    const CLASSES: [&str; 9] = [
        "unknown",
        "level set",
        "fog volume",
        "staggered",
        "point index",
        "point data",
        "topology",
        "voxel volume",
        "index",
    ];
    match grid.class {
        0 | 2 => Ok(()),
        c => Err(GridClassError {
            name: grid.name.clone(),
            class: CLASSES.get(c as usize).copied().unwrap_or("unknown-class"),
        }),
    }
}

#[cfg(test)]
mod tests {
    use crate::media::Medium;
    use crate::pbrt::{parse_str, ParseOptions};

    fn build(medium: &str) -> Result<crate::scene::Scene, String> {
        let text = format!("{medium}\nCamera \"perspective\"\nWorldBegin\n");
        let (desc, mut w) = parse_str(&text, &ParseOptions::default()).map_err(|e| e.to_string())?;
        let (b, _) = super::super::build(&desc, &mut w).map_err(|e| e.to_string())?;
        Ok(b.build(crate::accel::AccelKind::Obvhs).unwrap())
    }

    /// The error of a scene that must not build.
    fn error(medium: &str) -> String {
        build(medium).err().expect("the scene must not build")
    }

    fn fixture(name: &str) -> String {
        format!("{}/tests/data/nanovdb/{name}", env!("CARGO_MANIFEST_DIR"))
    }

    #[test]
    fn a_nanovdb_medium_is_placed_by_its_transform_and_file_errors_name_the_file() {
        let m = format!(
            "Translate 1 2 3\nMakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"{}\"",
            fixture("plain.nvdb")
        );
        let scene = build(&m).unwrap();
        let Medium::NanoVdb(v) = &scene.media()[0] else { panic!("{:?}", scene.media()[0]) };
        // plain.nvdb: g = (i + 8j + 64k)/512 at world (1, 2, 3) + 0.5 (i, j, k), moved by (1, 2, 3).
        let at = |i: f32, j: f32, k: f32| v.density_at(glam::Vec3::new(2.0, 4.0, 6.0) + 0.5 * glam::Vec3::new(i, j, k));
        assert!((at(3.0, 2.0, 1.0) - (3.0 + 16.0 + 64.0) / 512.0).abs() < 1e-6);
        assert_eq!(v.bounds, (glam::Vec3::new(1.0, 2.0, 3.0), glam::Vec3::new(5.0, 6.0, 7.0)));

        let none = error("MakeNamedMedium \"m\" \"string type\" \"nanovdb\"");
        assert!(none.starts_with("<string>:1:1:") && none.contains("\"string filename\""), "{none}");
        let missing = error("MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"no.nvdb\"");
        assert!(missing.starts_with("<string>:1:") && missing.contains("no.nvdb"), "{missing}");
        let not_vdb = format!("MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"{}\"", file!());
        let not_vdb = error(&not_vdb);
        assert!(not_vdb.contains("not a NanoVDB file"), "{not_vdb}");
    }

    #[test]
    fn the_older_names_lescale_and_temperaturecutoff_are_read_not_refused() {
        // pbrt-v4's explosion scene names the scale "LeScale" and gives "temperaturecutoff".
        let m = format!(
            "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"{}\" \
             \"float LeScale\" 5 \"float temperaturecutoff\" 1 \"float temperatureoffset\" 2",
            fixture("plain.nvdb")
        );
        let text = format!("{m}\nCamera \"perspective\"\nWorldBegin\n");
        let (desc, mut w) = parse_str(&text, &ParseOptions::default()).unwrap();
        super::super::build(&desc, &mut w).unwrap();
        w.extend(desc.report_unused());
        assert!(w.iter().all(|w| !w.to_string().contains("not used")), "{w:?}");
    }

    #[test]
    fn densities_no_majorant_can_bound_are_located_errors() {
        // plain.nvdb holds voxel (3, 2, 1) = 83/512 once; replaced by each bad value in turn.
        let bytes = std::fs::read(fixture("plain.nvdb")).unwrap();
        let good = (83.0f32 / 512.0).to_le_bytes();
        let at = bytes.windows(4).position(|w| w == good).unwrap();
        let dir = std::env::temp_dir().join(format!("prism-nanovdb-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for bad in [f32::INFINITY, 1e30, 3.4e38, f32::NAN] {
            let mut b = bytes.clone();
            b[at..at + 4].copy_from_slice(&bad.to_le_bytes());
            let path = dir.join("bad.nvdb");
            std::fs::write(&path, b).unwrap();
            let m =
                format!("MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"{}\"", path.display());
            let e = error(&m);
            assert!(e.starts_with("<string>:1:") && e.contains("bad.nvdb") && e.contains("density"), "{bad}: {e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
        // Coefficients and scales no majorant can bound, in every medium.
        for bad in [
            "\"homogeneous\" \"rgb sigma_a\" [1e30 1 1]",
            "\"homogeneous\" \"float scale\" 3.4e38",
            "\"uniformgrid\" \"float density\" [1 1e30]  \"integer nx\" 2",
            "\"uniformgrid\" \"float density\" [1 1e10] \"integer nx\" 2 \"float scale\" 1e10",
        ] {
            let e = error(&format!("MakeNamedMedium \"m\" \"string type\" {bad}"));
            assert!(e.starts_with("<string>:1:") && e.contains("1e15"), "{bad}: {e}");
        }
    }
}
