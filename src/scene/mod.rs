//! The pbrt-v4 scene-file front end: text → [`SceneDesc`], a renderer-independent description.
//!
//! ```text
//! tokenizer (file:line:col) → parser (graphics state, includes, objects) → SceneDesc
//!                                      └→ shapes / mesh_io (PLY, OBJ, inline meshes)
//! ```
//! Entry points: [`parse_file`] and [`parse_str`]. After building the renderer's scene from the
//! desc, call [`SceneDesc::report_unused`] to warn about parameters nothing read.
//! The supported subset is listed in docs/scene-format.md. (`desc::CameraDesc` is not re-exported
//! here: the renderer's own `scene::CameraDesc` owns that name.)

pub mod desc;
pub mod error;
pub mod mesh_io;
pub mod names;
pub mod params;
pub mod parser;
pub mod shapes;
mod source;
pub mod tokenizer;

pub use desc::{
    AreaLightDesc, Directive, InstanceDesc, LightDesc, MaterialDesc, MaterialRef, NamedMaterial,
    ObjectDesc, SceneDesc, ShapeDesc, ShapeGeometry, TextureClass, TextureDesc,
};
pub use error::{Location, SceneError, Warning};
pub use params::{FloatOrTexture, ParamSet, ParamValue, SpectrumOrTexture, SpectrumParam};
pub use parser::{look_at, parse_file, parse_str, ParseOptions};
