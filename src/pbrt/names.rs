//! The type names prism renders, and pbrt-v4's other names with what prism substitutes.
//!
//! One place to extend as shapes, cameras and the rest land: move a name from a `PBRT_ONLY_*`
//! table into the matching `PRISM_*` list. Material, light and medium names live beside their
//! enums (`material::PBRT_NAMES`, `light::PBRT_NAMES`, `media::PBRT_NAMES`), so a new one is
//! added where it is implemented.

/// Shapes prism renders. "objmesh" is prism's extension (docs/scene-format.md).
pub const PRISM_SHAPES: &[&str] =
    &["trianglemesh", "plymesh", "objmesh", "sphere", "disk", "cylinder", "bilinearmesh", "loopsubdiv", "curve"];
/// pbrt-v4 shapes prism skips (with a warning), and what the warning says prism does.
pub const PBRT_ONLY_SHAPES: &[(&str, &str)] = &[];

/// Materials prism renders (listed beside the `Material` enum they become).
pub const PRISM_MATERIALS: &[&str] = crate::material::PBRT_NAMES;
/// pbrt-v4 materials prism replaces, with the replacement type (used with default parameters).
pub const PBRT_ONLY_MATERIALS: &[(&str, &str)] = &[];

/// Non-area lights prism renders (listed beside the `Light` enum they become).
pub const PRISM_LIGHTS: &[&str] = crate::light::PBRT_NAMES;
/// pbrt-v4 lights prism skips.
pub const PBRT_ONLY_LIGHTS: &[(&str, &str)] = &[];
/// Area lights prism renders.
pub const PRISM_AREA_LIGHTS: &[&str] = &["diffuse"];

/// Cameras prism renders.
pub const PRISM_CAMERAS: &[&str] = &["perspective", "orthographic", "spherical", "realistic"];
/// pbrt-v4 cameras prism replaces.
pub const PBRT_ONLY_CAMERAS: &[(&str, &str)] = &[];

/// Films prism writes.
pub const PRISM_FILMS: &[&str] = &["rgb", "gbuffer", "spectral"];
/// pbrt-v4 films prism replaces.
pub const PBRT_ONLY_FILMS: &[(&str, &str)] = &[];

/// Medium types prism renders (MakeNamedMedium "string type").
pub const MEDIA: &[&str] = crate::media::PBRT_NAMES;

/// Integrators prism runs.
/// "path" renders a scene with media as "volpath"; without media "volpath" is "path".
/// "lightpath", "bdpt" and "mlt" step through media themselves and render scenes whose lights
/// and camera they can trace from and to, and fall back to "path" (or, with media, "volpath")
/// with a warning elsewhere (`Integrator::fallback_reason`); "sppm" likewise where a light
/// cannot emit photons. "function" is pbrt-v4's sampler test, run by `prism render` instead
/// of a render.
pub const PRISM_INTEGRATORS: &[&str] = &[
    "path",
    "volpath",
    "ambientocclusion",
    "randomwalk",
    "simplepath",
    "simplevolpath",
    "lightpath",
    "bdpt",
    "mlt",
    "sppm",
    "function",
];
/// pbrt-v4 integrators prism replaces with its path tracer.
pub const PBRT_ONLY_INTEGRATORS: &[(&str, &str)] = &[];

/// Samplers (all pbrt-v4 names are accepted; the renderer picks its own sequence).
pub const SAMPLERS: &[&str] = &["halton", "independent", "paddedsobol", "pmj02bn", "sobol", "stratified", "zsobol"];
/// Pixel reconstruction filters.
pub const FILTERS: &[&str] = &["box", "gaussian", "mitchell", "sinc", "triangle"];
/// Colour spaces of RGB parameters.
pub const COLOR_SPACES: &[&str] = &["srgb", "aces2065-1", "rec2020", "dci-p3"];
/// Texture types (kept as written; the builder maps them).
pub const TEXTURES: &[&str] = &[
    "bilerp",
    "checkerboard",
    "constant",
    "directionmix",
    "dots",
    "fbm",
    "imagemap",
    "marble",
    "mix",
    "ptex",
    "scale",
    "windy",
    "wrinkled",
];

/// How a type name is classified.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// prism renders it: the name as the list spells it.
    Supported(&'static str),
    /// pbrt-v4 knows it; prism does what the `&str` says instead.
    Substitute(&'static str),
    /// Nobody knows it.
    Unknown,
}

/// Classifies `name` against a supported list and a pbrt-only table.
pub fn lookup(name: &str, supported: &[&'static str], pbrt_only: &[(&'static str, &'static str)]) -> Lookup {
    if let Some(&s) = supported.iter().find(|s| **s == name) {
        Lookup::Supported(s)
    } else if let Some(&(_, s)) = pbrt_only.iter().find(|(n, _)| *n == name) {
        Lookup::Substitute(s)
    } else {
        Lookup::Unknown
    }
}

/// All valid names, sorted, comma-separated, for "unknown type" errors.
pub fn valid_list(supported: &[&str], pbrt_only: &[(&str, &str)]) -> String {
    let mut v: Vec<&str> = supported.iter().copied().chain(pbrt_only.iter().map(|p| p.0)).collect();
    v.sort_unstable();
    v.join(", ")
}
