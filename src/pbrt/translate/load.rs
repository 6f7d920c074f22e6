//! A pbrt-v4 scene file from disk to a [`SceneBuilder`]: parse, build, report what was not
//! used, and in strict mode refuse every feature prism does not render.

use super::{build_moving_meshes, FileSettings};
use crate::pbrt::error::{check_strict, SceneError, Warning};
use crate::pbrt::{parse_file, ParseOptions};
use crate::scene::SceneBuilder;
use std::path::{Path, PathBuf};

/// A scene file read and mapped onto a builder.
pub struct LoadedScene {
    /// The scene, ready to build.
    pub builder: SceneBuilder,
    /// What the file asks of the render.
    pub settings: FileSettings,
    /// Every warning, in order: the parser's, the builder's, then parameters nothing read.
    pub warnings: Vec<Warning>,
    /// Every file the scene reads: the scene files, then meshes, images and spectra
    /// ([`crate::pbrt::SceneDesc::input_files`]).
    pub inputs: Vec<PathBuf>,
}

/// Loads the scene file at `path`. With `opts.strict` the first warning about an unsupported
/// feature, wherever it arose (parser, shapes, materials, lights, film), is the error.
pub fn load_file(path: &Path, opts: &ParseOptions) -> Result<LoadedScene, SceneError> {
    let (mut desc, mut warnings) = parse_file(path, opts)?;
    let (builder, settings) = build_moving_meshes(&mut desc, &mut warnings, opts.quadrics)?;
    warnings.extend(desc.report_unused());
    if opts.strict {
        check_strict(&warnings)?;
    }
    Ok(LoadedScene { builder, settings, warnings, inputs: desc.input_files() })
}
