//! The pbrt-v4 scene-file reader: tokens ([`tokenizer`]), parameter lists ([`params`]), the
//! parser into a [`SceneDesc`] ([`parser`]), and the translation of that description into a
//! [`crate::scene::SceneBuilder`] with the render settings the file asks for ([`build`]).

mod curve_params;
pub mod desc;
pub mod error;
pub mod input;
pub mod location;
pub mod mesh_io;
pub mod names;
mod number_list;
pub mod params;
pub mod parser;
mod quadric_mode;
mod quadric_params;
pub mod shapes;
mod source;
pub mod tokenizer;
mod translate;

pub use crate::bsdf::named_spectra::named_spectrum;
pub use desc::{
    AreaLightDesc, Directive, InstanceDesc, LightDesc, MaterialDesc, MaterialRef, MediumDesc, MediumNames,
    NamedMaterial, ObjectDesc, SceneDesc, ShapeDesc, ShapeGeometry, TextureClass, TextureDesc,
};
pub use error::{Location, SceneError, Warning};
pub use params::{FloatOrTexture, ParamSet, ParamType, ParamValue, SpectrumOrTexture, SpectrumParam};
pub use parser::{look_at, parse_file, parse_str, ParseOptions};
pub use quadric_mode::QuadricMode;
pub use translate::{
    build, build_moving_meshes, build_with, input_stamps, load_file, FileSettings, InputStamp, LoadedScene,
    PBRT_DEFAULT_MAX_DEPTH,
};
